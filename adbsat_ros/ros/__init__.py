"""ROS 2: the node, the live bag tools and the demo; the only part of adbsat_ros importing rclpy.

Modules:

- :mod:`~adbsat_ros.ros.node`: :class:`AdbsatNode`, a thin shell over the estimator's
  per-message handler; :mod:`~adbsat_ros.ros.executors`, :mod:`~adbsat_ros.ros.log_throttle`
  and :mod:`~adbsat_ros.ros.node_help` (its ``--help``) are its helpers;
  :mod:`~adbsat_ros.ros.node_core` holds its interfaces and callbacks, shared with the managed
  (lifecycle) node; :mod:`~adbsat_ros.ros.parameter_values` declares its parameters with their
  types and reads ``adbsat-ros param set`` values as a parameter's type;
  :mod:`~adbsat_ros.ros.message_info` counts the messages its subscriptions lost.
- :mod:`~adbsat_ros.ros.bag_play`, :mod:`~adbsat_ros.ros.bag_record`, :mod:`~adbsat_ros.ros.graph`:
  ``bag play`` and ``bag record`` without the ``ros2`` command.
- :mod:`~adbsat_ros.ros.demo`, :mod:`~adbsat_ros.ros.demo_report`: ``adbsat-ros demo``.
- :mod:`~adbsat_ros.ros.orbit_publisher`: a small publisher to try the node.
"""
