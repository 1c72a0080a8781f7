"""The estimator with an articulated body: joint positions from joint states (state-like: stale,
missing and bad ones refused and counted), the wrench of the body posed at them with its
per-link loads and joint efforts, shading cached per configuration."""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from adbsat_ros.bags import io as bag_io
from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.handling import MessageHandler
from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS
from adbsat_ros.estimator.samples import Rejection
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.geometry.example_urdf import example_satellite_urdf
from adbsat_ros.messages.cdr import AttitudeFields, Stamp
from adbsat_ros.messages.decoding import decode_joint_state
from adbsat_ros.messages.encoding import encode_wrench
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.panel_method import PanelMethod

R = 6378137.0 + 300e3
V = math.sqrt(3.986004418e14 / R)
# body x along the orbital velocity (90 deg about z), then 23 deg about body y: the flow meets
# the wings at an angle, off their hinges' axis
_C, _S = math.cos(math.pi / 4), math.sin(math.pi / 4)
_c, _s = math.cos(0.2), math.sin(0.2)
TILTED = (-_S * _s, _C * _s, _S * _c, _C * _c)
HINGES = ("wing_left_hinge", "wing_right_hinge")


def estimator(**overrides) -> AeroWrenchEstimator:
    params = dict(
        PARAMETER_DEFAULTS,
        mesh="example-articulated",
        time_mode="epoch",
        center_of_mass=[0.05, 0.0, 0.01],
    )
    params.update(overrides)
    return AeroWrenchEstimator(WrenchSettings.from_parameters(params))


def ready(est, angles=(0.3, -0.5), stamp=1.0):
    est.on_state(stamp, [R, 0.0, 1e3], [0.0, V, 10.0])
    est.on_joint_state(stamp, HINGES, angles)
    return est


