"""The shading of an articulated body: on the joint grid, the nearest grid point or the blend of
the Kuhn simplex of grid points around the positions (continuous in them); in exact mode
(``joint_shading_exact``), the ray-cast shading of the body posed at the positions for the flow
direction itself, counted as the node reports it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbsat_ros.estimator.settings import WrenchSettings, setup_from_settings
from adbsat_ros.geometry import frames
from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.example_urdf import example_finned_urdf, example_satellite_urdf
from adbsat_ros.physics.model import build_model
from adbsat_ros.shading.cache import ShadingCache
from adbsat_ros.shading.joint_grid import grid_key
from adbsat_ros.shading.lighting import lit_projected_area
from adbsat_ros.shading.shader import make_shader

STEP = math.radians(2.0)


@pytest.fixture(scope="module")
def wings():
    return ArticulatedBody.from_urdf(example_satellite_urdf())


@pytest.fixture(scope="module")
def fins():
    return ArticulatedBody.from_urdf(example_finned_urdf())


def configuration_cache(body, interpolate, step=STEP):
    return ShadingCache(
        body=body,
        posed_shader=lambda positions: make_shader(body.mesh(positions)),
        resolution_deg=0.25,
        angle_step=step,
        length_step=1e-3,
        joint_interpolate=interpolate,
        max_configurations=256,
    )


def lighting_at(cache, u, positions):
    return cache.lighting(u, cache.vertices(positions))


def test_the_simplex_weights_reproduce_the_positions(fins):
    cache = configuration_cache(fins, True)
    rng = np.random.default_rng(11)
    names = list(fins.joints)
    for _ in range(50):
        q = rng.uniform(-0.5, 0.5, len(names))
        vertices = cache.vertices(dict(zip(names, q.tolist())))
        weights = np.array([w for w, _ in vertices])
        points = np.array([key for _, key in vertices], dtype=float) * STEP
        assert 1 <= len(vertices) <= len(names) + 1
        assert (weights > 0.0).all() and weights.sum() == pytest.approx(1.0, abs=1e-12)
        np.testing.assert_allclose(weights @ points, q, rtol=0, atol=1e-12)
        # the vertices are corners of the grid cell around q
        assert (np.abs(points - q) <= STEP * (1 + 1e-9)).all()


def test_at_and_near_a_joint_limit_the_blend_reproduces_the_positions(fins):
    """The fins' limits (+-0.6 rad) are no multiple of 2 deg: in the cell the limit cuts, the
    weights are measured between the clipped grid positions."""
    cache = configuration_cache(fins, True)
    names = list(fins.joints)
    for q0 in (0.6, 0.599, -0.6, -0.5995):
        positions = {name: (q0 if k == 0 else 0.1 * k) for k, name in enumerate(names)}
        vertices = cache.vertices(positions)
        weights = np.array([w for w, _ in vertices])
        points = np.array([list(cache.configuration(key).values()) for _, key in vertices])
        assert (weights > 0.0).all() and weights.sum() == pytest.approx(1.0, abs=1e-12)
        np.testing.assert_allclose(weights @ points, list(positions.values()), atol=1e-12)
    at_limit = {name: 0.6 for name in names}
    assert [list(cache.configuration(key).values()) for _, key in cache.vertices(at_limit)] == [
        [0.6] * 4
    ]


def test_on_a_grid_point_one_configuration_is_used(fins):
    cache = configuration_cache(fins, True)
    on_grid = {name: math.radians(2.0 * k) for k, name in enumerate(fins.joints)}  # (rounding)
    assert cache.vertices(on_grid) == [(1.0, (0, 1, 2, 3))]
    equal = dict.fromkeys(fins.joints, 0.3)  # one fraction for all: two points, not five
    assert len(cache.vertices(equal)) == 2
    key = grid_key(fins.joints, cache.steps, equal)
    assert configuration_cache(fins, False).vertices(equal) == [(1.0, key)]


def lit_area(body, cache, positions, u):
    return lit_projected_area(body.mesh(positions), u, lighting_at(cache, u, positions))


def test_the_blend_is_continuous_across_the_grid_and_exact_on_it(wings):
    """A wing turning through grid lines behind the body: the snapped lighting steps at the
    midpoints between grid points, the blend does not, and on a grid point it is that point's."""
    u = frames.flow_direction(0.0, math.radians(150.0))  # the body shades the left wing
    blend, snap = configuration_cache(wings, True), configuration_cache(wings, False)
    name = "wing_left_hinge"
    mid = 7.5 * STEP  # between grid points 7 and 8
    eps = 1e-7
    other = {"wing_right_hinge": 0.0}
    below, above = {name: mid - eps, **other}, {name: mid + eps, **other}
    mesh = wings.mesh({name: mid, **other})  # (one mesh: the lightings' change alone)

    def step(cache):
        return lit_projected_area(mesh, u, lighting_at(cache, u, above)) - lit_projected_area(
            mesh, u, lighting_at(cache, u, below)
        )

    step_snap, step_blend = step(snap), step(blend)
    assert abs(step_snap) > 1e-6  # m^2: the nearest point changes here, and its shadow
    assert abs(step_blend) < 1e-3 * abs(step_snap)
    at = {name: 8 * STEP, **other}
    np.testing.assert_array_equal(
        lighting_at(blend, u, at).lit_fraction, lighting_at(snap, u, at).lit_fraction
    )
    assert blend.last_keys == (((8, 0), blend.key(u)),)


