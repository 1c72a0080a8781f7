"""The model that owns its body: :meth:`Model.evaluate` and :meth:`Model.solar` give, bit for
bit, what the kernels give when handed the lightings explicitly (rigid and articulated bodies,
nearest and interpolated cells, the joint grid, exact mode, no shading, a facet-less body);
test particles with a seed; a database lookup; settings changes that keep the shading."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
import trimesh

from adbsat_ros import panels_from_trimesh
from adbsat_ros.geometry import frames
from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.model import build_model
from adbsat_ros.physics.setup import BodySpec, Setup, ShadingPolicy, SolverSpec
from adbsat_ros.physics.solar import solar_coefficients
from adbsat_ros.physics.tpmc.method import TestParticleMethod
from adbsat_ros.shading.cache import ShadingCache
from adbsat_ros.shading.shader import make_shader

FLOW = FreeStream(7600.0, 900.0, mean_mass_amu=17.0)
ANGLES_DEG = ((0.0, 0.0), (12.0, -7.0), (33.0, 61.0), (-75.0, 150.0), (12.0, -7.0))


def directions():
    """Flow directions, not unit length (as the node gives the gas motion), one repeated."""
    return [2.5 * frames.flow_direction(math.radians(a), math.radians(b)) for a, b in ANGLES_DEG]


def same(result, reference) -> None:
    """The totals and per-panel values equal bit for bit."""
    for name in ("Cf_G", "Cm_G", "Cf_w", "Cm_B", "cos_delta", "cp", "ctau", "lit_fraction"):
        assert np.array_equal(getattr(result, name), getattr(reference, name)), name
    assert result.area_projected == reference.area_projected


def same_articulated(result, reference) -> None:
    same(result.total, reference.total)
    for name in ("effort_coefficients", "link_force", "link_moment", "joint_positions"):
        assert np.array_equal(getattr(result, name), getattr(reference, name)), name


def rigid_twin(model, **options) -> ShadingCache:
    """A cache of its own, of the shader the kernel would make, for the explicit lightings."""
    policy = model.setup.shading
    shader = make_shader(model.mesh, mode=policy.mode, samples=policy.samples)
    return ShadingCache(shader, policy.cache_resolution_deg, **options)


@pytest.fixture(scope="module")
def concave():
    """A box shading a plate: shadows move between the cells."""
    box = trimesh.creation.box(extents=(0.5, 0.5, 0.5))
    plate = trimesh.creation.box(extents=(0.05, 1.6, 1.2))
    plate.apply_translation((0.6, 0.0, 0.0))
    return panels_from_trimesh(trimesh.util.concatenate([box, plate]))


@pytest.mark.parametrize("interpolation", [False, True])
def test_rigid_evaluate_equals_the_panel_method_with_the_cache_lightings(interpolation):
    setup = Setup(shading=ShadingPolicy(cache_resolution_deg=4.0, interpolation=interpolation))
    model = build_model(setup)
    assert model.backend == "panel" and model.method.facets is not None
    twin = rigid_twin(model, interpolate=interpolation)
    for u in directions():
        result = model.evaluate(FLOW, u)
        reference = model.method.coefficients(FLOW, flow_direction=u, lighting=twin.lighting(u))
        same(result, reference)
    for a, b in ANGLES_DEG:  # angles: the wind axes of the angles given
        aoa, aos = math.radians(a), math.radians(b)
        result = model.evaluate(FLOW, angles=(aoa, aos))
        lighting = twin.lighting(frames.flow_direction(aoa, aos))
        same(result, model.method.coefficients(FLOW, aoa, aos, lighting=lighting))
        assert (result.aoa, result.aos) == (aoa, aos)


def test_rigid_evaluate_with_surface_changes_equals_the_method_with_that_surface():
    model = build_model(Setup(model="maxwell", shading=ShadingPolicy(cache_resolution_deg=4.0)))
    twin = rigid_twin(model, interpolate=True)
    surface = model.method.surface_with(alpha=0.62, alpha_n=0.62)
    for u in directions():
        result = model.evaluate(FLOW, u, changes={"alpha": 0.62, "alpha_n": 0.62})
        reference = model.method.coefficients(
            FLOW, flow_direction=u, lighting=twin.lighting(u), surface=surface
        )
        same(result, reference)
    unchanged = model.evaluate(FLOW, directions()[2])
    assert not np.array_equal(unchanged.Cf_G, result.Cf_G)


def test_exact_mode_equals_the_shader_at_the_direction_itself(concave):
    setup = Setup(shading=ShadingPolicy(exact_offline=1))
    model = build_model(setup, concave)
    shader = make_shader(concave, mode="raycast")
    for u in directions():
        lighting = shader.lighting(u)
        same(
            model.evaluate(FLOW, u),
            model.method.coefficients(FLOW, flow_direction=u, lighting=lighting),
        )
    # a convex body shades nothing: no cache, the all-lit sums
    convex = build_model(setup, panels_from_trimesh(trimesh.creation.box(extents=(1, 2, 3))))
    assert convex.cache is None
    u = directions()[3]
    same(
        convex.evaluate(FLOW, u), convex.method.coefficients(FLOW, flow_direction=u, lighting=None)
    )


def test_no_shading_and_a_facet_less_body():
    model = build_model(Setup(shading=ShadingPolicy(mode="none")))
    assert model.cache is None
    for u in directions():
        same(
            model.evaluate(FLOW, u),
            model.method.coefficients(FLOW, flow_direction=u, lighting=None),
        )
    sphere = panels_from_trimesh(trimesh.creation.icosphere(subdivisions=2, radius=0.5))
    model = build_model(Setup(shading=ShadingPolicy(mode="projection", interpolation=True)), sphere)
    assert model.method.facets is None
    twin = rigid_twin(model, interpolate=True)
    for u in directions():
        reference = model.method.coefficients(FLOW, flow_direction=u, lighting=twin.lighting(u))
        same(model.evaluate(FLOW, u), reference)


# ---------------------------------------------------------------------------------- articulated
def joint_states(body):
    """Joint positions off the grid: two in one grid cell, one coming back."""
    states = []
    for scale in (0.13, 0.1301, -0.37, 0.13):
        states.append(
            {
                name: scale * min(joint.upper, 1.0) * (1.0 - 0.15 * k)
                for k, (name, joint) in enumerate(body.joints.items())
            }
        )
    return states


def posed_twin(model, **options) -> ShadingCache:
    """A cache of its own whose shaders are made from the posed mesh, for explicit lightings."""
    policy = model.setup.shading

    def posed_shader(positions):
        panels = model.body.mesh(positions)
        return make_shader(panels, mode=policy.mode, samples=policy.samples, topology_store=None)

    return ShadingCache(body=model.body, posed_shader=posed_shader, **options)


@pytest.mark.parametrize("joint_interpolation", [False, True])
def test_articulated_grid_equals_the_articulated_method_with_the_cache_lightings(
    joint_interpolation,
):
    policy = ShadingPolicy(
        cache_resolution_deg=3.0,
        interpolation=joint_interpolation,
        joint_resolution_deg=2.0,
        joint_interpolation=joint_interpolation,
    )
    model = build_model(Setup(body=BodySpec("example-finned"), shading=policy))
    assert model.backend == "articulated" and model.method.facets is not None
    twin = posed_twin(
        model,
        resolution_deg=3.0,
        interpolate=joint_interpolation,
        angle_step=math.radians(2.0),
        length_step=policy.joint_resolution_m,
        joint_interpolate=joint_interpolation,
        max_configurations=8,
    )
    method = model.method
    for positions in joint_states(model.body):
        joints = model.prepare_joints(positions)
        configuration = method.configuration(positions)
        for u in directions():
            lighting = twin.lighting(u, twin.vertices(configuration.positions))
            reference = method.coefficients(
                FLOW, configuration, flow_direction=u, lighting=lighting
            )
            same_articulated(model.evaluate(FLOW, u, joints), reference)
        # the positions themselves, prepared on the way
        same_articulated(model.evaluate(FLOW, u, positions), reference)


def test_articulated_exact_mode_equals_the_posed_shader(tmp_path):
    policy = ShadingPolicy(joint_exact=True)
    model = build_model(Setup(body=BodySpec("example-finned"), shading=policy))
    method = model.method
    for positions in joint_states(model.body):
        joints = model.prepare_joints(positions)
        shader = make_shader(model.body.mesh(positions), mode="raycast", topology_store=None)
        configuration = method.configuration(positions)
        for u in directions()[1:3]:
            lighting = shader.lighting(u)
            reference = method.coefficients(
                FLOW, configuration, flow_direction=u, lighting=lighting
            )
            same_articulated(model.evaluate(FLOW, u, joints), reference)
    # no shading: the all-lit rows posed
    plain = build_model(Setup(body=BodySpec("example-finned"), shading=ShadingPolicy("none")))
    u = directions()[2]
    for positions in joint_states(plain.body):
        reference = plain.method.coefficients(FLOW, positions, flow_direction=u, lighting=None)
        same_articulated(plain.evaluate(FLOW, u, positions), reference)


SPHERE_ARM_URDF = """<robot name="arm">
  <link name="base"><visual><geometry><box size="0.4 0.4 0.4"/></geometry></visual></link>
  <link name="ball"><visual><origin xyz="0.5 0 0"/>
    <geometry><sphere radius="0.1"/></geometry></visual></link>
  <joint name="swing" type="revolute"><parent link="base"/><child link="ball"/>
    <origin xyz="0.2 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
