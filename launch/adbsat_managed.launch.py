"""Launch adbsat_node as a managed (lifecycle) node, then configure and activate it.

In a ROS 2 installation (the launch package is not among the pip wheels):

    ros2 launch adbsat_ros adbsat_managed.launch.py [params_file:=/path/to/params.yaml]

The node loads its mesh and settings at configure (a set-up that cannot be loaded leaves it
unconfigured, the reason logged) and publishes once active.
"""

import os

from ament_index_python.packages import get_package_share_directory
from launch.actions import DeclareLaunchArgument, EmitEvent, RegisterEventHandler
from launch.events import matches_action
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import LifecycleNode
from launch_ros.event_handlers import OnStateTransition
from launch_ros.events.lifecycle import ChangeState
from lifecycle_msgs.msg import Transition

from launch import LaunchDescription


def generate_launch_description():
    """The managed node with the parameters file, configured, then activated once inactive."""
    default_params = os.path.join(
        get_package_share_directory("adbsat_ros"), "config", "adbsat.yaml"
    )
    node = LifecycleNode(
        package="adbsat_ros",
        executable="adbsat_node",
        name="adbsat_node",
        namespace="",
        arguments=["--managed"],
        parameters=[LaunchConfiguration("params_file")],
        output="screen",
    )
    configure = EmitEvent(
        event=ChangeState(
            lifecycle_node_matcher=matches_action(node),
            transition_id=Transition.TRANSITION_CONFIGURE,
        )
    )
    activate = RegisterEventHandler(
        OnStateTransition(
            target_lifecycle_node=node,
            goal_state="inactive",
            entities=[
                EmitEvent(
                    event=ChangeState(
                        lifecycle_node_matcher=matches_action(node),
                        transition_id=Transition.TRANSITION_ACTIVATE,
                    )
                )
            ],
        )
    )
    return LaunchDescription(
        [
            DeclareLaunchArgument(
                "params_file", default_value=default_params, description="parameters file"
            ),
            node,
            activate,
            configure,
        ]
    )
