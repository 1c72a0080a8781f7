"""The ROS 2 node with real rclpy (no mocks): physics of the published wrench, bad inputs,
parameters, queued messages.

Every test runs the node and a peer node in one process on a fresh rclpy context, on the test run's
own ROS_DOMAIN_ID with discovery limited to localhost (conftest.py); one test runs the node as a
separate process from the command line with the bundled parameters file.
"""

import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

import datetime as dt
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import rclpy
import trimesh
from closed_forms import sentman_sphere_cd
from edges import NUMBER_PARAMETERS, as_parameter, parameter_edges
from geometry_msgs.msg import QuaternionStamped
from rclpy.parameter import Parameter
from rclpy.parameter_client import AsyncParameterClient
from rclpy.serialization import serialize_message
from ros_harness import (
    HANG_TIMEOUT,
    Peer,
    circular_orbit_state,
    make_context,
    node_and_peer,
    stamp_to_float,
    to_stamp,
)

from adbsat_ros.environment.atmosphere import SpaceWeather
from adbsat_ros.environment.flight_conditions import flight_conditions
from adbsat_ros.estimator.parameters import (
    EXECUTORS,
    PARAMETER_DEFAULTS,
    READ_ONLY_PARAMETERS,
    parameter_range_text,
)
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.ros.node import AdbsatNode

RADIUS = 0.5
EPOCH = "2026-03-20T12:00:00"
ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def sphere_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("mesh") / "sphere.stl"
    trimesh.creation.icosphere(subdivisions=4, radius=RADIUS).export(path)
    return str(path)


@pytest.fixture(params=EXECUTORS)
def ros(sphere_file, request):
    """A context, an executor of each kind the node offers, the node (sphere, epoch time, no
    shading) and a peer."""
    overrides = [
        Parameter("mesh", value=sphere_file),
        Parameter("shading", value="none"),
        Parameter("time_mode", value="epoch"),
        Parameter("epoch_utc", value=EPOCH),
        Parameter("center_of_mass", value=[0.1, -0.2, 0.3]),
        Parameter("diagnostics_period", value=0.2),
    ]
    with node_and_peer(overrides, request.param) as running:
        yield running


def state_accepted(node) -> bool:
    """Whether the node has an orbital state (its /diagnostics status says so)."""
    return not node.diagnostic_fields().message.endswith("no orbital state")


def diagnostic_value(node, key: str) -> str:
    return dict(node.diagnostic_fields().values)[key]


