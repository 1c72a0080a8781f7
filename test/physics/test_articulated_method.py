"""The articulated panel method (each link in its own frame, made once) against the panel method
of the posed body's merged mesh: the same totals, per-panel values, link loads and joint efforts
at every configuration, with shading; the fin's hinge torque against a hand computation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fin_cases import FIN_URDF, newton_hinge_torque

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.example_satellite import BODY_SIZE, WING_GAP, WING_SIZE, WING_X_CENTRE
from adbsat_ros.geometry.example_urdf import example_finned_urdf, example_satellite_urdf
from adbsat_ros.physics.articulated_method import ArticulatedMethod
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.facets import blend_sums
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.panel_loads import panel_loads
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.physics.posed_facets import PosedSums
from adbsat_ros.physics.surface import MaterialTable, SurfaceProperties
from adbsat_ros.shading.lighting import LightingBlend
from adbsat_ros.shading.shader import make_shader

FLOW = FreeStream(7800.0, 1000.0, mean_mass_amu=16.0)
REFERENCE = Reference(moment_point=(0.1, 0.02, -0.03))


@pytest.fixture(scope="module", params=["wings", "fins"])
def body(request):
    text = example_satellite_urdf() if request.param == "wings" else example_finned_urdf()
    return ArticulatedBody.from_urdf(text)


def configurations(body):
    """Three configurations within the joints' limits, each joint at its own position."""
    out = []
    for scale in (0.0, 0.5, -0.9):
        values = {}
        for k, (name, joint) in enumerate(body.joints.items()):
            span = min(joint.upper, 1.0)
            values[name] = scale * span * (1.0 - 0.2 * k)
        out.append(values)
    return out


def directions():
    out = []
    for aoa, aos in ((0.0, 0.0), (25.0, 40.0), (-60.0, 130.0)):
        out.append(frames.flow_direction(math.radians(aoa), math.radians(aos)))
    return out


def test_equals_the_panel_method_of_the_posed_mesh(body):
    """One method object for every configuration: nothing is rebuilt when a joint moves."""
    method = ArticulatedMethod(body, "sentman", reference=REFERENCE)
    assert method.facets is not None  # (boxes: the links' facets posed, one evaluation)
    shaded_somewhere = False
    for values in configurations(body):
        mesh = body.mesh(values)
        shader = make_shader(mesh)
        merged = PanelMethod(mesh, "sentman", reference=method.reference)
        for u in directions():
            lighting = shader.lighting(u)
            shaded_somewhere |= lighting.shaded_index.size > 0
            got = method.coefficients(FLOW, values, flow_direction=u, lighting=lighting)
            want = merged.coefficients(FLOW, flow_direction=u, lighting=lighting)
            total = got.total
            np.testing.assert_allclose(total.Cf_G, want.Cf_G, rtol=0, atol=1e-13)
            np.testing.assert_allclose(total.Cm_G, want.Cm_G, rtol=0, atol=1e-13)
            assert total.area_projected == pytest.approx(want.area_projected, rel=1e-13)
            np.testing.assert_allclose(total.cp, want.cp, rtol=0, atol=1e-12)
            np.testing.assert_allclose(total.ctau, want.ctau, rtol=0, atol=1e-12)
            np.testing.assert_array_equal(total.lit_fraction, want.lit_fraction)
            assert total.drag == pytest.approx(want.drag, rel=1e-12)
            loads = panel_loads(mesh, want)
            split = body.loads(
                loads.force, loads.point, values, loads.moment_point, loads.reference_length
            )
            np.testing.assert_allclose(got.link_force, split.link_force, rtol=0, atol=1e-13)
            np.testing.assert_allclose(got.link_moment, split.link_moment, rtol=0, atol=1e-13)
            for name, effort in split.joint_effort.items():
                assert got.joint_effort[name] == pytest.approx(effort, rel=1e-9, abs=1e-15)
    assert shaded_somewhere  # (inter-part shading was exercised)


def test_link_loads_sum_to_the_total(body):
    method = ArticulatedMethod(body, "cll", reference=REFERENCE)
    flow = FreeStream(7600.0, 800.0, number_densities={"O": 1e15, "N2": 2e14, "He": 1e13})
    values = configurations(body)[1]
    got = method.coefficients(flow, values, math.radians(10.0), math.radians(-20.0))
    np.testing.assert_allclose(got.link_force.sum(axis=0), got.total.Cf_G, rtol=0, atol=1e-15)
    np.testing.assert_allclose(got.link_moment.sum(axis=0), got.total.Cm_G, rtol=0, atol=1e-15)


