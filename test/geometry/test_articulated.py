"""Articulated satellites from a URDF: the panels of a configuration are its parts merged into
one mesh, a turned joint turns its link's panels about its axis, and bad joint positions and
files are refused by name."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fin_cases import FIN_URDF, newton_hinge_torque, rotation_y

from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.example_satellite import BODY_SIZE, WING_GAP, WING_X_CENTRE, combine
from adbsat_ros.geometry.example_urdf import example_satellite_urdf
from adbsat_ros.geometry.mesh import MeshError
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.shading.shader import make_shader

FLOW = FreeStream(7800.0, 1000.0, mean_mass_amu=16.0)


@pytest.fixture(scope="module")
def body():
    return ArticulatedBody.from_urdf(example_satellite_urdf(), source="example-articulated")


def coefficients(mesh, aoa_deg, aos_deg):
    """Sentman with ray-cast shading (inter-part shading matters) at one attitude."""
    shader = make_shader(mesh, mode="raycast")
    aoa, aos = math.radians(aoa_deg), math.radians(aos_deg)
    method = PanelMethod(mesh, "sentman")
    return method.coefficients(FLOW, aoa, aos, lighting=shader.lighting_angles(aoa, aos))


def test_at_zero_the_panels_are_the_parts_merged_into_one_mesh(body):
    mesh = body.mesh()
    parts = body.parts()
    merged = combine(
        [(v, f) for _, v, f, _ in parts],
        part_materials=[m for _, _, _, m in parts],
        material_names=body.material_names,
    )
    for name in ("vertices", "normals", "areas", "barycentres", "material_index"):
        np.testing.assert_array_equal(getattr(mesh, name), getattr(merged, name))
    assert mesh.material_names == merged.material_names == ("body", "solar_array")
    a, b = coefficients(mesh, 20.0, 35.0), coefficients(merged, 20.0, 35.0)
    np.testing.assert_array_equal(a.Cf_G, b.Cf_G)
    np.testing.assert_array_equal(a.Cm_G, b.Cm_G)
    assert body.panel_link.shape == (mesh.n_panels,)
    assert set(np.unique(body.panel_link)) == {0, 1, 2}


@pytest.mark.parametrize("theta_deg", [-60.0, 15.0, 90.0, 150.0])
def test_a_turned_hinge_is_the_wing_rotated_about_it(body, theta_deg):
    """The left wing's hinge at theta equals the zero configuration's wing rotated by theta
    about the hinge line (through (WING_X_CENTRE, 0.3, 0), along y), computed here by hand; the
    coefficients with ray-cast shading agree to rounding."""
    theta = math.radians(theta_deg)
    turned = body.mesh({"wing_left_hinge": theta})
    hinge = np.array([WING_X_CENTRE, BODY_SIZE[1] / 2 + WING_GAP, 0.0])
    by_hand = []
    for link, v, f, material in body.parts():
        if link == "wing_left":
            v = (v - hinge) @ rotation_y(theta).T + hinge
        by_hand.append((v, f, material))
    reference = combine(
        [(v, f) for v, f, _ in by_hand],
        part_materials=[m for _, _, m in by_hand],
        material_names=body.material_names,
    )
    np.testing.assert_allclose(turned.vertices, reference.vertices, atol=1e-12)
    for aoa, aos in ((0.0, 0.0), (30.0, -20.0), (-45.0, 60.0)):
        a, b = coefficients(turned, aoa, aos), coefficients(reference, aoa, aos)
        np.testing.assert_allclose(a.Cf_G, b.Cf_G, rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(a.Cm_G, b.Cm_G, rtol=1e-9, atol=1e-12)
    untouched = body.panel_link != body.links.index("wing_left")
    np.testing.assert_array_equal(turned.vertices[untouched], body.mesh().vertices[untouched])


def test_turning_a_wing_changes_the_drag_as_its_projected_area(body):
    """Edge-on at zero (the wings' faces parallel to the flow at aoa = 0: 1.0 m x 0.03 m seen),
    a wing turned by 90 deg faces the flow (1.0 m x 0.5 m seen): the projected area grows by
    1.0 m x (0.5 m - 0.03 m), nothing shading it."""
    flat = coefficients(body.mesh(), 0.0, 0.0)
    turned = coefficients(body.mesh({"wing_left_hinge": math.pi / 2}), 0.0, 0.0)
    assert turned.area_projected - flat.area_projected == pytest.approx(
        1.0 * (0.5 - 0.03), rel=1e-9
    )
    assert turned.drag > flat.drag


@pytest.mark.parametrize(
    "values, message",
    [
        (
            {"elbow": 0.1},
            "joint 'elbow' is not a moving joint of example-articulated; its joints are",
        ),
        ({"wing_left_hinge": math.nan}, "joint wing_left_hinge: position must be finite"),
        ({"wing_left_hinge": "up"}, "joint wing_left_hinge: position must be a number"),
        ({"wing_left_hinge": 3.2}, r"outside its limits \[-3.14159, 3.14159\] rad"),
    ],
)
def test_bad_joint_positions_are_refused_by_name(body, values, message):
    with pytest.raises(ValueError, match=message):
        body.mesh(values)


@pytest.mark.parametrize(
    "text, message",
    [
        ("<robot name='x'><link name='a'/></robot>", "no link has geometry"),
        ("<robot name='x'><link name='a'>", "not a readable URDF"),
        (
            "<robot name='x'><link name='a'><visual><geometry><box size='500 1 1'/></geometry>"
            "</visual></link></robot>",
            "the mesh is 500 m across",
        ),
        (
            "<robot name='x'><link name='a'><visual><geometry><box size='1 1 1'/></geometry>"
            "</visual></link><link name='b'/></robot>",
            "one tree from one root link; links no joint carries: a, b",
        ),
        (
            "<robot name='x'><link name='a'><visual><geometry><box size='1 1 1'/></geometry>"
            "</visual></link><link name='b'/><link name='c'/>"
            "<joint name='j1' type='fixed'><parent link='b'/><child link='c'/></joint>"
            "<joint name='j2' type='fixed'><parent link='c'/><child link='b'/></joint></robot>",
            "links not carried from the root a by a chain of joints: b, c",
        ),
        (
            "<robot name='x'><link name='a'><visual><geometry><box size='1 1 1'/></geometry>"
            "</visual></link><link name='b'/>"
            "<joint name='j' type='revolute'><parent link='a'/><child link='b'/>"
            "<axis xyz='0 0 0'/><limit lower='-1' upper='1' effort='1' velocity='1'/>"
            "</joint></robot>",
            r"joint j: axis \(0, 0, 0\) has no direction",
        ),
        (
            "<robot name='x'><link name='a'><visual><geometry><box size='1 1 1'/></geometry>"
            "</visual></link><link name='b'/>"
            "<joint name='j' type='continuous'><parent link='a'/><child link='b'/>"
            "<axis xyz='0 nan 1'/></joint></robot>",
            r"joint j: axis \(0, nan, 1\) has no direction",
        ),
        (
            "<robot name='x'><link name='a'><visual><geometry><box size='1 1 1'/></geometry>"
            "</visual></link><link name='b'/><link name='c'/>"
            "<joint name='j' type='revolute'><parent link='a'/><child link='b'/></joint>"
            "<joint name='k' type='revolute'><parent link='b'/><child link='c'/></joint>"
            "<joint name='l' type='fixed'><parent link='c'/><child link='b'/></joint></robot>",
            "joint l: its child 'b' is not a link, or is carried by another joint too",
        ),
        (
            "<robot name='x'><link name='a'><visual><geometry><box size='1 1 1'/></geometry>"
            "</visual></link>"
            "<joint name='j' type='revolute'><parent link='a'/><child link='z'/></joint></robot>",
            "joint j: its child 'z' is not a link",
        ),
        (
            "<robot name='x'><link name='a'><visual><geometry><box size='1 1 1'/></geometry>"
            "</visual></link><link name='b'/><link name='c'/>"
            "<joint name='f' type='fixed'><parent link='a'/><child link='b'/></joint>"
            "<joint name='m' type='continuous'><parent link='a'/><child link='c'/>"
            "<mimic joint='f'/></joint></robot>",
            "joint m mimics 'f', which is not a moving joint; the moving joints are none",
        ),
    ],
)
def test_bad_urdfs_are_refused_naming_the_problem(text, message):
    with pytest.raises(MeshError, match=message):
        ArticulatedBody.from_urdf(text)


def test_the_links_loads_sum_to_the_totals(body):
    """Per-panel loads (panel_loads) summed per link give the total force and moment, with
    shading (partly lit panels act at their lit centroids)."""
    from adbsat_ros.physics.panel_loads import panel_loads

    values = {"wing_left_hinge": 0.7, "wing_right_hinge": -0.3}
    mesh = body.mesh(values)
    result = coefficients(mesh, 25.0, 40.0)
    assert result.lighting.shift_index.size > 0  # some panels partly shaded
    loads = panel_loads(mesh, result)
    split = body.loads(loads.force, loads.point, values, loads.moment_point, loads.reference_length)
    np.testing.assert_allclose(split.link_force.sum(axis=0), result.Cf_G, rtol=0, atol=1e-13)
    np.testing.assert_allclose(split.link_moment.sum(axis=0), result.Cm_G, rtol=0, atol=1e-13)
    assert set(split.joint_effort) == {"wing_left_hinge", "wing_right_hinge"}


@pytest.mark.parametrize("d", [0.2, -0.35, 0.6])
def test_a_fins_hinge_torque_is_the_hand_computed_one(d):
    from adbsat_ros.geometry import frames
    from adbsat_ros.physics.coefficients import Reference
    from adbsat_ros.physics.panel_loads import panel_loads

    fin = ArticulatedBody.from_urdf(FIN_URDF)
    mesh = fin.mesh({"hinge": d})
    method = PanelMethod(mesh, "newton", reference=Reference(area=1.0, length=1.0))
    aoa, aos = math.radians(5.0), math.radians(-3.0)
    result = method.coefficients(FLOW, aoa, aos)
    loads = panel_loads(mesh, result)
    split = fin.loads(loads.force, loads.point, {"hinge": d}, np.zeros(3), 1.0)
    expected = newton_hinge_torque(d, frames.flow_direction(aoa, aos))
    assert split.joint_effort["hinge"] == pytest.approx(expected, rel=1e-9)
    assert abs(expected) > 1e-5  # (a fin's load passes close to its hinge)


def test_fins_deflected_either_way_give_mirrored_pitch_and_yaw():
    """The finned example (symmetric about its x-z and x-y planes) in a flow along x: the pitch
    fins deflected by +d and -d give opposite pitch moments and hinge torques, the yaw fins
    opposite yaw moments; nothing else changes sign."""
    from adbsat_ros.geometry.loading import articulated_body
    from adbsat_ros.physics.panel_loads import panel_loads

    finned = articulated_body("example-finned")
    method_for = {}
    out = {}
    for sign in (1.0, -1.0):
        values = {"fin_py_hinge": sign * 0.3, "fin_ny_hinge": sign * 0.3}
        values |= {"fin_pz_hinge": sign * 0.2, "fin_nz_hinge": sign * 0.2}
        mesh = finned.mesh(values)
        method_for[sign] = PanelMethod(mesh, "sentman", shading="none")  # (symmetry of geometry)
        result = method_for[sign].coefficients(FLOW, 0.0, 0.0)
        loads = panel_loads(mesh, result)
        out[sign] = (result, finned.loads(loads.force, loads.point, values, np.zeros(3), 1.0))
    (rp, lp), (rn, ln) = out[1.0], out[-1.0]
    assert rp.drag == pytest.approx(rn.drag, rel=1e-9)
    np.testing.assert_allclose(rp.Cm_G[1:], -rn.Cm_G[1:], rtol=1e-9, atol=1e-15)
    assert abs(rp.Cm_G[1]) > 1e-3 and abs(rp.Cm_G[2]) > 1e-3  # pitch and yaw
    for name in finned.joints:
        assert lp.joint_effort[name] == pytest.approx(-ln.joint_effort[name], rel=1e-9)


TREE_URDF = """<robot name="tree">
  <link name="base"><visual><geometry><box size="1 1 1"/></geometry></visual></link>
  <link name="arm"><visual><geometry><box size="0.2 0.2 1"/></geometry></visual></link>
  <link name="slider"/>
  <link name="tip"><visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual></link>
  <link name="twin"><visual><geometry><box size="0.3 0.1 0.1"/></geometry></visual></link>
  <link name="camera"/>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="arm"/>
    <origin xyz="0.5 0.1 -0.2" rpy="0.3 -0.2 0.9"/><axis xyz="0 1 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/>
  </joint>
  <joint name="slide" type="prismatic">
    <parent link="arm"/><child link="slider"/>
    <origin xyz="0 0 0.5" rpy="0 0.4 0"/><axis xyz="0.6 0 0.8"/>
    <limit lower="-0.3" upper="0.3" effort="1" velocity="1"/>
  </joint>
  <joint name="wrist" type="continuous">
    <parent link="slider"/><child link="tip"/>
    <origin xyz="0.1 0 0" rpy="-0.5 0 0.2"/><axis xyz="1 0 0"/>
  </joint>
  <joint name="twin_joint" type="revolute">
    <parent link="base"/><child link="twin"/>
    <origin xyz="-0.5 0 0" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
    <mimic joint="shoulder" multiplier="-0.5" offset="0.1"/>
  </joint>
  <joint name="mount" type="fixed">
    <parent link="base"/><child link="camera"/>
    <origin xyz="0 0.5 0.5" rpy="0.1 0.2 0.3"/>
  </joint>
</robot>"""


def axis_angle(axis, angle) -> np.ndarray:
    """Rodrigues' rotation matrix about ``axis`` (any length) by ``angle`` [rad]."""
    x, y, z = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * k @ k


def frame(xyz, rpy, rotation=np.eye(3), shift=(0.0, 0.0, 0.0)) -> np.ndarray:
    """4 x 4 pose of a URDF origin (``xyz``, roll-pitch-yaw ``rpy``: Rz Ry Rx) followed by
    ``rotation`` and ``shift`` in the frame it places."""
    r, p, y = rpy
    rx = axis_angle((1, 0, 0), r) if r else np.eye(3)
    ry = axis_angle((0, 1, 0), p) if p else np.eye(3)
    rz = axis_angle((0, 0, 1), y) if y else np.eye(3)
    out = np.eye(4)
    out[:3, :3] = rz @ ry @ rx @ rotation
    out[:3, 3] = np.asarray(xyz, dtype=float) + rz @ ry @ rx @ np.asarray(shift, dtype=float)
    return out


def test_a_joints_rotation_is_a_rotation_by_its_angle():
    """A continuous joint about an axis of any length and either sense turns its link by a
    rotation: orthonormal, determinant 1, the axis fixed and a vector normal to it turned by
    the angle (Rodrigues' formula)."""
    rng = np.random.default_rng(11)
    axes = [rng.normal(size=3) * (3.7 if k % 2 else 1.0) for k in range(9)]
    axes += [np.eye(3)[k % 3] * (-1.0) ** k for k in range(3)]
    joint = (
        "<link name='l{0}'/><joint name='j{0}' type='continuous'><parent link='base'/>"
        "<child link='l{0}'/><axis xyz='{1} {2} {3}'/></joint>"
    )
    body = ArticulatedBody.from_urdf(
        "<robot name='axes'><link name='base'><visual><geometry><box size='1 1 1'/></geometry>"
        "</visual></link>"
        + "".join(joint.format(k, *(repr(float(a)) for a in axis)) for k, axis in enumerate(axes))
        + "</robot>"
    )
    for _ in range(20):
        angles = rng.uniform(-7.0, 7.0, size=len(axes))
        poses = body.link_poses({f"j{k}": a for k, a in enumerate(angles)})
        for k, (axis, angle) in enumerate(zip(axes, angles)):
            r = poses[body.links.index(f"l{k}")][:3, :3]
            np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-15)
            assert np.linalg.det(r) == pytest.approx(1.0, abs=1e-14)
            unit = axis / np.linalg.norm(axis)
            np.testing.assert_allclose(r @ unit, unit, atol=1e-15)
            normal = np.cross(unit, [0.3, -0.5, 0.8])
            normal /= np.linalg.norm(normal)
            turned = r @ normal
            assert math.atan2(np.cross(normal, turned) @ unit, normal @ turned) == pytest.approx(
                math.remainder(angle, 2.0 * math.pi), abs=1e-12
            )
            np.testing.assert_allclose(r, axis_angle(axis, angle), rtol=0, atol=1e-14)