def angle_deg(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return math.degrees(math.acos(np.clip(a @ b / np.linalg.norm(a) / np.linalg.norm(b), -1, 1)))


def vec(v):
    return np.array([v.x, v.y, v.z])


def test_circular_orbit_wrench_is_drag_of_a_sphere(ros):
    node, peer = ros
    pos, vel = circular_orbit_state(300e3)
    peer.send_state(0.0, pos, vel)
    peer.spin_for(0.05)
    stamps = [0.01 * k for k in range(1, 11)]
    for t in stamps:
        peer.send_attitude(t, (0.0, 0.0, 0.0, 1.0))  # body axes = ECI axes
    assert peer.spin_until(lambda: len(peer.wrenches) == 10), f"got {len(peer.wrenches)} wrenches"
    w = peer.wrenches[-1]
    assert w.header.frame_id == "base_link"
    assert [stamp_to_float(m.header.stamp) for m in peer.wrenches] == pytest.approx(
        stamps, abs=1e-9
    )
    force, torque = vec(w.wrench.force), vec(w.wrench.torque)

    # Independent flight conditions at the last stamp (state propagated 0.1 s at constant velocity)
    t = stamps[-1]
    utc = dt.datetime.fromisoformat(EPOCH).replace(tzinfo=dt.timezone.utc) + dt.timedelta(seconds=t)
    cond = flight_conditions(
        utc,
        np.add(pos, np.multiply(vel, t)),
        vel,
        SpaceWeather(150, 150, 4),
        frame="eci",
        accommodation_model="fixed",
        accommodation_options={"alpha": 1.0},
    )
    # relative wind: satellite velocity minus the co-rotating air, omega x r (omega ~ z in ECI)
    omega = np.array([0.0, 0.0, 7.292115e-5])
    v_rel = np.asarray(vel) - np.cross(omega, np.add(pos, np.multiply(vel, t)))
    assert angle_deg(force, -v_rel) < 0.5
    assert np.linalg.norm(v_rel) == pytest.approx(cond.speed, rel=1e-3)
    flow = cond.free_stream()
    cd = sentman_sphere_cd(flow.speed_ratio, 300.0 / flow.temperature)  # alpha = 1: T_r = T_w
    expected = 0.5 * cond.mass_density * cond.speed**2 * cd * math.pi * RADIUS**2
    assert np.linalg.norm(force) == pytest.approx(expected, rel=5e-3)
    # torque about the offset centre of mass c of a sphere centred on the origin: (0 - c) x F
    c = np.array([0.1, -0.2, 0.3])
    assert np.allclose(torque, np.cross(-c, force), rtol=1e-6, atol=1e-12 * np.linalg.norm(force))
    # coefficients topic: wrench = q Aref Cf, q Aref Lref Cm
    cf = peer.coefficients[-1]
    area = node.get_parameter("reference_area").value
    length = node.get_parameter("reference_length").value
    q = 0.5 * cond.mass_density * cond.speed**2
    assert np.allclose(q * area * vec(cf.wrench.force), force, rtol=1e-3)
    assert np.allclose(q * area * length * vec(cf.wrench.torque), torque, rtol=1e-3)


def test_a_fixed_rate_stream_gets_its_flight_conditions_prepared_and_the_same_wrenches(ros):
    """After each wrench the node readies what the next regular stamp needs (the knots of its flight
    conditions); the wrenches equal those of an estimator fed the same messages without that."""
    from adbsat_ros.estimator.estimator import AeroWrenchEstimator

    node, peer = ros
    pos, vel = circular_orbit_state(300e3)
    peer.send_state(0.0, pos, vel)
    peer.spin_for(0.05)
    stamps = [0.01 * k for k in range(1, 8)] + [0.0825, 0.09]  # regular, then two irregular steps
    for k, t in enumerate(stamps):  # one at a time: each prepared after the one before
        peer.send_attitude(t, (0.0, 0.0, 0.0, 1.0))
        assert peer.spin_until(lambda: len(peer.wrenches) == k + 1)
    # the 3rd..7th stamps were predicted from the two before; 0.0825 and 0.09 were not
    assert diagnostic_value(node, "conditions_prepared_used") == "5"
    reference = AeroWrenchEstimator(node.estimator.settings, node.estimator.mesh)
    reference.on_state(0.0, pos, vel)
    for msg in peer.wrenches:
        sample = reference.on_attitude(stamp_to_float(msg.header.stamp), (0.0, 0.0, 0.0, 1.0))
        assert vec(msg.wrench.force).tolist() == sample.force.tolist()
        assert vec(msg.wrench.torque).tolist() == sample.torque.tolist()
    assert reference.diagnostic_values(None, [])["conditions_prepared_used"] == 0


@pytest.mark.parametrize("executor", EXECUTORS)
def test_attitudes_and_a_state_that_queue_up_are_served_in_order_with_their_own_wrenches(executor):
    """Attitudes (and a state between them) that wait in the queue while the node is busy are
    served by the executor one callback each: every wrench arrives, in order, bit for bit the one
    an estimator fed the same messages one at a time gives; a NaN among them is rejected and
    counted; the state applies from the attitudes after it."""
    from adbsat_ros.estimator.estimator import AeroWrenchEstimator

    ctx, spinner = make_context(executor)
    node = AdbsatNode(
        context=ctx,
        parameter_overrides=[  # the bundled satellite, raycast shading
            Parameter("time_mode", value="epoch"),
            Parameter("epoch_utc", value=EPOCH),
            Parameter("qos_depth", value=50),
            Parameter("center_of_mass", value=[0.1, -0.02, 0.03]),
        ],
    )
    spinner.add_node(node)
    peer = Peer(ctx, spinner)
    try:
        assert peer.wait_for_subscribers()
        pos, vel = (np.asarray(v, dtype=float) for v in circular_orbit_state(300e3))
        later_vel = vel + np.array([0.0, 0.0, 25.0])  # a second state with some cross-track wind
        peer.send_state(0.0, pos, vel)
        assert peer.spin_until(lambda: state_accepted(node))

        def attitude(k):  # tilting by 1 deg per message about y, a little about z
            a, b = math.radians(1.0 * k), math.radians(0.3 * k)
            q = np.array([0.0, math.sin(a / 2), math.sin(b / 2), math.cos(a / 2) * math.cos(b / 2)])
            return (math.nan, 0.0, 0.0, 1.0) if k == 4 else tuple(q / np.linalg.norm(q))

        # nobody spins while these are sent: they queue in the node's subscriptions
        for k in range(1, 8):
            peer.send_attitude(0.001 * k, attitude(k))
        time.sleep(0.05)
        peer.send_state(0.0065, pos + 0.0065 * vel, later_vel)
        time.sleep(0.05)
        for k in range(8, 15):
            peer.send_attitude(0.001 * k, attitude(k))
        time.sleep(0.3)
        assert peer.spin_until(lambda: len(peer.wrenches) == 13)
        peer.spin_for(0.1)
        assert len(peer.wrenches) == 13  # 14 attitudes, the NaN one rejected
        assert node.estimator.rejections["non_finite"] == 1

        # the events executor serves in arrival order; the single-threaded one takes a waiting
        # state before a waiting attitude (the order of the subscriptions), so here before all
        state_before = 1 if executor == "single_threaded" else 8
        reference = AeroWrenchEstimator(node.estimator.settings, node.estimator.mesh)
        reference.on_state(0.0, pos, vel)
        expected = []
        for k in range(1, 15):
            if k == state_before:
                reference.on_state(0.0065, pos + 0.0065 * vel, later_vel)
            if k != 4:
                t = stamp_to_float(to_stamp(0.001 * k))  # the stamp as the message carries it
                expected.append((t, reference.on_attitude(t, attitude(k))))
        for msg, (t, sample) in zip(peer.wrenches, expected):
            assert stamp_to_float(msg.header.stamp) == t
            assert vec(msg.wrench.force).tolist() == sample.force.tolist()
            assert vec(msg.wrench.torque).tolist() == sample.torque.tolist()
        forces = [tuple(vec(m.wrench.force)) for m in peer.wrenches]
        assert len(set(forces)) == 13  # every attitude had a wrench of its own
    finally:
        spinner.shutdown()
        peer.node.destroy_node()
        node.destroy_node()
        rclpy.try_shutdown(context=ctx)


@pytest.mark.parametrize("executor", EXECUTORS)
def test_a_burst_published_while_the_node_is_blocked_gets_every_wrench_in_order(executor):
    """40 attitudes published while nothing spins (the node blocked) wait in its subscription;
    once the executor spins, each gets its wrench, in order, equal to what an estimator fed the
    same messages one at a time gives."""
    from adbsat_ros.estimator.estimator import AeroWrenchEstimator

    n = 40
    ctx, spinner = make_context(executor)
    node = AdbsatNode(
        context=ctx,
        parameter_overrides=[  # the bundled satellite, raycast shading
            Parameter("time_mode", value="epoch"),
            Parameter("epoch_utc", value=EPOCH),
            Parameter("qos_depth", value=50),
        ],
    )
    spinner.add_node(node)
    peer = Peer(ctx, spinner)
    try:
        assert peer.wait_for_subscribers()
        pos, vel = circular_orbit_state(300e3)
        peer.send_state(0.0, pos, vel)
        assert peer.spin_until(lambda: state_accepted(node))

        def attitude(k):  # 2 deg per message about a tilted axis: a new shading cell each
            a = math.radians(2.0 * k)
            axis = np.array([0.2, 1.0, 0.3]) / np.linalg.norm([0.2, 1.0, 0.3])
            return (*(math.sin(a / 2) * axis), math.cos(a / 2))

        stamps = [stamp_to_float(to_stamp(0.001 * k)) for k in range(1, n + 1)]
        for k, t in enumerate(stamps, start=1):
            peer.send_attitude(t, attitude(k))
        time.sleep(0.3)  # all delivered to the node's subscription before anything spins
        assert peer.spin_until(lambda: len(peer.wrenches) == n)
        peer.spin_for(0.1)
        assert len(peer.wrenches) == n and node.estimator.published == n
        reference = AeroWrenchEstimator(node.estimator.settings, node.estimator.mesh)
        reference.on_state(0.0, pos, vel)
        for k, (msg, t) in enumerate(zip(peer.wrenches, stamps), start=1):
            sample = reference.on_attitude(t, attitude(k))
            assert stamp_to_float(msg.header.stamp) == t
            assert vec(msg.wrench.force).tolist() == sample.force.tolist()
            assert vec(msg.wrench.torque).tolist() == sample.torque.tolist()
        assert len({tuple(vec(m.wrench.force)) for m in peer.wrenches}) == n
    finally:
        spinner.shutdown()
        peer.node.destroy_node()
        node.destroy_node()
        rclpy.try_shutdown(context=ctx)


@pytest.mark.parametrize("executor", EXECUTORS)
def test_a_stream_sent_while_the_node_computes_loses_no_attitude_and_keeps_the_order(executor):
    """Attitudes sent back to back from a thread while the node spins (so that they queue up while
    it computes): each gets exactly one wrench, in order, however long the node takes for them."""
    import threading

    ctx, spinner = make_context(executor)
    node = AdbsatNode(
        context=ctx,
        parameter_overrides=[
            Parameter("time_mode", value="epoch"),
            Parameter("epoch_utc", value=EPOCH),
            Parameter("qos_depth", value=1000),
        ],
    )
    spinner.add_node(node)
    n = 400
    # (the wrenches may queue up too, behind the attitudes still waiting: room for all of them)
    peer = Peer(ctx, spinner, depth=n)
    try:
        assert peer.wait_for_subscribers()
        pos, vel = circular_orbit_state(300e3)
        peer.send_state(0.0, pos, vel)
        assert peer.spin_until(lambda: state_accepted(node))

        def send():
            for k in range(1, n + 1):
                peer.send_attitude(0.001 * k, (0.0, math.sin(0.001 * k), 0.0, math.cos(0.001 * k)))
                time.sleep(0.0002)

        sender = threading.Thread(target=send)
        sender.start()
        assert peer.spin_until(lambda: len(peer.wrenches) >= n)
        sender.join()
        peer.spin_for(0.2)
        stamps = [round(stamp_to_float(m.header.stamp) * 1000) for m in peer.wrenches]
        assert stamps == list(range(1, n + 1))
        assert node.estimator.published == n and sum(node.estimator.rejections.values()) == 0
    finally:
        spinner.shutdown()
        peer.node.destroy_node()
        node.destroy_node()
        rclpy.try_shutdown(context=ctx)


def test_attitude_rotates_the_force_into_the_body_frame(ros):
    node, peer = ros
    pos, vel = circular_orbit_state(300e3)
    peer.send_state(0.0, pos, vel)
    peer.spin_for(0.05)
    peer.send_attitude(0.01, (0.0, 0.0, 0.0, 1.0))
    # body rotated +90 deg about z: body x = ECI y, so ECI vectors appear rotated -90 deg in body
    peer.send_attitude(0.02, (0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4)))
    assert peer.spin_until(lambda: len(peer.wrenches) == 2)
    f0, f1 = vec(peer.wrenches[0].wrench.force), vec(peer.wrenches[1].wrench.force)
    rz = np.array([[0, 1, 0], [-1, 0, 0], [0, 0, 1.0]])  # R(90 deg about z) transposed
    assert np.allclose(f1, rz @ f0, rtol=1e-3, atol=1e-3 * np.linalg.norm(f0))