def test_by_default_it_ray_casts_the_posed_body(body):
    method = ArticulatedMethod(body, "sentman")
    values = configurations(body)[2]
    u = directions()[1]
    own = method.coefficients(FLOW, values, flow_direction=u)
    lighting = make_shader(body.mesh(values)).lighting(u)
    given = method.coefficients(FLOW, values, flow_direction=u, lighting=lighting)
    np.testing.assert_array_equal(own.total.Cf_G, given.total.Cf_G)
    unshaded = ArticulatedMethod(body, "sentman", shading="none")
    assert unshaded.coefficients(FLOW, values, flow_direction=u).total.lighting is None


@pytest.mark.parametrize("d", [0.25, -0.4])
def test_a_fins_hinge_torque_is_the_hand_computed_one(d):
    fin = ArticulatedBody.from_urdf(FIN_URDF)
    method = ArticulatedMethod(fin, "newton", reference=Reference(area=1.0, length=1.0))
    aoa, aos = math.radians(5.0), math.radians(-3.0)
    got = method.coefficients(FLOW, {"hinge": d}, aoa, aos)
    expected = newton_hinge_torque(d, frames.flow_direction(aoa, aos))
    assert abs(expected) > 1e-5
    assert got.joint_effort["hinge"] == pytest.approx(expected, rel=1e-9)
    q = 0.01
    assert got.joint_efforts(q)["hinge"] == pytest.approx(q * expected, rel=1e-12)  # N m


def test_a_prismatic_joints_effort_is_the_force_along_it():
    urdf = FIN_URDF.replace('type="revolute"', 'type="prismatic"').replace(
        '<axis xyz="0 1 0"/>', '<axis xyz="1 0 0"/>'
    )
    body = ArticulatedBody.from_urdf(urdf)
    method = ArticulatedMethod(body, "newton", reference=Reference(area=2.0, length=3.0))
    got = method.coefficients(FLOW, {"hinge": 0.05}, math.radians(20.0), 0.0)
    assert got.joint_effort["hinge"] == pytest.approx(got.total.Cf_G[0], rel=1e-12)
    assert got.joint_efforts(10.0)["hinge"] == pytest.approx(10.0 * 2.0 * got.total.Cf_G[0])


def test_bad_positions_and_lightings_are_refused_by_name(body):
    method = ArticulatedMethod(body, "sentman", shading="none")
    name = next(iter(body.joints))
    with pytest.raises(ValueError, match=f"joint {name}: position .* outside its limits"):
        method.coefficients(FLOW, {name: 10.0}, 0.0, 0.0)
    with pytest.raises(ValueError, match="joint 'nope' is not a moving joint"):
        method.coefficients(FLOW, {"nope": 0.0}, 0.0, 0.0)
    with pytest.raises(ValueError, match=f"joint {name}: position must be finite"):
        method.coefficients(FLOW, {name: math.nan}, 0.0, 0.0)
    wrong = make_shader(body.link_mesh(body.links.index(body.root))).lighting_angles(0.1, 0.2)
    with pytest.raises(ValueError, match="lighting has"):
        method.coefficients(FLOW, None, 0.1, 0.2, lighting=wrong)
    with pytest.raises(ValueError, match="shading must be one of"):
        ArticulatedMethod(body, "sentman", shading="rays")


@pytest.mark.parametrize("gamma_deg", [20.0, 30.0])
def test_the_body_shades_the_root_of_the_wing_behind_it_by_geometry(gamma_deg):
    """Both wings of the example turned 90 deg about their hinges face +x; the gas comes from
    +x and +y at gamma to x (u = (-cos g, -sin g, 0)). The left wing (+y) is upstream of the
    body and fully lit; the body's -y face (y = -0.25, x up to 0.6) shades the right wing's
    front face (x = WING_X_CENTRE + 0.015) over the span 0.05 m from its root up to
    (0.6 - x_face) tan g - 0.05 m. The ray-cast lit areas match, and the shaded wing carries
    less load than the lit one."""
    body = ArticulatedBody.from_urdf(example_satellite_urdf())
    values = {"wing_left_hinge": math.pi / 2, "wing_right_hinge": math.pi / 2}
    mesh = body.mesh(values)
    g = math.radians(gamma_deg)
    u = np.array([-math.cos(g), -math.sin(g), 0.0])
    lighting = make_shader(mesh).lighting(u)
    face_x = WING_X_CENTRE + WING_SIZE[2] / 2
    shaded_span = (BODY_SIZE[0] / 2 - face_x) * math.tan(g) - WING_GAP
    assert 0.0 < shaded_span < WING_SIZE[1]
    front = mesh.normals[:, 0] > 0.999
    lit = {}
    for name in ("wing_left", "wing_right"):
        on_link = front & (body.panel_link == body.links.index(name))
        lit[name] = float((lighting.lit_fraction[on_link] * mesh.areas[on_link]).sum())
    chord = WING_SIZE[0]
    assert lit["wing_left"] == pytest.approx(chord * WING_SIZE[1], rel=1e-9)
    assert lit["wing_right"] == pytest.approx(chord * (WING_SIZE[1] - shaded_span), rel=5e-3)
    result = ArticulatedMethod(body, "sentman").coefficients(FLOW, values, flow_direction=u)
    left, right = (result.link_force[body.links.index(n)] for n in ("wing_left", "wing_right"))
    assert abs(right[0]) < 0.85 * abs(left[0])


