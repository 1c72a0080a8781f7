"""Messages lost on the way to the node, with real rclpy: ``messages_lost`` in /diagnostics.

The node's executor is not spun while the attitudes are published, so they all wait in the
node's subscription queue (KEEP_LAST ``qos_depth``): a queue smaller than the burst must drop the
oldest, and the node counts them from the publisher's sequence numbers; one as deep as the burst
drops none.
"""

import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

import numpy as np
import trimesh
from geometry_msgs.msg import QuaternionStamped
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile
from ros_harness import circular_orbit_state, node_and_peer, to_stamp

from adbsat_ros.estimator.parameters import EXECUTORS

#: Attitudes in one burst (the peer's publisher keeps 100).
BURST = 60
#: Long enough to catch a hang only.
PATIENCE = 60.0


@pytest.fixture(scope="module")
def sphere_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("mesh") / "sphere.stl"
    trimesh.creation.icosphere(subdivisions=2, radius=0.5).export(path)
    return str(path)


def running(sphere_file, executor, qos_depth):
    overrides = [
        Parameter("mesh", value=sphere_file),
        Parameter("shading", value="none"),
        Parameter("time_mode", value="epoch"),
        Parameter("epoch_utc", value="2026-03-20T12:00:00"),
        Parameter("qos_depth", value=qos_depth),
    ]
    return node_and_peer(overrides, executor)


def random_quaternions(n, seed=3):
    q = np.random.default_rng(seed).normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def started(node, peer):
    """A state, then one attitude the node answers: the attitude publisher's count starts."""
    pos, vel = circular_orbit_state(300e3)
    peer.send_state(1.0, pos, vel)
    assert peer.spin_until(lambda: _state_known(node), PATIENCE)
    peer.send_attitude(1.0, (0.0, 0.0, 0.0, 1.0))
    assert peer.spin_until(lambda: len(peer.wrenches) == 1, PATIENCE)


def _state_known(node):
    return not node.diagnostic_fields().message.endswith("no orbital state")


def burst(node, peer, n=BURST):
    """``n`` random attitudes published while the executor stands still, then served; the
    attitudes the node answered and the ones it counts lost, once every one is accounted for
    and nothing more comes."""
    for k, q in enumerate(random_quaternions(n), start=1):
        peer.send_attitude(1.0 + 0.001 * k, q)
    assert peer.spin_until(lambda: len(peer.wrenches) - 1 + node.messages_lost >= n, PATIENCE)
    peer.spin_for(0.3)  # the node is quiet: nothing more arrives
    return len(peer.wrenches) - 1, node.messages_lost


@pytest.mark.parametrize("executor", EXECUTORS)
def test_attitudes_dropped_from_a_full_queue_are_counted_lost(sphere_file, executor):
    """A burst of 60 attitudes into a queue of 5: every attitude is either answered or counted
    lost, and /diagnostics says so."""
    with running(sphere_file, executor, qos_depth=5) as (node, peer):
        started(node, peer)
        answered, lost = burst(node, peer)
        assert answered + lost == BURST
        assert 1 <= answered <= 5 and lost >= BURST - 5
        values = dict(node.diagnostic_fields().values)
        assert values["messages_lost"] == values["attitudes_lost"] == str(lost)
        assert values["states_lost"] == "0"
        assert node.estimator.published == answered + 1


@pytest.mark.parametrize("executor", EXECUTORS)
def test_a_burst_the_queue_holds_loses_nothing(sphere_file, executor):
    """The same burst into a queue of 100: every attitude answered, none counted lost."""
    with running(sphere_file, executor, qos_depth=100) as (node, peer):
        started(node, peer)
        answered, lost = burst(node, peer)
        assert (answered, lost) == (BURST, 0)
        assert dict(node.diagnostic_fields().values)["messages_lost"] == "0"


@pytest.mark.parametrize("executor", EXECUTORS)
def test_two_publishers_numbering_apart_lose_nothing(sphere_file, executor):
    """Two publishers whose numbers interleave far apart (one sent 30 before the other's first):
    no message is lost and none is counted lost."""
    with running(sphere_file, executor, qos_depth=100) as (node, peer):
        started(node, peer)
        other = Node("other_attitudes", context=node.context)
        try:
            publisher = other.create_publisher(QuaternionStamped, "attitude", QoSProfile(depth=100))
            assert peer.spin_until(lambda: node.count_publishers("attitude") == 2, PATIENCE)

            def send(t):
                msg = QuaternionStamped()
                msg.header.stamp, msg.header.frame_id = to_stamp(t), "eci"
                msg.quaternion.w = 1.0
                publisher.publish(msg)

            for k in range(30):
                send(1.1 + 0.001 * k)
            assert peer.spin_until(lambda: len(peer.wrenches) == 31, PATIENCE)
            for k in range(20):  # alternately: numbers 2, 31, 3, 32, ...
                peer.send_attitude(1.2 + 0.002 * k, (0.0, 0.0, 0.0, 1.0))
                send(1.201 + 0.002 * k)
            assert peer.spin_until(lambda: len(peer.wrenches) == 71, PATIENCE)
            peer.spin_for(0.3)
            assert node.messages_lost == 0
        finally:
            other.destroy_node()