def test_body_frame_twist_is_rotated_with_the_pose(ros):
    node, peer = ros
    pos, vel = circular_orbit_state(300e3)
    peer.send_state(0.0, pos, vel)
    peer.spin_for(0.05)
    peer.send_attitude(0.01, (0, 0, 0, 1.0))
    assert peer.spin_until(lambda: len(peer.wrenches) == 1)
    # the same state with the twist in the body frame of a body rotated 90 deg about z
    q = (0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4))
    v_body = np.array([[0, 1, 0], [-1, 0, 0], [0, 0, 1.0]]) @ np.asarray(vel)
    peer.send_state(0.011, pos, v_body, child="body", orientation=q)
    peer.spin_for(0.05)
    peer.send_attitude(0.012, (0, 0, 0, 1.0))
    assert peer.spin_until(lambda: len(peer.wrenches) == 2)
    f0, f1 = (vec(w.wrench.force) for w in peer.wrenches)
    assert np.allclose(f0, f1, rtol=2e-3)


def test_bad_inputs_are_rejected_counted_and_the_node_stays_up(ros):
    node, peer = ros
    est = node.estimator
    pos, vel = circular_orbit_state(300e3)
    good = (0.0, 0.0, 0.0, 1.0)

    def expect(reason, published_before, send):
        count = est.rejections[reason]
        send()
        assert peer.spin_until(lambda: est.rejections[reason] == count + 1), reason
        peer.spin_for(0.05)
        assert len(peer.wrenches) == published_before, f"{reason}: a wrench was published"

    expect("no_state", 0, lambda: peer.send_attitude(0.0, good))
    peer.send_state(1.0, pos, vel)
    peer.spin_for(0.05)
    expect("non_finite", 0, lambda: peer.send_attitude(1.01, (math.nan, 0, 0, 1)))
    expect("bad_quaternion", 0, lambda: peer.send_attitude(1.02, (0, 0, 0, 0)))
    expect("bad_quaternion", 0, lambda: peer.send_attitude(1.03, (0, 0, 0, 1.1)))
    expect("stale_state", 0, lambda: peer.send_attitude(5.0, good))
    expect("non_finite", 0, lambda: peer.send_state(1.04, (math.inf, 0, 0), vel))
    # slightly non-unit quaternion: normalised and used
    peer.send_attitude(1.05, (0, 0, 0, 1.0004))
    assert peer.spin_until(lambda: len(peer.wrenches) == 1)
    # one attitude out of order: refused alone, the state kept
    expect("out_of_order", 1, lambda: peer.send_attitude(1.0, good))
    peer.send_attitude(1.06, good)
    assert peer.spin_until(lambda: len(peer.wrenches) == 2)
    # time going back beyond time_jump_reset (a looping bag): rejected, history reset
    expect("time_backwards", 2, lambda: peer.send_attitude(0.0, good))
    expect("no_state", 2, lambda: peer.send_attitude(1.07, good))
    # a state outside the atmosphere model: refused, and the latest good state kept
    peer.send_state(1.9, pos, vel)
    far = np.asarray(pos) * (6378137.0 + 2000e3) / np.linalg.norm(pos)
    expect("altitude_out_of_range", 2, lambda: peer.send_state(2.0, far, vel))
    peer.send_attitude(2.0, good)
    assert peer.spin_until(lambda: len(peer.wrenches) == 3)
    # a twist in an unknown frame, a state in a frame of no known name
    expect("bad_state_frame", 3, lambda: peer.send_state(2.1, pos, vel, child="camera"))
    expect("bad_state_frame", 3, lambda: peer.send_state(2.2, pos, vel, frame="sim_world"))
    # an attitude given in the body frame, or in ECEF while the state is ECI
    expect("bad_attitude_frame", 3, lambda: peer.send_attitude(2.3, good, frame="base_link"))
    expect("bad_attitude_frame", 3, lambda: peer.send_attitude(2.4, good, frame="ecef"))
    # zero relative velocity (at rest in the co-rotating air): a zero wrench is published
    omega = np.array([0.0, 0.0, 7.292115e-5])
    peer.send_state(3.0, pos, np.cross(omega, pos))
    peer.spin_for(0.05)
    peer.send_attitude(3.0, good)
    assert peer.spin_until(lambda: len(peer.wrenches) == 4)
    # the near-zero residual comes from precession-nutation, far below any real drag
    assert np.linalg.norm(vec(peer.wrenches[-1].wrench.force)) < 1e-9
    # still up and computing
    peer.send_state(4.0, pos, vel)
    peer.spin_for(0.05)
    peer.send_attitude(4.0, good)
    assert peer.spin_until(lambda: len(peer.wrenches) == 5)
    assert np.linalg.norm(vec(peer.wrenches[-1].wrench.force)) > 1e-5
    # attitudes arrive as CDR bytes: bytes that are no QuaternionStamped are counted, not used
    expect("undecodable", 5, lambda: peer.attitude_pub.publish(b"\x00\x01\x00\x00" + b"\xff" * 12))
    # a valid message that the fast reader refuses (trailing bytes) is decoded by the typesupport
    msg = QuaternionStamped()
    msg.header.stamp, msg.header.frame_id, msg.quaternion.w = to_stamp(4.01), "eci", 1.0
    peer.attitude_pub.publish(bytes(serialize_message(msg)) + bytes(8))
    assert peer.spin_until(lambda: len(peer.wrenches) == 6)
    assert stamp_to_float(peer.wrenches[-1].header.stamp) == pytest.approx(4.01, abs=1e-9)
    assert np.allclose(
        vec(peer.wrenches[-1].wrench.force), vec(peer.wrenches[-2].wrench.force), rtol=1e-3
    )
    # diagnostics report the rejections, each by its name
    for key, count in (("rejected_bad_quaternion", "2"), ("rejected_bad_attitude_frame", "2")):
        assert peer.spin_until(
            lambda: any(
                any(kv.key == key and kv.value == count for kv in st.values)
                for d in peer.diagnostics
                for st in d.status
            )
        ), key