def test_the_wrench_is_the_panel_method_of_the_posed_body():
    """With ray-cast shading at the cell of the flow (nearest cell, no interpolation) the
    estimator's wrench equals a PanelMethod of the merged mesh at the joint positions with the
    shading of the configuration grid's point (here the positions themselves, on the grid)."""
    step = 0.25
    angles = (math.radians(20 * step), math.radians(-8 * step))  # on the joint grid
    est = ready(estimator(shading_interpolation=False), angles)
    sample = est.on_attitude(1.0, TILTED)
    positions = dict(zip(HINGES, angles))
    mesh = est.body.mesh(positions)
    cache = est.model.cache
    [(_, grid_key)] = vertices = cache.vertices(positions)
    np.testing.assert_allclose(
        list(cache.configuration(grid_key).values()), angles, rtol=0, atol=1e-15
    )
    method = PanelMethod(mesh, "sentman", reference=est.method.reference)
    u = sample.flow_direction_body
    [(_, cell)] = cache.read(u, vertices, count=False)  # (the cell's centre, shaded)
    lighting = cell.lighting
    want = method.coefficients(_flow(sample), flow_direction=u, lighting=lighting)
    q = sample.dynamic_pressure
    np.testing.assert_allclose(sample.force, want.force(q), rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(sample.torque, want.torque(q), rtol=1e-12, atol=1e-18)
    joints = sample.joints
    assert joints.names == HINGES
    np.testing.assert_array_equal(joints.positions, angles)
    # (to rounding of the largest component: a component near zero is rounding noise itself)
    for links, total in ((joints.link_forces, sample.force), (joints.link_torques, sample.torque)):
        scale = 1e-12 * np.abs(total).max()
        np.testing.assert_allclose(links.sum(axis=0), total, rtol=0, atol=scale)
    assert abs(joints.efforts[0]) > 0.0


def _flow(sample):
    return sample.conditions.free_stream()


def test_turning_a_wing_changes_the_wrench_and_its_hinge_torque():
    est = ready(estimator(), (0.0, 0.0))
    flat = est.on_attitude(1.0, TILTED)
    est.on_joint_state(1.01, HINGES, (0.8, 0.0))
    turned = est.on_attitude(1.01, TILTED)
    assert not np.allclose(flat.force, turned.force, rtol=1e-3)
    assert not np.allclose(flat.joints.link_forces[1], turned.joints.link_forces[1], rtol=1e-3)
    right = flat.joints.link_forces[2]  # the other wing: only the 10 ms later stamp differs
    np.testing.assert_allclose(
        turned.joints.link_forces[2], right, rtol=0, atol=1e-4 * abs(right).max()
    )
    assert turned.joints.positions[0] == 0.8
    # each hinge runs along its wing's span through the middle of its chord: a flat plate's
    # load acts at its centroid, so the hinge holds (almost) nothing, turned or not
    for sample in (flat, turned):
        wing_load = np.linalg.norm(sample.joints.link_forces[1]) * 0.5  # N x chord [m]
        assert wing_load > 0.0
        assert abs(sample.joints.efforts[0]) < 1e-9 * wing_load


def test_a_joint_state_repeating_the_positions_keeps_the_posed_body():
    """Positions are posed once per change: a joint state repeating them (later stamp) keeps
    the posed body, one that moves a joint poses it anew."""
    est = ready(estimator(), (0.3, -0.5))
    posed, prepare = [], est.joints.prepare
    est.joints.prepare = lambda positions: posed.append(dict(positions)) or prepare(positions)
    first = est.on_attitude(1.0, TILTED)
    est.on_joint_state(1.01, HINGES, (0.3, -0.5))
    again = est.on_attitude(1.01, TILTED)
    est.on_joint_state(1.02, HINGES, (0.3, -0.4))
    moved = est.on_attitude(1.02, TILTED)
    assert [list(p.values()) for p in posed] == [[0.3, -0.5], [0.3, -0.4]]
    assert list(again.joints.positions) == list(first.joints.positions) == [0.3, -0.5]
    assert list(moved.joints.positions) == [0.3, -0.4]


def test_no_joint_state_yet_refuses_the_attitude():
    est = estimator()
    est.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    with pytest.raises(Rejection, match="no position received yet for joint wing_left_hinge"):
        est.on_attitude(1.0, TILTED)
    est.on_joint_state(1.0, HINGES[:1], (0.1,))  # one joint only
    with pytest.raises(Rejection, match="wing_right_hinge") as info:
        est.on_attitude(1.0, TILTED)
    assert info.value.reason == "no_joint_state"
    assert est.rejections["no_joint_state"] == 2


def test_a_stale_joint_state_refuses_the_attitude():
    est = ready(estimator(joint_state_timeout=0.5))
    est.on_state(2.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    with pytest.raises(Rejection, match="joint_state_timeout 0.5 s") as info:
        est.on_attitude(2.0, TILTED)
    assert info.value.reason == "stale_joint_state"
    est.on_joint_state(1.9, HINGES, (0.1, 0.1))
    assert est.on_attitude(2.0, TILTED).joints is not None
    assert est.rejections["stale_joint_state"] == 1


@pytest.mark.parametrize(
    "left, right, stale",
    [
        (1.5, 1.5, None),  # both exactly the timeout behind: served
        (2.5, 2.5, None),  # both exactly the timeout ahead: served
        (1.4, 1.9, "wing_left_hinge"),  # the left too old
        (1.9, 1.4, "wing_right_hinge"),  # the right too old, the left fresh
        (2.0, 2.6, "wing_right_hinge"),  # the right too far ahead of the attitude
        (1.4, 2.6, "wing_left_hinge"),  # both out: the first in the body's order is named
    ],
)
def test_every_joint_position_must_lie_within_the_timeout_of_the_attitude(left, right, stale):
    est = estimator(joint_state_timeout=0.5)
    est.on_state(2.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    est.on_joint_state(left, HINGES[:1], (0.1,))
    est.on_joint_state(right, HINGES[1:], (0.1,))
    if stale is None:
        assert est.on_attitude(2.0, TILTED).joints is not None
        return
    with pytest.raises(Rejection, match=f"joint {stale}'s latest position") as info:
        est.on_attitude(2.0, TILTED)
    assert info.value.reason == "stale_joint_state"


@pytest.mark.parametrize(
    "names, positions, message",
    [
        (("antenna",), (0.0,), "joint 'antenna' is not in example-articulated"),
        (HINGES, (math.nan, 0.0), "joint wing_left_hinge: position must be finite"),
        (HINGES, (4.0, 0.0), r"joint wing_left_hinge: position 4.0 rad is outside its limits"),
        (HINGES, (0.0,), "2 names and 1 positions"),
        (HINGES + HINGES[:1], (0.0, 0.0, 0.0), "names a joint twice"),
    ],
)
def test_bad_joint_states_are_refused_whole_and_counted(names, positions, message):
    est = ready(estimator(), (0.2, 0.2))
    with pytest.raises(Rejection, match=message) as info:
        est.on_joint_state(1.0, names, positions)
    assert info.value.reason == "bad_joint_state"
    assert est.rejections["bad_joint_state"] == 1
    sample = est.on_attitude(1.0, TILTED)  # the earlier positions stand
    np.testing.assert_array_equal(sample.joints.positions, (0.2, 0.2))


def test_a_rigid_mesh_refuses_joint_states():
    est = estimator(mesh="example")
    with pytest.raises(Rejection, match="the body has no joints"):
        est.on_joint_state(1.0, HINGES, (0.0, 0.0))


def test_robot_description_text_is_the_body():
    est = ready(estimator(mesh="example", robot_description=example_satellite_urdf()))
    assert est.body.source == "robot_description"
    assert est.on_attitude(1.0, TILTED).joints.names == HINGES


def diagnostics(est) -> dict:
    return est.diagnostic_values(None, [])


def test_a_slowly_turning_array_poses_the_body_once_per_grid_step():
    """Sun tracking: 0.1 deg/s for 20 s at 20 Hz (400 messages, 2 deg) with the default grid
    of 0.25 deg: about 2 / 0.25 + 1 configurations shaded, every other message a hit."""
    est = estimator(shading_interpolation=False)
    est.on_state(0.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    for k in range(400):
        t = 0.05 * k
        if k % 20 == 0:
            est.on_state(t, [R, 0.0, 1e3], [0.0, V, 10.0])
        angle = math.radians(10.0 + 0.1 * t)
        est.on_joint_state(t, HINGES, (angle, angle))  # (both wings track the Sun)
        est.on_attitude(t, TILTED)
    values = diagnostics(est)
    assert 8 <= values["joint_configurations_shaded"] <= 10
    assert values["joint_configuration_hits"] == 400 - values["joint_configurations_shaded"]


def test_the_configurations_share_the_bound_on_the_lightings_kept():
    """shading_cache_size bounds the lightings kept over all configurations: of eight flow
    cells with a bound of 6 the two least recently used are dropped (shaded again when read
    again), the latest kept."""
    est = estimator(shading_interpolation=False, shading_cache_size=6, joint_shading_cache_size=2)
    ready(est)

    def attitude(k, stamp):
        turn = math.radians(2.0 * k)  # eight attitudes 2 deg apart about x: eight cells
        return est.on_attitude(stamp, (math.sin(turn / 2), 0.0, 0.0, math.cos(turn / 2)))

    for k in range(8):
        attitude(k, 1.0 + 0.01 * k)
    counts = diagnostics(est)
    assert (counts["shading_cache_misses"], counts["shading_cache_hits"]) == (8, 0)
    assert counts["joint_configurations_shaded"] == 1
    attitude(7, 1.1)  # kept
    assert diagnostics(est)["shading_cache_hits"] == 1
    attitude(0, 1.11)  # dropped: shaded again
    assert diagnostics(est)["shading_cache_misses"] == 9


def test_articulated_bodies_refuse_a_database_and_solar_pressure():
    with pytest.raises(ValueError, match="parameter solar_pressure"):
        estimator(solar_pressure=True)
    with pytest.raises(ValueError, match="parameter coefficients_source"):
        estimator(coefficients_source="database", database_path="x.npz")


def test_the_unshaded_wrench_needs_no_shader():
    est = ready(estimator(shading="none"))
    sample = est.on_attitude(1.0, TILTED)
    positions = dict(zip(HINGES, (0.3, -0.5)))
    mesh = est.body.mesh(positions)
    ref = Reference(moment_point=(0.05, 0.0, 0.01)).resolved(est.body.mesh())
    want = PanelMethod(mesh, "sentman", reference=ref, shading="none").coefficients(
        _flow(sample), flow_direction=sample.flow_direction_body
    )
    np.testing.assert_allclose(
        sample.force, want.force(sample.dynamic_pressure), rtol=1e-12, atol=1e-18
    )


def test_interpolated_configurations_blend_the_grid_points_around_the_joints():
    """joint_shading_interpolation: both wings at one angle between grid points read the two
    grid configurations of their simplex for every attitude."""
    est = estimator(joint_shading_interpolation=True, joint_shading_resolution_deg=2.0)
    angle = math.radians(2.0 * 5.3)
    ready(est, (angle, angle))
    for k in range(10):
        est.on_attitude(1.0 + 0.01 * k, TILTED)
    values = diagnostics(est)
    assert values["joint_configurations_shaded"] == 2
    assert values["joint_configuration_hits"] == 2 * 10 - 2
    assert {key for key, _ in est.model.cache.last_keys} == {(5, 5), (6, 6)}


def test_the_joint_torques_message_is_made_only_when_asked_for():
    """The node asks for it while joint_torques has a subscriber; the wrench is the same. The
    message carries the joints' names, positions and efforts, stamped like the attitude."""
    est = ready(estimator())
    handler = MessageHandler(est)
    outcome = handler.on_attitude(AttitudeFields(Stamp(1, 5), TILTED))
    with_torques = encode_wrench(outcome.stamp, outcome.sample, est.settings)
    without = encode_wrench(outcome.stamp, outcome.sample, est.settings, joint_torques=False)
    assert without.joint_torques is None and without.wrench == with_torques.wrench
    joints = outcome.sample.joints
    fields = decode_joint_state(with_torques.joint_torques, bag_io.deserialize_joint_state)
    assert fields.stamp == Stamp(1, 5) and fields.names == joints.names
    assert fields.positions == tuple(joints.positions.tolist())
    efforts = bag_io.deserialize_joint_state(with_torques.joint_torques).effort
    assert efforts.tolist() == joints.efforts.tolist() and np.any(efforts != 0.0)


def test_a_joint_sample_pickles_with_its_link_loads():
    # The links' loads are computed when first read, from the sample's own numbers (not from
    # the method's caches): a joint sample pickled before they are read gives them afterwards,
    # equal to the original's.
    est = ready(estimator())
    joints = est.on_attitude(1.0, TILTED).joints
    copy = pickle.loads(pickle.dumps(joints))
    np.testing.assert_array_equal(copy.link_forces, joints.link_forces)
    np.testing.assert_array_equal(copy.link_torques, joints.link_torques)
    np.testing.assert_array_equal(copy.efforts, joints.efforts)
    assert np.abs(copy.link_forces).max() > 0.0


@pytest.mark.parametrize(
    "change",
    [
        {"joint_shading_resolution_deg": 2.0},
        {"joint_shading_interpolation": True},
        {"shading": "none"},
        {"gsi_model": "cll"},
    ],
    ids=["grid", "blend", "no-shading", "model"],
)
def test_new_settings_apply_to_the_joint_positions_already_received(change):
    # The joint positions are made ready when they arrive; settings changed after that must
    # still give the wrench a fresh estimator with the new settings gives at those positions.
    est = ready(estimator())
    est.on_attitude(1.0, TILTED)
    params = dict(PARAMETER_DEFAULTS, mesh="example-articulated", time_mode="epoch")
    params.update(center_of_mass=[0.05, 0.0, 0.01], **change)
    est.apply_settings(WrenchSettings.from_parameters(params))
    got = est.on_attitude(1.01, TILTED)
    want = ready(estimator(**change)).on_attitude(1.01, TILTED)
    np.testing.assert_array_equal(got.force, want.force)
    np.testing.assert_array_equal(got.torque, want.torque)
    np.testing.assert_array_equal(got.joints.efforts, want.joints.efforts)


@pytest.mark.parametrize("shading", ["raycast", "none"])
def test_a_body_without_moving_joints_needs_no_joint_state(shading):
    # Both hinges fixed: the URDF's body has no moving joint, so no joint state can come; its
    # wrench is the one of the same panels as a plain mesh, before and after a reset.
    text = example_satellite_urdf().replace('type="revolute"', 'type="fixed"')
    est = estimator(mesh="example", robot_description=text, shading=shading)
    assert est.body is not None and not est.body.joints
    rigid = AeroWrenchEstimator(
        WrenchSettings.from_parameters(
            dict(
                PARAMETER_DEFAULTS,
                mesh="example",
                time_mode="epoch",
                shading=shading,
                center_of_mass=[0.05, 0.0, 0.01],
            )
        ),
        est.body.mesh(),
    )
    for e in (est, rigid):
        e.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    got, want = est.on_attitude(1.0, TILTED), rigid.on_attitude(1.0, TILTED)
    assert got.joints.names == ()
    for a, b in ((got.force, want.force), (got.torque, want.torque)):  # (to rounding of the
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * np.abs(b).max())  # largest)
    est.reset()
    est.on_state(2.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    assert np.isfinite(est.on_attitude(2.0, TILTED).force).all()
