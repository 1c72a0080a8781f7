"""The node in someone else's ROS graph, with real rclpy: BEST_EFFORT inputs, the standard
qos_overrides parameters, and the managed node's process (diagnostics while inactive, shutdown)."""

import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

import subprocess
import sys

import rclpy
from geometry_msgs.msg import QuaternionStamped
from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState
from nav_msgs.msg import Odometry
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import ReliabilityPolicy, qos_profile_sensor_data
from ros_harness import (
    HANG_TIMEOUT,
    Peer,
    circular_orbit_state,
    make_context,
    node_and_peer,
    to_stamp,
)

from adbsat_ros.ros.node import AdbsatNode

ATTITUDE_RELIABILITY = "qos_overrides./attitude.subscription.reliability"
ATTITUDE_DEPTH = "qos_overrides./attitude.subscription.depth"
WARN = b"\x01"  # (a DiagnosticStatus level)


def test_a_best_effort_publisher_gets_wrenches():
    """Sensor-data QoS (BEST_EFFORT), the usual for estimators and simulator bridges."""
    with node_and_peer([Parameter("shading", value="none")]) as (node, peer):
        sender = Node("best_effort_sender", context=node.context)
        peer.executor.add_node(sender)
        attitudes = sender.create_publisher(QuaternionStamped, "attitude", qos_profile_sensor_data)
        states = sender.create_publisher(Odometry, "state", qos_profile_sensor_data)
        try:
            assert peer.spin_until(
                lambda: attitudes.get_subscription_count() and states.get_subscription_count()
            )
            pos, vel = circular_orbit_state(300e3)
            for k in range(1, 40):  # (a best-effort message may be lost: the next one is sent)
                t = 0.01 * k
                odometry = Odometry()
                odometry.header.stamp, odometry.header.frame_id = to_stamp(t), "eci"
                p, v = odometry.pose.pose.position, odometry.twist.twist.linear
                p.x, p.y, p.z = pos
                v.x, v.y, v.z = vel
                odometry.pose.pose.orientation.w = 1.0
                states.publish(odometry)
                attitude = QuaternionStamped()
                attitude.header.stamp, attitude.header.frame_id = to_stamp(t), "eci"
                attitude.quaternion.w = 1.0
                attitudes.publish(attitude)
                sent = len(peer.wrenches)
                peer.spin_until(lambda: len(peer.wrenches) > sent, timeout=HANG_TIMEOUT / 40)
                if len(peer.wrenches) >= 3:
                    break
            assert len(peer.wrenches) >= 3 and node.estimator.published >= 3
        finally:
            sender.destroy_node()


def test_a_state_in_a_wrong_frame_shows_as_such_in_the_diagnostics():
    """Not as a missing or stale state: the refusal leads the message and is counted by name."""
    with node_and_peer([Parameter("shading", value="none")]) as (node, peer):
        pos, vel = circular_orbit_state(300e3)
        peer.send_state(1.0, pos, vel, frame="ecef")  # (state_frame eci)
        assert peer.spin_until(lambda: node.estimator.rejections["bad_state_frame"] == 1)
        peer.send_attitude(1.0, (0.0, 0.0, 0.0, 1.0))
        assert peer.spin_until(lambda: node.estimator.rejections["no_state"] == 1)
        fields = node.diagnostic_fields()
        assert fields.message == "bad_state_frame: no orbital state"
        assert ("rejected_bad_state_frame", "1") in fields.values


def endpoint_qos(peer, topic: str):
    """The QoS of adbsat_node's subscription of ``topic`` as the graph reports it."""
    found = []
    assert peer.spin_until(
        lambda: bool(
            found.extend(
                i.qos_profile
                for i in peer.node.get_subscriptions_info_by_topic(topic)
                if i.node_name == "adbsat_node"
            )
            or found
        )
    )
    return found[0]