def test_parameter_changes_apply_or_are_rejected(ros):
    node, peer = ros
    pos, vel = circular_orbit_state(300e3)
    peer.send_state(0.0, pos, vel)
    peer.spin_for(0.05)
    peer.send_attitude(0.01, (0, 0, 0, 1.0))
    assert peer.spin_until(lambda: len(peer.wrenches) == 1)
    sentman = np.linalg.norm(vec(peer.wrenches[0].wrench.force))

    result = node.set_parameters([Parameter("gsi_model", value="newton")])[0]
    assert result.successful
    peer.send_attitude(0.02, (0, 0, 0, 1.0))
    assert peer.spin_until(lambda: len(peer.wrenches) == 2)
    newton = np.linalg.norm(vec(peer.wrenches[1].wrench.force))
    # Newtonian sphere: C_D = 2 on the projected area, Sentman at s ~ 8 with T_w = 300 K ~ 2.1
    assert newton < sentman and newton != pytest.approx(sentman, rel=1e-3)

    for name, value, needle in [
        ("alpha", 2.0, "alpha"),
        ("gsi_model", "magic", "gsi_model"),
        ("center_of_mass", [1.0, 2.0], "center_of_mass"),
        ("material_overrides", ["nonexistent:alpha=0.5"], "nonexistent"),
        ("mesh", "example", "mesh"),
        ("f107", 5000.0, "f107 must be in [50, 500] sfu"),
        ("ap", 1e4, "ap must be in [0, 400]"),
        ("wall_temperature", 1e300, "wall_temperature must be in [1, 3000] K"),
        ("center_of_mass", [1e300, 0.0, 0.0], "center_of_mass[x] must be in [-1000, 1000] m"),
        ("time_jump_reset", 0.0, "time_jump_reset"),
        ("eci_frame_ids", ["eci", "itrf"], "names both frames"),
    ]:
        result = node.set_parameters([Parameter(name, value=value)])[0]
        assert not result.successful and needle in result.reason, (name, result.reason)
    assert node.get_parameter("gsi_model").value == "newton"
    assert node.get_parameter("alpha").value == 1.0
    assert node.get_parameter("f107").value == 150.0 and node.estimator.settings.f107 == 150.0
    peer.send_attitude(0.03, (0, 0, 0, 1.0))
    assert peer.spin_until(lambda: len(peer.wrenches) == 3)
    assert np.linalg.norm(vec(peer.wrenches[2].wrench.force)) == pytest.approx(newton, rel=1e-4)