def test_the_links_poses_are_the_chains_closed_form():
    """Revolute, prismatic and continuous joints with tilted origins and axes that are not unit
    vectors, a chain three joints deep, a mimic joint and a fixed one: every link's pose is the
    product of its joints' origins and motions written out (Rodrigues' formula for the turns)."""
    body = ArticulatedBody.from_urdf(TREE_URDF)
    assert set(body.joints) == {"shoulder", "slide", "wrist"}
    rng = np.random.default_rng(7)
    for _ in range(6):
        q = {"shoulder": rng.uniform(-2, 2), "slide": rng.uniform(-0.3, 0.3)}
        q["wrist"] = rng.uniform(-7, 7)
        arm = frame((0.5, 0.1, -0.2), (0.3, -0.2, 0.9), axis_angle((0, 1, 1), q["shoulder"]))
        slide_axis = np.array([0.6, 0.0, 0.8])
        slider = arm @ frame((0, 0, 0.5), (0, 0.4, 0), shift=q["slide"] * slide_axis)
        tip = slider @ frame((0.1, 0, 0), (-0.5, 0, 0.2), axis_angle((1, 0, 0), q["wrist"]))
        twin = frame((-0.5, 0, 0), (0, 0, 0), axis_angle((0, 0, 1), -0.5 * q["shoulder"] + 0.1))
        camera = frame((0, 0.5, 0.5), (0.1, 0.2, 0.3))
        expected = {"base": np.eye(4), "arm": arm, "slider": slider, "tip": tip}
        expected |= {"twin": twin, "camera": camera}
        poses = body.link_poses(q)
        for link, pose in expected.items():
            np.testing.assert_allclose(poses[body.links.index(link)], pose, rtol=0, atol=1e-14)


