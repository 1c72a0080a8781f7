"""The managed (lifecycle) wrench node: the same node, brought up by the ROS 2 lifecycle protocol.

``configure`` loads the set-up the parameters give (mesh, models, shading structures) and makes
the publishers and subscriptions; a set-up that cannot be loaded fails the transition, the
reason logged, and the node stays unconfigured. ``activate`` starts serving: attitudes and states
are computed and published (lifecycle publishers publish only while active). ``deactivate``
stops serving and keeps the set-up; ``cleanup`` frees it. Parameters may be changed in any state
and are checked at once; those that need a new set-up (``mesh``, ``mesh_scale``,
``mesh_accept_size``, ``qos_depth``, ``body_frame_id``, ``executor``), read-only in the plain
node, change only while unconfigured, and the next ``configure`` uses them. Run it with
``adbsat_node --managed --ros-args ...`` and drive it with any lifecycle client
(``launch/adbsat_managed.launch.py`` for ROS installations).
The plain node (:mod:`.node`) stays the default.
"""

from __future__ import annotations

from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn

from adbsat_ros.geometry.mesh import MeshError
from adbsat_ros.ros.node_core import WrenchNodeCore
from adbsat_ros.ros.node_help import NODE_NAME


class AdbsatLifecycleNode(WrenchNodeCore, LifecycleNode):
    """The wrench node as a managed node (module docstring).

    Parameters
    ----------
    **node_kwargs
        Passed to ``rclpy.lifecycle.LifecycleNode`` (e.g. ``context``, ``parameter_overrides``).
    """

    serving = False
    managed = True

    def __init__(self, **node_kwargs):
        super().__init__(NODE_NAME, **node_kwargs)
        self.declare_wrench_parameters()

    def on_configure(self, state) -> TransitionCallbackReturn:
        """Load the set-up and make the interfaces; FAILURE (reason logged) if it cannot be."""
        try:
            self.set_up(self.create_lifecycle_publisher)
        except (MeshError, ValueError, OSError) as exc:
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
        """Free everything before the node goes."""
        self.serving = False
        self.tear_down(self.destroy_lifecycle_publisher)
        return TransitionCallbackReturn.SUCCESS