def test_bad_mesh_stops_the_node_with_one_line_and_status_1(tmp_path):
    env = dict(os.environ)
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "adbsat_ros.ros.node",
            "--ros-args",
            "-p",
            f"mesh:={tmp_path / 'none.obj'}",
        ],
        capture_output=True,
        text=True,
        timeout=60,
        env=env,
    )
    assert proc.returncode == 1
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "not found" in lines[0], proc.stderr


def first_wrench_of_node_process(cmd) -> None:
    """Start adbsat_node with ``cmd``, stream states and attitudes to it over DDS until a
    wrench comes back (asserting it does, and is not zero), then stop it."""
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    ctx, executor = make_context()
    peer = Peer(ctx, executor, name="remote_peer")
    try:
        assert peer.wait_for_subscribers(), "node process did not come up"
        pos, vel = circular_orbit_state(300e3)
        deadline = time.monotonic() + HANG_TIMEOUT
        t = 0.0
        while not peer.wrenches and time.monotonic() < deadline:
            t += 0.01
            peer.send_state(t, pos, vel)
            peer.send_attitude(t, (0, 0, 0, 1.0))
            peer.spin_for(0.05)
        assert peer.wrenches, "no wrench from the node process"
        assert np.linalg.norm(vec(peer.wrenches[0].wrench.force)) > 1e-5
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=HANG_TIMEOUT)
        except subprocess.TimeoutExpired:
            proc.kill()
        executor.shutdown()
        peer.node.destroy_node()
        rclpy.try_shutdown(context=ctx)


def test_node_process_with_the_bundled_params_file(sphere_file):
    """adbsat_node run as its own process with config/adbsat.yaml answers over DDS."""
    cmd = [
        sys.executable,
        "-m",
        "adbsat_ros.ros.node",
        "--ros-args",
        "--params-file",
        str(ROOT / "config" / "adbsat.yaml"),
        "-p",
        f"mesh:={sphere_file}",
        "-p",
        "time_mode:=epoch",
        "-p",
        f"epoch_utc:={EPOCH}",
    ]
    first_wrench_of_node_process(cmd)


def test_a_bad_params_file_stops_the_node_with_one_line(tmp_path):
    """A params file with a misspelt name, a value of the wrong type, or none at all: the node
    process stops at start-up with status 1 and one line naming the file and the parameter."""
    typo = tmp_path / "typo.yaml"
    typo.write_text("adbsat_node:\n  ros__parameters:\n    shadnig: none\n", encoding="utf-8")
    wrong = tmp_path / "wrong.yaml"
    wrong.write_text("adbsat_node:\n  ros__parameters:\n    f107: high\n", encoding="utf-8")
    for path, text in (
        (typo, "parameter shadnig: unknown (did you mean shading?)"),
        (wrong, "parameter f107: f107 must be a number"),
        (tmp_path / "missing.yaml", "no such parameters file"),
    ):
        cmd = [
            sys.executable,
            "-m",
            "adbsat_ros.ros.node",
            "--ros-args",
            "--params-file",
            str(path),
        ]
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
        assert done.returncode == 1
        assert done.stderr.startswith(f"adbsat_node: error: {path}: {text}")
        assert done.stderr.count("\n") == 1 and done.stderr.endswith("\n")


def test_a_params_file_may_give_numbers_as_integers(tmp_path, sphere_file):
    """``f107: 150`` and ``center_of_mass: [0, 0, 0]`` in YAML are integers to rclpy: the node
    takes them for its number parameters and answers."""
    path = tmp_path / "ints.yaml"
    path.write_text(
        "adbsat_node:\n  ros__parameters:\n    f107: 150\n    center_of_mass: [0, 0, 0]\n"
        f"    mesh: {sphere_file}\n    time_mode: epoch\n",
        encoding="utf-8",
    )
    cmd = [sys.executable, "-m", "adbsat_ros.ros.node", "--ros-args", "--params-file", str(path)]
    first_wrench_of_node_process(cmd)


def test_params_file_lists_every_parameter_with_its_default():
    from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS, load_parameters_file
    from adbsat_ros.estimator.settings import WrenchSettings

    params = load_parameters_file(ROOT / "config" / "adbsat.yaml")
    assert set(params) == set(PARAMETER_DEFAULTS)
    assert params == PARAMETER_DEFAULTS
    WrenchSettings.from_parameters(params)  # valid as shipped


def test_attitude_can_come_from_the_odometry_pose(ros):
    node, peer = ros
    assert node.set_parameters([Parameter("attitude_source", value="odometry")])[0].successful
    pos, vel = circular_orbit_state(300e3)
    q = (0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4))
    peer.send_state(0.5, pos, vel, orientation=q)
    assert peer.spin_until(lambda: len(peer.wrenches) == 1)
    assert stamp_to_float(peer.wrenches[0].header.stamp) == pytest.approx(0.5)
    # attitude messages are ignored in this mode
    peer.send_attitude(0.6, (0, 0, 0, 1.0))
    peer.spin_for(0.2)
    assert len(peer.wrenches) == 1
    # the body is turned 90 deg about z (body x = ECI y): the force, along -v_rel ~ -y ECI,
    # is along -x in the body frame
    f = vec(peer.wrenches[0].wrench.force)
    assert angle_deg(f, [-1.0, 0.0, 0.0]) < 0.5