SPHERE_ARM_URDF = """<robot name="arm">
  <link name="base"><visual><geometry><box size="0.4 0.4 0.4"/></geometry></visual></link>
  <link name="ball"><visual><origin xyz="0.5 0 0"/>
    <geometry><sphere radius="0.1"/></geometry></visual></link>
  <joint name="swing" type="revolute"><parent link="base"/><child link="ball"/>
    <origin xyz="0.2 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
</robot>"""


def test_a_surface_with_one_value_changed_equals_the_posed_mesh_with_it(body):
    # An accommodation model sets alpha at every message (surface_with): the articulated body
    # with its links' surfaces so changed equals the posed mesh's panel method with its own,
    # materials differing by link (their wall temperatures stay per material); and links
    # given different values of a parameter equal the posed mesh with that parameter per panel.
    names = body.material_names
    materials = MaterialTable(
        SurfaceProperties(wall_temperature=280.0),
        {name: {"wall_temperature": 300.0 + 40.0 * k} for k, name in enumerate(names)},
    )
    method = ArticulatedMethod(body, "sentman", materials, reference=REFERENCE)
    values = configurations(body)[1]
    mesh = body.mesh(values)
    merged = PanelMethod(mesh, "sentman", materials, reference=method.reference)
    u = directions()[1]
    lighting = make_shader(mesh).lighting(u)
    for alpha in (0.62, 0.95):
        got = method.coefficients(
            FLOW,
            values,
            flow_direction=u,
            lighting=lighting,
            surface=method.surface_with(alpha=alpha, alpha_n=alpha),
        ).total
        want = merged.coefficients(
            FLOW,
            flow_direction=u,
            lighting=lighting,
            surface=merged.surface_with(alpha=alpha, alpha_n=alpha),
        )
        np.testing.assert_allclose(got.Cf_G, want.Cf_G, rtol=0, atol=1e-13)
        np.testing.assert_allclose(got.Cm_G, want.Cm_G, rtol=0, atol=1e-13)
    # a different alpha on every link: per panel on the posed mesh
    surfaces = method.surface_with()  # (every link with geometry, in the order of link_spans)
    spans = [span for _, span in sorted(body.link_spans.items())]
    assert len(surfaces) == len(spans)
    per_panel = merged.surface_with()
    per_panel.alpha = np.ones(mesh.n_panels)
    for k, (surface, (start, stop)) in enumerate(zip(surfaces, spans)):
        surface.alpha = 0.5 + 0.1 * k
        per_panel.alpha[start:stop] = surface.alpha
    got = method.coefficients(FLOW, values, flow_direction=u, lighting=lighting, surface=surfaces)
    want = merged.coefficients(FLOW, flow_direction=u, lighting=lighting, surface=per_panel)
    np.testing.assert_allclose(got.total.Cf_G, want.Cf_G, rtol=0, atol=1e-13)
    np.testing.assert_allclose(got.total.Cm_G, want.Cm_G, rtol=0, atol=1e-13)


def test_a_configuration_serves_many_calls_and_only_its_own_method(body):
    method = ArticulatedMethod(body, "sentman", reference=REFERENCE)
    values = configurations(body)[2]
    configuration = method.configuration(values)
    u = directions()[1]
    lighting = make_shader(body.mesh(values)).lighting(u)
    by_positions = method.coefficients(FLOW, values, flow_direction=u, lighting=lighting)
    by_configuration = method.coefficients(FLOW, configuration, flow_direction=u, lighting=lighting)
    np.testing.assert_array_equal(by_configuration.total.Cf_G, by_positions.total.Cf_G)
    np.testing.assert_array_equal(by_configuration.total.Cm_G, by_positions.total.Cm_G)
    np.testing.assert_array_equal(by_configuration.link_moment, by_positions.link_moment)
    other = ArticulatedMethod(body, "sentman", reference=Reference(moment_point=(0.0, 0.3, 0.0)))
    with pytest.raises(ValueError, match="another ArticulatedMethod"):
        other.coefficients(FLOW, configuration, flow_direction=u, lighting=lighting)