def test_qos_overrides_set_a_subscriptions_reliability_and_depth():
    overrides = [
        Parameter("shading", value="none"),
        Parameter(ATTITUDE_RELIABILITY, value="reliable"),
        Parameter(ATTITUDE_DEPTH, value=3),
    ]
    with node_and_peer(overrides) as (node, peer):
        assert endpoint_qos(peer, "/attitude").reliability == ReliabilityPolicy.RELIABLE
        assert endpoint_qos(peer, "/state").reliability == ReliabilityPolicy.BEST_EFFORT
        # the depth is not part of what the middleware announces: the node's own subscription
        depths = {s.topic_name: s.qos_profile.depth for s in node._subscriptions_made}
        assert depths == {"/attitude": 3, "/state": 10}  # (the other: qos_depth)
        assert node.get_parameter(ATTITUDE_DEPTH).value == 3
        assert node.get_parameter("qos_overrides./wrench.publisher.reliability").value == (
            "reliable"
        )


@pytest.mark.parametrize(
    "name, value, message",
    [
        ("qos_overrides./attitude.subscription.relability", "reliable",
         r"relability: unknown \(did you mean qos_overrides\./attitude\.subscription\.reliability"),
        (ATTITUDE_RELIABILITY, "sometimes",
         "reliability: one of reliable, best_effort, system_default, got 'sometimes'"),
        ("qos_overrides./diagnostics.publisher.depth", -2, "depth: a whole number >= 0, got -2"),
    ],
)  # fmt: skip
def test_a_bad_qos_override_stops_the_node_naming_it(name, value, message):
    ctx, executor = make_context()
    try:
        with pytest.raises(ValueError, match=f"^parameter {name[:20]}.*{message}"):
            AdbsatNode(
                context=ctx,
                parameter_overrides=[
                    Parameter("shading", value="none"),
                    Parameter(name, value=value),
                ],
            )
    finally:
        executor.shutdown()
        rclpy.try_shutdown(context=ctx)


def test_a_managed_node_reports_its_state_and_ends_on_shutdown(tmp_path):
    """Unconfigured and inactive, its /diagnostics carry the lifecycle state; ``shutdown`` ends
    the process with status 0."""
    log = tmp_path / "node.log"
    cmd = [sys.executable, "-m", "adbsat_ros.ros.node", "--managed", "--ros-args"]
    cmd += ["-p", "shading:=none", "-p", "diagnostics_period:=0.2"]
    with open(log, "w") as out:
        proc = subprocess.Popen(cmd, stdout=out, stderr=out)
    ctx, executor = make_context()
    try:
        peer = Peer(ctx, executor)
        change = peer.node.create_client(ChangeState, "/adbsat_node/change_state")

        def state_reported(label):
            def seen():
                return any(
                    (kv.key, kv.value) == ("lifecycle_state", label)
                    for d in peer.diagnostics
                    for s in d.status
                    for kv in s.values
                )

            assert peer.spin_until(seen), f"no /diagnostics with {label}: {log.read_text()}"
            return next(
                s for d in peer.diagnostics for s in d.status if f"state {label}" in s.message
            )

        unconfigured = state_reported("unconfigured")
        assert unconfigured.level == WARN and "not configured" in unconfigured.message
        assert change.wait_for_service(timeout_sec=HANG_TIMEOUT)

        def transition(transition_id):
            future = change.call_async(ChangeState.Request(transition=Transition(id=transition_id)))
            assert peer.spin_until(future.done)
            return future.result().success

        assert transition(Transition.TRANSITION_CONFIGURE)
        inactive = state_reported("inactive")
        assert inactive.level == WARN and "published" in {kv.key for kv in inactive.values}
        assert transition(Transition.TRANSITION_INACTIVE_SHUTDOWN)
        assert proc.wait(timeout=HANG_TIMEOUT) == 0, log.read_text()
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        executor.shutdown()
        peer.node.destroy_node()
        rclpy.try_shutdown(context=ctx)