def test_log_throttle_logs_each_key_once_per_period():
    """One line per key and period, whatever the call rate; keys are independent."""
    from adbsat_ros.ros.log_throttle import LogThrottle

    class Lines:
        def __init__(self):
            self.lines = []

        def warning(self, text):
            self.lines.append(("warning", text))

        def error(self, text):
            self.lines.append(("error", text))

    now = [100.0]
    lines = Lines()
    throttle = LogThrottle(lines, period=5.0, clock=lambda: now[0])
    logged = [throttle("warning", "non_finite", f"nan {k}") for k in range(1000)]
    assert logged[0] and not any(logged[1:])
    assert throttle("error", "stale_state", "stale")  # another key is not held back
    now[0] += 4.999
    assert not throttle("warning", "non_finite", "nan again")
    now[0] += 0.002
    assert throttle("warning", "non_finite", "nan later")
    assert lines.lines == [("warning", "nan 0"), ("error", "stale"), ("warning", "nan later")]


def test_a_burst_of_bad_input_is_counted_and_logged_once_per_reason(ros):
    """500 rejected attitudes of two kinds: every one counted, one /rosout line per reason, and the
    next good attitude still answered."""
    from rcl_interfaces.msg import Log

    node, peer = ros
    est = node.estimator
    logs = []
    peer.node.create_subscription(Log, "/rosout", logs.append, 1000)
    pos, vel = circular_orbit_state(300e3)
    peer.send_state(1.0, pos, vel)
    peer.spin_for(0.05)
    before = dict(est.rejections)

    def rejected_since(reason):
        return est.rejections[reason] - before.get(reason, 0)

    for batch in range(50):  # in batches within the node's KEEP_LAST 10 history
        for k in range(5):
            t = 1.0 + 1e-4 * (5 * batch + k)
            peer.send_attitude(t, (math.nan, 0, 0, 1))
            peer.send_attitude(t, (0, 0, 0, 0))
        n = 5 * (batch + 1)
        assert peer.spin_until(
            lambda: rejected_since("non_finite") == n and rejected_since("bad_quaternion") == n
        ), dict(est.rejections)
    peer.send_attitude(1.1, (0, 0, 0, 1))
    assert peer.spin_until(lambda: len(peer.wrenches) == 1)
    peer.spin_for(0.2)
    rejected = [
        m.msg for m in logs if m.name == node.get_name() and m.msg.startswith("input rejected")
    ]
    assert sum(m.startswith("input rejected (non_finite)") for m in rejected) == 1, rejected
    assert sum(m.startswith("input rejected (bad_quaternion)") for m in rejected) == 1, rejected
    assert len(rejected) == 2, rejected


def test_state_bytes_that_are_no_odometry_are_counted_and_a_padded_one_is_decoded(ros):
    """States come in as CDR bytes too: garbage is counted as undecodable and gives no state; a
    valid Odometry the fast reader refuses (trailing bytes) goes through rclpy's typesupport and
    gives the wrench of the same state sent plainly."""
    from nav_msgs.msg import Odometry

    node, peer = ros
    est = node.estimator
    before = dict(est.rejections)
    peer.state_pub.publish(b"\x00\x01\x00\x00" + b"\xff" * 40)
    assert peer.spin_until(
        lambda: est.rejections["undecodable"] == before.get("undecodable", 0) + 1
    )
    peer.send_attitude(1.0, (0.0, 0.0, 0.0, 1.0))
    assert peer.spin_until(lambda: est.rejections["no_state"] == before.get("no_state", 0) + 1)
    pos, vel = circular_orbit_state(300e3)
    msg = Odometry()
    msg.header.stamp, msg.header.frame_id, msg.child_frame_id = to_stamp(2.0), "eci", "eci"
    msg.pose.pose.position.x, msg.pose.pose.position.y, msg.pose.pose.position.z = pos
    msg.twist.twist.linear.x, msg.twist.twist.linear.y, msg.twist.twist.linear.z = vel
    peer.state_pub.publish(bytes(serialize_message(msg)) + bytes(8))
    peer.spin_for(0.05)
    peer.send_attitude(2.0, (0.0, 0.0, 0.0, 1.0))
    assert peer.spin_until(lambda: len(peer.wrenches) == 1)
    peer.send_state(3.0, pos, vel)  # the same state, plainly, one second later (same place)
    peer.spin_for(0.05)
    peer.send_attitude(3.0, (0.0, 0.0, 0.0, 1.0))
    assert peer.spin_until(lambda: len(peer.wrenches) == 2)
    first, second = (vec(w.wrench.force) for w in peer.wrenches)
    assert np.linalg.norm(first) > 1e-5
    assert np.allclose(
        first, second, rtol=1e-3
    )  # 1 s apart: the atmosphere and Earth turn a little


def test_coefficients_follow_their_subscribers_as_they_come_and_go(ros):
    """The coefficients topic is published while it has a subscriber: the node counts them from
    the middleware's matched events (not per message), so a reader that leaves stops it and one
    that comes starts it again."""
    from geometry_msgs.msg import WrenchStamped
    from rclpy.qos import QoSProfile

    node, peer = ros
    pos, vel = circular_orbit_state(300e3)
    peer.send_state(0.0, pos, vel)
    assert peer.spin_until(lambda: state_accepted(node))
    assert peer.spin_until(lambda: node.coefficient_readers == 1)
    extra = peer.node.create_subscription(
        WrenchStamped, "coefficients", lambda msg: None, QoSProfile(depth=10)
    )
    assert peer.spin_until(lambda: node.coefficient_readers == 2)
    peer.node.destroy_subscription(extra)
    peer.node.destroy_subscription(
        next(s for s in peer.node.subscriptions if s.topic_name == "/coefficients")
    )
    assert peer.spin_until(lambda: node.coefficient_readers == 0)
    before = len(peer.coefficients)
    for k in range(5):
        peer.send_attitude(0.01 * k, (0.0, 0.0, 0.0, 1.0))
    assert peer.spin_until(lambda: node.estimator.published >= 5)
    peer.spin_for(0.2)
    assert len(peer.coefficients) == before  # nobody listening: nothing sent
    peer.node.create_subscription(
        WrenchStamped, "coefficients", peer.coefficients.append, QoSProfile(depth=100)
    )
    assert peer.spin_until(lambda: node.coefficient_readers == 1)
    peer.send_attitude(0.06, (0.0, 0.0, 0.0, 1.0))
    assert peer.spin_until(lambda: len(peer.coefficients) > before)