def test_a_link_without_facets_is_evaluated_in_its_own_frame_with_the_same_result():
    """A sphere's panels all face their own ways (no facets to group), so the body is evaluated
    link by link in the links' frames instead of as posed facets: the same numbers."""
    body = ArticulatedBody.from_urdf(SPHERE_ARM_URDF)
    method = ArticulatedMethod(body, "sentman", reference=REFERENCE)
    assert method.facets is None
    values = {"swing": 0.7}
    mesh = body.mesh(values)
    u = directions()[1]
    lighting = make_shader(mesh).lighting(u)
    got = method.coefficients(FLOW, values, flow_direction=u, lighting=lighting)
    want = PanelMethod(mesh, "sentman", reference=method.reference).coefficients(
        FLOW, flow_direction=u, lighting=lighting
    )
    np.testing.assert_allclose(got.total.Cf_G, want.Cf_G, rtol=0, atol=1e-13)
    np.testing.assert_allclose(got.total.Cm_G, want.Cm_G, rtol=0, atol=1e-13)
    np.testing.assert_allclose(got.total.cp, want.cp, rtol=0, atol=1e-12)


def test_a_blend_gives_the_same_numbers_whichever_of_its_parts_were_seen_before(body):
    """A joint state poses a blend's parts together; a part seen alone before is read back.
    Either way every output is the same, bit for bit (offline analysis and a live node meet
    the parts in different orders)."""
    values = configurations(body)[1]
    us = directions()
    mesh = body.mesh(values)
    shader = make_shader(mesh)
    parts = [shader.lighting(u) for u in us]
    blend = LightingBlend([(0.5, parts[0]), (0.3, parts[1]), (0.2, parts[2])])
    together = ArticulatedMethod(body, "sentman", reference=REFERENCE)
    one_by_one = ArticulatedMethod(body, "sentman", reference=REFERENCE)
    u = us[0]
    for part in parts[:2]:  # (two parts met alone first, at these positions)
        one_by_one.coefficients(FLOW, values, flow_direction=u, lighting=part)
    a = together.coefficients(FLOW, values, flow_direction=u, lighting=blend)
    b = one_by_one.coefficients(FLOW, values, flow_direction=u, lighting=blend)
    for name in ("Cf_G", "Cm_G"):
        np.testing.assert_array_equal(getattr(a.total, name), getattr(b.total, name))
    np.testing.assert_array_equal(a.link_force, b.link_force)
    np.testing.assert_array_equal(a.link_moment, b.link_moment)
    np.testing.assert_array_equal(a.effort_coefficients, b.effort_coefficients)
    # and the blend is the weighted mean of its parts' results (the method is linear in them)
    alone = [
        ArticulatedMethod(body, "sentman", reference=REFERENCE).coefficients(
            FLOW, values, flow_direction=u, lighting=part
        )
        for part in parts
    ]
    mean = sum(w * c.total.Cf_G for w, c in zip((0.5, 0.3, 0.2), alone))
    np.testing.assert_allclose(a.total.Cf_G, mean, rtol=1e-12, atol=1e-15)
    efforts = sum(w * c.effort_coefficients for w, c in zip((0.5, 0.3, 0.2), alone))
    np.testing.assert_allclose(a.effort_coefficients, efforts, rtol=1e-10, atol=1e-14)


