"""The node with an articulated body (real rclpy): joint positions on joint_states, the wrench of
the posed body, the aerodynamic torque of every joint on joint_torques (the same numbers as the
estimator given the same messages), bad joint states refused and counted with the node up."""

import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

import math  # noqa: E402

import numpy as np  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402
from ros_harness import circular_orbit_state, node_and_peer, to_stamp  # noqa: E402
from sensor_msgs.msg import JointState  # noqa: E402

from adbsat_ros.estimator.estimator import AeroWrenchEstimator  # noqa: E402
from adbsat_ros.estimator.settings import WrenchSettings  # noqa: E402
from adbsat_ros.geometry.example_urdf import example_satellite_urdf  # noqa: E402

EPOCH = "2026-03-20T12:00:00"
HINGES = ["wing_left_hinge", "wing_right_hinge"]
# body x along the orbital velocity, then 23 deg about body y: the wings meet the flow at an angle
_C, _S, _c, _s = math.cos(math.pi / 4), math.sin(math.pi / 4), math.cos(0.2), math.sin(0.2)
ATTITUDE = (-_S * _s, _C * _s, _S * _c, _C * _c)
SETTINGS = {
    "robot_description": example_satellite_urdf(),
    "time_mode": "epoch",
    "epoch_utc": EPOCH,
    "center_of_mass": [0.05, 0.0, 0.01],
    "diagnostics_period": 0.2,
}


@pytest.fixture
def ros():
    with node_and_peer(Parameter(k, value=v) for k, v in SETTINGS.items()) as running:
        yield running


def joint_state(t, names, positions):
    msg = JointState()
    msg.header.stamp = to_stamp(t)
    msg.name = list(names)
    msg.position = [float(x) for x in positions]
    return msg


def joint_states_handled(node) -> int:
    """Joint states the node has taken so far, accepted or refused."""
    return node.estimator.joints.accepted + node.estimator.rejections["bad_joint_state"]


def test_joint_torques_come_with_every_wrench_as_the_estimator_computes_them(ros):
    node, peer = ros
    joints_pub = peer.node.create_publisher(JointState, "joint_states", 10)
    torques = []
    peer.node.create_subscription(JointState, "joint_torques", torques.append, 10)
    assert peer.spin_until(lambda: node.joint_torque_readers == 1)  # (published while subscribed)
    assert peer.spin_until(lambda: joints_pub.get_subscription_count() == 1)
    pos, vel = circular_orbit_state(300e3)
    inputs = [(0.0, (0.3, -0.2)), (0.02, (0.6, -0.2))]
    peer.send_state(0.0, pos, vel)
    peer.spin_for(0.05)
    for k, (t, angles) in enumerate(inputs):
        joints_pub.publish(joint_state(t, HINGES, angles))
        assert peer.spin_until(lambda: node.estimator.joints.accepted == k + 1)
        peer.send_attitude(t + 0.01, ATTITUDE)
        assert peer.spin_until(lambda: len(torques) == k + 1 and len(peer.wrenches) == k + 1)
    reference = AeroWrenchEstimator(WrenchSettings.from_parameters(SETTINGS))
    reference.on_state(0.0, pos, vel)
    for (t, angles), msg, wrench in zip(inputs, torques, peer.wrenches):
        reference.on_joint_state(t, HINGES, angles)
        sample = reference.on_attitude(t + 0.01, ATTITUDE)
        assert msg.header == wrench.header and msg.header.frame_id == "base_link"
        assert list(msg.name) == HINGES
        assert list(msg.position) == list(angles)
        assert list(msg.effort) == sample.joints.efforts.tolist()
        force = wrench.wrench.force
        assert [force.x, force.y, force.z] == sample.force.tolist()
    assert not np.allclose(torques[0].effort, torques[1].effort, rtol=1e-6, atol=0)
    assert peer.wrenches[0].wrench.force != peer.wrenches[1].wrench.force  # a wing turned


def test_bad_joint_states_are_refused_and_counted_and_the_node_stays_up(ros):
    node, peer = ros
    joints_pub = peer.node.create_publisher(JointState, "joint_states", 10)
    assert peer.spin_until(lambda: joints_pub.get_subscription_count() == 1)
    pos, vel = circular_orbit_state(300e3)
    peer.send_state(0.0, pos, vel)
    peer.spin_for(0.05)
    peer.send_attitude(0.01, ATTITUDE)  # no joint state yet
    bad = (
        joint_state(0.02, ["antenna"], [0.0]),
        joint_state(0.02, HINGES, [math.nan, 0.0]),
        joint_state(0.02, HINGES, [7.0, 0.0]),  # beyond the hinge's +-pi
        joint_state(0.02, HINGES, [0.1]),
    )
    for count, msg in enumerate(bad, start=1):
        joints_pub.publish(msg)
        assert peer.spin_until(lambda: joint_states_handled(node) == count)
    peer.send_attitude(0.03, ATTITUDE)
    joints_pub.publish(joint_state(0.04, HINGES, [0.1, 0.1]))
    assert peer.spin_until(lambda: node.estimator.joints.accepted == 1)
    peer.send_attitude(0.05, ATTITUDE)
    assert peer.spin_until(lambda: len(peer.wrenches) == 1)
    values = dict(node.diagnostic_fields().values)
    assert values["rejected_bad_joint_state"] == "4"
    assert values["rejected_no_joint_state"] == "2"
    assert values["joint_states_accepted"] == "1"
    assert values["published"] == "1"