def test_attitudes_missing_from_the_stream_are_counted_in_the_diagnostics(ros):
    """A 100 Hz attitude stream with three messages never sent: /diagnostics says three are
    missing; the middleware reported none lost."""
    node, peer = ros
    pos, vel = circular_orbit_state(300e3)
    peer.send_state(1.0, pos, vel)
    peer.spin_for(0.05)
    sent = [k for k in range(20) if k not in (7, 8, 9)]
    for count, k in enumerate(sent, start=1):  # each answered before the next: none overwritten
        peer.send_attitude(1.0 + 0.01 * k, (0, 0, 0, 1.0))
        assert peer.spin_until(lambda: len(peer.wrenches) == count)
    values = dict(node.diagnostic_fields().values)
    assert values["attitudes_missing"] == "3" and values["messages_lost"] == "0"


def test_the_knudsen_number_is_reported_and_warned_about(ros):
    """/diagnostics reports Kn of the latest wrench (mean free path over the reference length);
    below knudsen_warning the status is WARN and says why."""
    node, peer = ros
    pos, vel = circular_orbit_state(300e3)
    peer.send_state(1.0, pos, vel)
    peer.spin_for(0.05)
    peer.send_attitude(1.0, (0, 0, 0, 1.0))
    assert peer.spin_until(lambda: len(peer.wrenches) == 1)
    fields = node.diagnostic_fields()
    kn = float(dict(fields.values)["knudsen_number"])
    assert kn > 1e3 and fields.level == 0  # 300 km: free-molecular by far
    assert node.set_parameters([Parameter("knudsen_warning", value=10 * kn)])[0].successful
    fields = node.diagnostic_fields()
    assert fields.level == 1 and "flow not free-molecular" in fields.message


def test_every_number_parameter_takes_its_edges_at_run_time_and_refuses_beyond(ros):
    """Through the node's parameter service (what ``ros2 param set`` calls): every run-time
    number parameter takes the edges of its range and refuses just beyond with the range in the
    reason, its old value kept; ``ros2 param describe`` shows the range."""
    node, peer = ros
    client = AsyncParameterClient(peer.node, node.get_name())
    assert client.wait_for_services(timeout_sec=HANG_TIMEOUT)

    def call(future):
        assert peer.spin_until(future.done)
        return future.result()

    names = [n for n in NUMBER_PARAMETERS if n not in READ_ONLY_PARAMETERS]
    # the centre of mass must also lie near the body (the example's box, z in [-10.5, 10.5] m,
    # within its parameter range): its parameter edges are refused by that rule, by name
    names.remove("center_of_mass")
    for x in parameter_edges("center_of_mass")[0][:2]:
        result = call(client.set_parameters([Parameter("center_of_mass", value=[0.0, 0.0, x])]))
        assert not result.results[0].successful
        assert "center_of_mass z must be in [-10.5, 10.5] m" in result.results[0].reason
    for x in (-10.5, 10.5, 0.0):
        result = call(client.set_parameters([Parameter("center_of_mass", value=[0.0, 0.0, x])]))
        assert result.results[0].successful, result.results[0].reason
    described = call(client.describe_parameters(names)).descriptors
    for name, descriptor in zip(names, described):
        assert descriptor.additional_constraints == parameter_range_text(name) != ""
    for name in names:
        inside, outside = parameter_edges(name)
        for x in inside:
            value = as_parameter(name, x)
            result = call(client.set_parameters([Parameter(name, value=value)])).results[0]
            assert result.successful, (name, x, result.reason)
            assert node.get_parameter(name).value == pytest.approx(value, abs=0.0)
        kept = node.get_parameter(name).value
        for x in outside:
            result = call(client.set_parameters([Parameter(name, value=as_parameter(name, x))]))
            reason = result.results[0].reason
            assert not result.results[0].successful, (name, x)
            # (an integer parameter given a fraction, NaN or infinity: refused by its type)
            assert "must be in" in reason or "expected 'Type.INTEGER'" in reason, reason
            assert node.get_parameter(name).value == pytest.approx(kept, abs=0.0)
        # back to its default, so that the next parameter's edges apply alone
        default = Parameter(name, value=PARAMETER_DEFAULTS[name])
        assert call(client.set_parameters([default])).results[0].successful
    values = {name: node.get_parameter(name).value for name in PARAMETER_DEFAULTS}
    assert node.estimator.settings == WrenchSettings.from_parameters(values)