def test_the_rows_posed_and_blended_give_the_lightings_coefficients_bit_for_bit(body):
    """The pure entries (a lighting's link rows, blended and posed at the configuration's
    posing; the coefficients of them) give what ``coefficients(lighting=...)`` gives, bit for
    bit, for a blend, one lighting and none; and posing the blend equals blending the posed
    parts (posing is linear)."""
    values = configurations(body)[2]
    us = directions()
    shader = make_shader(body.mesh(values))
    parts = [shader.lighting(u) for u in us]
    weights = (0.5, 0.3, 0.2)
    blend = LightingBlend(list(zip(weights, parts)))
    method = ArticulatedMethod(body, "sentman", reference=REFERENCE)
    pure = ArticulatedMethod(body, "sentman", reference=REFERENCE)
    configuration = pure.configuration(values)
    posing, facets = configuration.posing, pure.facets
    u, angles = frames.attitude_flow(None, None, us[1])
    for lighting, lit_parts, part_weights in (
        (blend, parts, weights),
        (parts[1], parts[1:2], (1.0,)),
        (None, [None], (1.0,)),
    ):
        rows = [facets.link_rows(part) for part in lit_parts]
        sums = PosedSums(blend_sums(list(zip(part_weights, rows))), posing)
        got = pure.coefficients_of_rows(FLOW, u, angles, configuration, sums, lighting)
        want = method.coefficients(FLOW, values, flow_direction=us[1], lighting=lighting)
        for name in ("Cf_G", "Cm_G", "cp", "ctau", "lit_fraction"):
            np.testing.assert_array_equal(getattr(got.total, name), getattr(want.total, name))
        assert got.total.area_projected == want.total.area_projected
        np.testing.assert_array_equal(got.effort_coefficients, want.effort_coefficients)
        np.testing.assert_array_equal(got.link_force, want.link_force)
        np.testing.assert_array_equal(got.link_moment, want.link_moment)
        for matrix, posed in ((posing.matrix, sums.ten), (posing.efforts, sums.columns)):
            parts_posed = [np.einsum("gi,gic->gc", r, matrix) for r in rows]
            blended = sum(w * p for w, p in zip(part_weights, parts_posed))
            np.testing.assert_allclose(posed, blended, rtol=1e-12, atol=1e-12 * abs(blended).max())
    assert np.abs(want.link_force).max() > 0.0
    # the rows are the lighting's alone: the same bits on a method that saw other lightings
    np.testing.assert_array_equal(facets.link_rows(parts[0]), method.facets.link_rows(parts[0]))


def test_a_link_without_facets_splits_a_blend_by_link_with_the_same_result():
    """Evaluated link by link, a blend's parts are split into the links' panels per message
    (a link with no panel shaded in any part all lit): the numbers of the posed mesh's panel
    method with the same blend, and of the pure entry."""
    body = ArticulatedBody.from_urdf(SPHERE_ARM_URDF)
    method = ArticulatedMethod(body, "sentman", reference=REFERENCE)
    values = {"swing": 0.4}
    mesh = body.mesh(values)
    us = directions()
    shader = make_shader(mesh)
    blend = LightingBlend([(0.6, shader.lighting(us[1])), (0.4, shader.lighting(us[2]))])
    got = method.coefficients(FLOW, values, flow_direction=us[1], lighting=blend)
    want = PanelMethod(mesh, "sentman", reference=method.reference).coefficients(
        FLOW, flow_direction=us[1], lighting=blend
    )
    np.testing.assert_allclose(got.total.Cf_G, want.Cf_G, rtol=0, atol=1e-13)
    np.testing.assert_allclose(got.total.Cm_G, want.Cm_G, rtol=0, atol=1e-13)
    assert got.total.area_projected == pytest.approx(want.area_projected, rel=1e-13)
    configuration = method.configuration(values)
    u, angles = frames.attitude_flow(None, None, us[1])
    pure = method.coefficients_of_rows(FLOW, u, angles, configuration, None, blend)
    np.testing.assert_array_equal(pure.total.Cf_G, got.total.Cf_G)
    np.testing.assert_array_equal(pure.effort_coefficients, got.effort_coefficients)


def test_a_configuration_makes_its_load_map_once_when_the_links_loads_are_read(body):
    """The load map is the configuration's own: the links' loads of two evaluations there read
    one map, and a configuration at other positions gives other efforts."""
    method = ArticulatedMethod(body, "sentman", reference=REFERENCE, shading="none")
    first, second = (method.configuration(v) for v in configurations(body)[1:])
    a = method.coefficients(FLOW, first, 0.2, 0.1)
    b = method.coefficients(FLOW, first, -0.3, 0.4)
    assert "load_map" not in vars(first)  # (only the totals read so far)
    np.testing.assert_allclose(a.link_force.sum(axis=0), a.total.Cf_G, rtol=0, atol=1e-15)
    b.link_moment
    assert first.load_map is vars(first)["load_map"]
    c = method.coefficients(FLOW, second, 0.2, 0.1)
    assert np.any(c.effort_coefficients != a.effort_coefficients)
    np.testing.assert_allclose(c.link_moment.sum(axis=0), c.total.Cm_G, rtol=0, atol=1e-15)
