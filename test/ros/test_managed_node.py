"""The managed (lifecycle) node with real rclpy: a bad set-up fails configure and leaves it
unconfigured, activate publishes, deactivate stops, cleanup and configure again take changed
parameters; transitions over the standard lifecycle services."""

import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

import rclpy
from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState, GetState
from rclpy.lifecycle import TransitionCallbackReturn
from rclpy.parameter import Parameter
from ros_harness import HANG_TIMEOUT, Peer, circular_orbit_state, make_context

from adbsat_ros.ros.managed_node import AdbsatLifecycleNode


@pytest.fixture
def managed(tmp_path):
    ctx, executor = make_context()
    node = AdbsatLifecycleNode(
        context=ctx,
        parameter_overrides=[
            Parameter("mesh", value=str(tmp_path / "missing.obj")),
            Parameter("shading", value="none"),
            Parameter("time_mode", value="epoch"),
        ],
    )
    executor.add_node(node)
    peer = Peer(ctx, executor)
    yield node, peer
    executor.shutdown()
    peer.node.destroy_node()
    node.destroy_node()
    rclpy.try_shutdown(context=ctx)


#: Seconds to spin for a wrench that must not come: a node that publishes answers within this on an
#: idle machine (a loaded one can only make the check weaker, never fail it).
NO_WRENCH_WAIT = 2.0


def wrench_after_an_attitude(peer, t, wait=HANG_TIMEOUT) -> bool:
    """Send a state and an attitude stamped t; whether a wrench comes back within ``wait`` s."""
    count = len(peer.wrenches)
    pos, vel = circular_orbit_state(300e3)
    peer.send_state(t, pos, vel)
    peer.spin_for(0.05)
    peer.send_attitude(t + 0.001, (0.0, 0.0, 0.0, 1.0))
    return peer.spin_until(lambda: len(peer.wrenches) > count, timeout=wait)


def test_configure_fails_on_a_bad_mesh_and_the_transitions_work(managed):
    node, peer = managed
    assert node.trigger_configure() == TransitionCallbackReturn.FAILURE
    assert node.estimator is None and node.count_publishers("wrench") == 0  # still unconfigured
    # while unconfigured the set-up parameters may change (read-only in the plain node)
    assert node.set_parameters([Parameter("mesh", value="example")])[0].successful
    assert node.trigger_configure() == TransitionCallbackReturn.SUCCESS
    # while configured they may not
    refused = node.set_parameters([Parameter("qos_depth", value=5)])[0]
    assert (
        not refused.successful and "changes only while the node is unconfigured" in refused.reason
    )
    assert peer.wait_for_subscribers()
    # configured, not active: nothing published
    assert not wrench_after_an_attitude(peer, 1.0, wait=NO_WRENCH_WAIT)
    assert node.trigger_activate() == TransitionCallbackReturn.SUCCESS
    assert wrench_after_an_attitude(peer, 2.0)
    assert node.trigger_deactivate() == TransitionCallbackReturn.SUCCESS
    assert not wrench_after_an_attitude(peer, 3.0, wait=NO_WRENCH_WAIT)
    assert node.trigger_cleanup() == TransitionCallbackReturn.SUCCESS
    assert node.estimator is None
    assert node.set_parameters([Parameter("gsi_model", value="newton")])[0].successful
    assert node.trigger_configure() == TransitionCallbackReturn.SUCCESS
    assert node.estimator.settings.gsi_model == "newton"  # reconfigured with the change
    assert node.trigger_activate() == TransitionCallbackReturn.SUCCESS
    assert wrench_after_an_attitude(peer, 4.0)


def test_transitions_over_the_lifecycle_services(managed):
    node, peer = managed
    assert node.set_parameters([Parameter("mesh", value="example")])[0].successful
    change = peer.node.create_client(ChangeState, "/adbsat_node/change_state")
    get = peer.node.create_client(GetState, "/adbsat_node/get_state")
    assert change.wait_for_service(timeout_sec=HANG_TIMEOUT)
    assert get.wait_for_service(timeout_sec=HANG_TIMEOUT)

    def call(client, request):
        future = client.call_async(request)
        assert peer.spin_until(future.done)
        return future.result()

    for transition in (Transition.TRANSITION_CONFIGURE, Transition.TRANSITION_ACTIVATE):
        assert call(change, ChangeState.Request(transition=Transition(id=transition))).success
    assert call(get, GetState.Request()).current_state.label == "active"
    assert peer.wait_for_subscribers()
    assert wrench_after_an_attitude(peer, 1.0)