def test_help_prints_the_topics_and_parameters_and_exits():
    """adbsat_node --help prints every topic and every parameter with its default and range,
    and exits 0 without starting a node."""
    from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS, parameter_range_text

    proc = subprocess.run(
        [sys.executable, "-m", "adbsat_ros.ros.node", "--help"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr
    for topic in ("attitude", "state", "wrench", "coefficients", "/diagnostics"):
        assert f"  {topic} " in proc.stdout
    for name, default in PARAMETER_DEFAULTS.items():
        assert f"  {name} = {default!r}" in proc.stdout
        if parameter_range_text(name):
            assert f"valid: {parameter_range_text(name)}" in proc.stdout


def test_the_propagator_outputs_are_the_wrench_in_the_state_frame_and_over_the_mass(ros):
    """wrench_inertial: the body force turned by the attitude into the state frame (frame_id
    the state frame's), the torque as in the body frame; acceleration: that force over the
    mass, and the inertia's inverse times the torque. Published while subscribed."""
    from geometry_msgs.msg import AccelStamped, WrenchStamped

    node, peer = ros
    inertia = [[12.0, 0.5, 0.0], [0.5, 20.0, -1.0], [0.0, -1.0, 25.0]]
    result = node.set_parameters(
        [
            Parameter("mass", value=150.0),
            Parameter("inertia", value=[x for row in inertia for x in row]),
        ]
    )
    assert all(r.successful for r in result), [r.reason for r in result]
    inertial, accel = [], []
    peer.node.create_subscription(WrenchStamped, "wrench_inertial", inertial.append, 10)
    peer.node.create_subscription(AccelStamped, "acceleration", accel.append, 10)
    assert peer.spin_until(lambda: node.count_subscribers("acceleration") == 1)
    pos, vel = circular_orbit_state(300e3)
    peer.send_state(0.0, pos, vel)
    peer.spin_for(0.05)
    angle = 0.7  # the body turned about z in ECI
    q = (0.0, 0.0, math.sin(angle / 2), math.cos(angle / 2))
    peer.send_attitude(0.01, q)
    assert peer.spin_until(lambda: peer.wrenches and inertial and accel)
    body = peer.wrenches[-1].wrench
    rotation = np.array(
        [
            [math.cos(angle), -math.sin(angle), 0.0],
            [math.sin(angle), math.cos(angle), 0.0],
            [0, 0, 1],
        ]
    )
    force_eci = rotation @ vec(body.force)
    got = inertial[-1]
    assert got.header.frame_id == "eci" and got.header.stamp == peer.wrenches[-1].header.stamp
    scale = np.linalg.norm(force_eci)  # (components far below it carry its rounding)
    np.testing.assert_allclose(vec(got.wrench.force), force_eci, rtol=0, atol=1e-12 * scale)
    np.testing.assert_array_equal(vec(got.wrench.torque), vec(body.torque))
    a = accel[-1]
    assert a.header.frame_id == "eci"
    np.testing.assert_allclose(
        vec(a.accel.linear), force_eci / 150.0, rtol=0, atol=1e-12 * scale / 150.0
    )
    expected = np.linalg.solve(np.array(inertia), vec(body.torque))
    np.testing.assert_allclose(
        vec(a.accel.angular), expected, rtol=0, atol=1e-12 * np.linalg.norm(expected)
    )
    assert np.linalg.norm(vec(a.accel.linear)) > 0.0


def test_solar_pressure_publishes_the_solar_and_the_total_wrench(ros):
    """With solar_pressure set at run time: solar_wrench (the Sun at +x of the equinox noon
    pushes the sphere along -x: a sphere of radius r, absorbing, gets P pi r^2), total_wrench
    the sum of it and the wrench, the solar values in /diagnostics."""
    from geometry_msgs.msg import WrenchStamped

    from adbsat_ros.environment.sun import sun_state

    node, peer = ros
    assert node.set_parameters([Parameter("solar_pressure", value=True)])[0].successful
    solar, total = [], []
    peer.node.create_subscription(WrenchStamped, "solar_wrench", solar.append, 10)
    peer.node.create_subscription(WrenchStamped, "total_wrench", total.append, 10)
    assert peer.spin_until(lambda: node.count_subscribers("total_wrench") == 1)
    pos, vel = circular_orbit_state(300e3)
    peer.send_state(0.0, pos, vel)
    peer.spin_for(0.05)
    peer.send_attitude(0.01, (0.0, 0.0, 0.0, 1.0))
    assert peer.spin_until(lambda: peer.wrenches and solar and total)
    aero, sun_push, both = peer.wrenches[-1].wrench, solar[-1].wrench, total[-1].wrench
    assert solar[-1].header == total[-1].header == peer.wrenches[-1].header
    np.testing.assert_array_equal(vec(both.force), vec(aero.force) + vec(sun_push.force))
    np.testing.assert_array_equal(vec(both.torque), vec(aero.torque) + vec(sun_push.torque))
    sun = sun_state(dt.datetime(2026, 3, 20, 12, 0, 0, 10_000), pos)
    assert sun.lit_fraction == 1.0
    area = node.estimator.mesh.areas.sum() / 4.0  # a sphere's cross-section: a quarter
    expected = -sun.pressure * area * sun.direction_eci
    np.testing.assert_allclose(vec(sun_push.force), expected, rtol=2e-2, atol=1e-3 * sun.pressure)
    assert peer.spin_until(
        lambda: any(
            any(kv.key == "solar_lit_fraction" and kv.value == "1.0" for kv in st.values)
            for d in peer.diagnostics
            for st in d.status
        )
    )


def test_the_panel_marker_shows_every_panel_coloured_by_its_pressure(ros):
    """panel_marker: one triangle per panel of the mesh, in the body frame, coloured as the
    pressure picture colours the latest wrench's panels; published while subscribed."""
    from visualization_msgs.msg import Marker

    from adbsat_ros.plotting.panels import panel_colours

    node, peer = ros
    assert node.set_parameters([Parameter("marker_period", value=0.2)])[0].successful
    markers = []
    peer.node.create_subscription(Marker, "panel_marker", markers.append, 1)
    pos, vel = circular_orbit_state(300e3)
    peer.send_state(0.0, pos, vel)
    peer.spin_for(0.05)
    peer.send_attitude(0.01, (0.0, 0.0, 0.0, 1.0))
    assert peer.spin_until(lambda: bool(peer.wrenches))
    assert peer.spin_until(lambda: bool(markers))
    marker = markers[-1]
    mesh = node.estimator.mesh
    assert marker.type == Marker.TRIANGLE_LIST and marker.header.frame_id == "base_link"
    assert len(marker.points) == len(marker.colors) == 3 * mesh.n_panels
    np.testing.assert_allclose(
        [(p.x, p.y, p.z) for p in marker.points[:6]], mesh.vertices[:2].reshape(-1, 3), atol=1e-12
    )
    colours = np.array([(c.r, c.g, c.b) for c in marker.colors[::3]])
    assert np.all((colours >= 0.0) & (colours <= 1.0))
    sample = node.health.last_sample.coefficients
    expected, _, _ = panel_colours(sample.cp, sample.cos_delta, sample.lit_fraction)
    np.testing.assert_allclose(colours, expected[:, :3], atol=1e-6)  # (float32 in the message)
    assert len(np.unique(colours.round(3), axis=0)) > 10  # the pressures vary over the sphere