def test_the_blend_is_closer_to_the_exact_shading_than_the_nearest_point(fins):
    """Lit projected area against shading at the exact configuration, over attitudes and
    deflections where the parts shade each other."""
    blend, snap = configuration_cache(fins, True), configuration_cache(fins, False)
    rng = np.random.default_rng(5)
    errors = {"blend": [], "snap": []}
    for _ in range(6):
        u = frames.flow_direction(math.radians(rng.uniform(-40, 40)), math.radians(160.0))
        q = dict(zip(fins.joints, rng.uniform(-0.17, 0.17, 4).tolist()))
        exact = lit_projected_area(fins.mesh(q), u, make_shader(fins.mesh(q)).lighting(u))
        errors["blend"].append(abs(lit_area(fins, blend, q, u) - exact))
        errors["snap"].append(abs(lit_area(fins, snap, q, u) - exact))
    assert max(errors["snap"]) > 0.0  # (inter-part shading changed with the deflections)
    assert sum(errors["blend"]) < 0.5 * sum(errors["snap"])
    # counters: every grid point read is counted, kept or made
    assert blend.configuration_hits + blend.configuration_misses >= 6
    assert blend.misses >= len(blend) >= 6  # (each point made has shaded its cell)


# ---------------------------------------------------------------- exact mode
@pytest.fixture(scope="module", params=["wings", "fins"])
def body(request):
    text = example_satellite_urdf() if request.param == "wings" else example_finned_urdf()
    return ArticulatedBody.from_urdf(text)


def source(body, **parameters):
    """The node's shading cache of ``body`` with these parameters."""
    settings = WrenchSettings.from_parameters(parameters)
    return build_model(setup_from_settings(settings), body).cache


def lighting(cache, u, positions):
    """``(lighting, hit)`` of one read at joint ``positions``: its one cell's."""
    hits = cache.hits
    [(_, cell)] = cache.read(u, cache.vertices(positions))
    return cell.lighting, cache.hits > hits


def random_cases(body, n, seed):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        positions = {
            name: float(rng.uniform(max(joint.lower, -1.0), min(joint.upper, 1.0)))
            for name, joint in body.joints.items()
        }
        aoa, aos = math.radians(rng.uniform(-40.0, 40.0)), math.radians(rng.uniform(-180, 180))
        yield positions, frames.flow_direction(aoa, aos)


def test_it_is_the_ray_cast_shading_of_the_body_posed_at_the_positions(body):
    """Against a shader made afresh for the posed panels (its own vertex merging and topology,
    where the exact mode reuses the links' own): the same lit fractions and shifts to rounding.
    """
    exact = source(body, joint_shading_exact=True)
    shaded = 0
    for positions, u in random_cases(body, 5, seed=3):
        lit, hit = lighting(exact, u, positions)
        reference = make_shader(body.mesh(positions), topology_store=None).lighting(u)
        np.testing.assert_allclose(lit.lit_fraction, reference.lit_fraction, atol=1e-12)
        shift = np.zeros((body.mesh().n_panels, 3))
        shift[lit.shift_index] = lit.shift
        expected = np.zeros_like(shift)
        expected[reference.shift_index] = reference.shift
        np.testing.assert_allclose(shift, expected, atol=1e-12)
        assert hit is False  # (shaded, not read)
        shaded += int((reference.lit_fraction < 1.0).any())
    assert shaded >= 2  # (some parts shade others in these cases)


def test_on_the_grid_and_at_a_cell_centre_it_is_the_grid_caches_answer(body):
    """The grid cache (nearest configuration, nearest direction cell) samples the exact mode:
    at a grid configuration and a cell centre both give the same numbers, bit for bit."""
    grid = source(body, shading_interpolation=False)
    exact = source(body, joint_shading_exact=True)
    step = math.radians(0.25)
    for k, (positions, u) in enumerate(random_cases(body, 3, seed=5)):
        on_grid = {name: round(q / step) * step for name, q in positions.items()}
        centre = grid.centre(grid.key(u))
        a, _ = lighting(grid, centre, on_grid)
        b, _ = lighting(exact, centre, on_grid)
        np.testing.assert_array_equal(a.lit_fraction, b.lit_fraction)
        np.testing.assert_array_equal(a.shift_index, b.shift_index)
        np.testing.assert_array_equal(a.shift, b.shift)


def test_its_counters_say_what_was_posed_and_what_was_shaded(body):
    cache = source(body, joint_shading_exact=True)
    (p1, u1), (p2, u2) = random_cases(body, 2, seed=8)
    lighting(cache, u1, p1)
    assert (cache.configuration_misses, cache.configuration_hits) == (1, 0)
    assert (cache.misses, cache.hits) == (1, 0)
    _, hit = lighting(cache, u1, p1)  # the same message again: the same lighting, read
    assert hit is True and (cache.misses, cache.hits) == (1, 1)
    lighting(cache, u2, p1)  # the joints have not moved: the posed body kept, shaded again
    assert (cache.configuration_misses, cache.configuration_hits) == (1, 1)
    assert cache.misses == 2
    lighting(cache, u2, p2)  # new positions: posed again
    assert cache.configuration_misses == 2 and cache.misses == 3
    assert cache.last_keys == ((tuple(p2[name] for name in body.joints), tuple(u2.tolist())),)
    assert cache.info()["misses"] == 3
