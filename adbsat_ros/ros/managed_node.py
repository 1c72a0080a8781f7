"""The managed (lifecycle) wrench node; docs/node.md, "Managed (lifecycle) node"."""

from __future__ import annotations

from rclpy.exceptions import InvalidParameterTypeException
from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn

from adbsat_ros.geometry.mesh import MeshError
from adbsat_ros.ros.node_core import WrenchNodeCore
from adbsat_ros.ros.node_help import NODE_NAME


class AdbsatLifecycleNode(WrenchNodeCore, LifecycleNode):
    """The wrench node as a managed node; ``node_kwargs`` go to ``LifecycleNode``."""

    serving = False
    managed = True
    #: Whether the node went through ``shutdown`` (finalized): its process ends.
    finalized = False

    def __init__(self, **node_kwargs):
        super().__init__(NODE_NAME, **node_kwargs)
        self.declare_wrench_parameters()

    @property
    def lifecycle_state(self) -> str:
        """The label of the current lifecycle state (``unconfigured``, ``inactive``, ...)."""
        return self._state_machine.current_state[1]  # (as rclpy's own trigger_shutdown reads it)

    def on_configure(self, state) -> TransitionCallbackReturn:
        """Load the set-up and make the interfaces; FAILURE (reason logged) if it cannot be."""
        try:
            self.set_up(self.create_lifecycle_publisher)
        except (MeshError, ValueError, OSError, RuntimeError, InvalidParameterTypeException) as exc:
            self.get_logger().error(f"configure failed: {exc}")
            self.tear_down(self.destroy_lifecycle_publisher)
            return TransitionCallbackReturn.FAILURE
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state) -> TransitionCallbackReturn:
        """Serve messages and publish."""
        self.serving = True
        return super().on_activate(state)

    def on_deactivate(self, state) -> TransitionCallbackReturn:
        """Stop serving; keep the set-up."""
        self.serving = False
        return super().on_deactivate(state)

    def on_cleanup(self, state) -> TransitionCallbackReturn:
        """Free the set-up and the interfaces."""
        self.serving = False
        self.tear_down(self.destroy_lifecycle_publisher)
        return TransitionCallbackReturn.SUCCESS

    def on_shutdown(self, state) -> TransitionCallbackReturn:
        """Free everything before the node goes; its process then ends (status 0)."""
        self.serving = False
        self.tear_down(self.destroy_lifecycle_publisher)
        self.finalized = True
        return TransitionCallbackReturn.SUCCESS