def test_a_urdf_of_collision_geometry_only_has_it_as_its_body():
    link = "<link name='{2}'><{0}><geometry><box size='{1}'/></geometry></{0}></link>"
    joint = "<joint name='j' type='fixed'><parent link='a'/><child link='b'/></joint>"
    visual = ArticulatedBody.from_urdf(
        f"<robot name='x'>{link.format('visual', '1 .5 .4', 'a')}</robot>"
    )
    collision = ArticulatedBody.from_urdf(
        f"<robot name='x'>{link.format('collision', '1 .5 .4', 'a')}</robot>"
    )
    np.testing.assert_array_equal(collision.mesh().vertices, visual.mesh().vertices)
    assert collision.mesh().total_area == pytest.approx(2 * (0.5 + 0.4 + 0.2))
    assert collision.material_names == ("default",)
    # a visual anywhere: the visuals are the body, every collision passed over
    mixed = ArticulatedBody.from_urdf(
        f"<robot name='x'>{link.format('visual', '1 .5 .4', 'a')}"
        f"{link.format('collision', '3 3 3', 'b')}{joint}</robot>"
    )
    np.testing.assert_array_equal(mixed.mesh().vertices, visual.mesh().vertices)
    with pytest.raises(MeshError, match="no link has geometry"):
        ArticulatedBody.from_urdf("<robot name='x'><link name='a'/></robot>")