</robot>"""


def test_an_articulated_body_with_a_facet_less_link():
    """A sphere's panels face their own ways: the links are evaluated one by one, with the
    lighting split by link, as the kernel does with the same lighting."""
    body = ArticulatedBody.from_urdf(SPHERE_ARM_URDF)
    policy = ShadingPolicy(cache_resolution_deg=3.0, joint_resolution_deg=2.0)
    model = build_model(Setup(body=BodySpec("arm.urdf"), shading=policy), body)
    assert model.method.facets is None
    twin = posed_twin(
        model, resolution_deg=3.0, interpolate=True, angle_step=math.radians(2.0), length_step=1e-3
    )
    for positions in ({"swing": 0.7}, {"swing": -1.234}):
        configuration = model.method.configuration(positions)
        for u in directions()[:3]:
            lighting = twin.lighting(u, twin.vertices(configuration.positions))
            reference = model.method.coefficients(
                FLOW, configuration, flow_direction=u, lighting=lighting
            )
            same_articulated(model.evaluate(FLOW, u, positions), reference)


def test_articulated_surface_changes_and_refusals():
    model = build_model(Setup(body=BodySpec("example-finned"), shading=ShadingPolicy("none")))
    positions = joint_states(model.body)[0]
    u = directions()[1]
    surface = model.method.surface_with(alpha=0.4, alpha_n=0.4)
    reference = model.method.coefficients(
        FLOW, positions, flow_direction=u, lighting=None, surface=surface
    )
    result = model.evaluate(FLOW, u, positions, changes={"alpha": 0.4, "alpha_n": 0.4})
    same_articulated(result, reference)
    name, joint = next(iter(model.body.joints.items()))
    with pytest.raises(ValueError, match=name):
        model.prepare_joints({name: joint.upper + 1.0})
    with pytest.raises(ValueError, match="rigid bodies only"):
        model.solar(np.array([0.0, 0.0, 1.0]))


# ---------------------------------------------------------------------------------- other backends
def test_test_particles_with_a_seed_equal_the_solver_with_that_seed():
    box = panels_from_trimesh(trimesh.creation.box(extents=(1.0, 0.6, 0.4)))
    setup = Setup(model="maxwell", solver=SolverSpec("tpmc", particles=2000, seed=7))
    model = build_model(setup, box)
    assert model.backend == "tpmc"
    solver = TestParticleMethod(box, "maxwell", model.materials, reference=model.method.reference)
    aoa, aos = math.radians(20.0), math.radians(-10.0)
    for seed, expected_seed in ((None, 7), (3, 3)):
        result = model.evaluate(FLOW, angles=(aoa, aos), seed=seed)
        reference = solver.coefficients(FLOW, aoa, aos, particles=2000, seed=expected_seed)
        for name in ("Cf_G", "Cm_G", "Cf_G_error", "Cm_G_error", "Cf_w"):
            assert np.array_equal(getattr(result, name), getattr(reference, name)), name
    other = model.evaluate(FLOW, angles=(aoa, aos), seed=4)
    assert not np.array_equal(other.Cf_G, result.Cf_G)
    # both solvers: the panel method by default, test particles when asked
    both = build_model(replace(setup, solver=SolverSpec("both", particles=2000, seed=7)), box)
    u = frames.flow_direction(aoa, aos)
    lighting = rigid_twin(both, interpolate=True).lighting(u)
    same(
        both.evaluate(FLOW, u), both.method.coefficients(FLOW, flow_direction=u, lighting=lighting)
    )
    particles = both.evaluate(FLOW, u, solver="tpmc", seed=3)
    reference = solver.coefficients(FLOW, flow_direction=u, particles=2000, seed=3)
    assert np.array_equal(particles.Cf_G, reference.Cf_G)
    with pytest.raises(ValueError, match="solver"):
        both.evaluate(FLOW, u, solver="dsmc")


def test_a_database_lookup_is_handed_the_unit_direction():
    model = build_model(Setup())
    seen = []

    def lookup(u):
        seen.append(u)
        if u[2] > 0.9:
            raise ValueError("outside the database's attitudes")
        return 2.0 * u, np.array([u[1], -u[0], 0.5])

    database = model.with_lookup(lookup)
    assert database.backend == "database" and database.cache is None
    assert model.backend == "panel"  # (the model itself is unchanged)
    gas = np.array([-3.0, 0.4, 1.2])
    result = database.evaluate(FLOW, gas)
    u = frames.unit_vector(gas)
    assert np.array_equal(seen[-1], u) and np.array_equal(result.flow_direction, u)
    assert np.array_equal(result.Cf_G, 2.0 * u)
    q, reference = 37.5, model.method.reference
    assert np.array_equal(result.force(q), q * reference.area * (2.0 * u))
    assert np.array_equal(result.torque(q), (q * reference.area * reference.length) * result.Cm_G)
    assert math.isnan(result.area_projected)
    with pytest.raises(ValueError, match="per-panel"):
        result.cp
    with pytest.raises(ValueError, match="outside"):
        database.evaluate(FLOW, [0.0, 0.0, 1.0])


@pytest.mark.parametrize("interpolation", [False, True])
def test_solar_equals_the_kernel_with_the_cache_lightings(interpolation):
    policy = ShadingPolicy(cache_resolution_deg=4.0, interpolation=interpolation)
    model = build_model(Setup(shading=policy))
    twin = rigid_twin(model, interpolate=interpolation)
    for u in directions():
        sun = -u / np.linalg.norm(u)
        model.evaluate(FLOW, u)  # (the flow's reads and the Sun's share the cells)
        result = model.solar(sun)
        reference = solar_coefficients(model.method, sun, lighting=twin.lighting(-sun))
        for name in ("Cf_G", "Cm_G", "Cf_s", "Cm_S"):
            assert np.array_equal(getattr(result, name), getattr(reference, name)), name
        assert result.area_lit == reference.area_lit
    none = build_model(Setup(shading=ShadingPolicy("none")))
    sun = np.array([0.3, -0.2, 0.9])
    assert np.array_equal(
        none.solar(sun).Cf_G, solar_coefficients(none.method, sun, lighting=None).Cf_G
    )


def test_with_setup_keeps_the_cache_when_only_the_model_changes():
    setup = Setup(shading=ShadingPolicy(cache_resolution_deg=4.0))
    model = build_model(setup)
    u = directions()[3]
    model.evaluate(FLOW, u)
    other = model.with_setup(
        replace(setup, model="maxwell", surface=replace(setup.surface, alpha=0.7))
    )
    assert other.cache is model.cache and other.mesh is model.mesh
    assert other.method is not model.method and other.method.model == "maxwell"
    twin = rigid_twin(model, interpolate=True)
    same(
        other.evaluate(FLOW, u),
        other.method.coefficients(FLOW, flow_direction=u, lighting=twin.lighting(u)),
    )
    reshaded = model.with_setup(replace(setup, shading=replace(setup.shading, cache_size=10)))
    assert reshaded.mesh is model.mesh and reshaded.cache is not model.cache
    assert reshaded.cache.max_entries == 10
    moved = model.with_setup(replace(setup, body=BodySpec("intake-box")))
    assert moved.mesh.n_panels != model.mesh.n_panels


def test_bad_inputs_are_refused_naming_them():
    model = build_model(Setup())
    with pytest.raises(ValueError, match="not both"):
        model.evaluate(FLOW, [1.0, 0.0, 0.0], angles=(0.1, 0.2))
    with pytest.raises(ValueError, match="flow"):
        model.evaluate(FLOW, [0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="exact_offline"):
        Setup(shading=ShadingPolicy(exact_offline=-1))
