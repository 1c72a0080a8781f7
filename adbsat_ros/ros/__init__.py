"""ROS 2: the node, the live bag tools and the demo; the only part of adbsat_ros importing rclpy.

Modules:

- :mod:`~adbsat_ros.ros.node`, :mod:`~adbsat_ros.ros.managed_node`: :class:`AdbsatNode` (a thin
  shell over the estimator's per-message handler) and its lifecycle form, sharing
  :mod:`~adbsat_ros.ros.node_core`; helpers :mod:`~adbsat_ros.ros.executors`,
  :mod:`~adbsat_ros.ros.log_throttle`, :mod:`~adbsat_ros.ros.node_help` (``--help``),
  :mod:`~adbsat_ros.ros.parameter_values`, :mod:`~adbsat_ros.ros.message_info` (lost messages),
  :mod:`~adbsat_ros.ros.readers` (which optional outputs have readers).
- :mod:`~adbsat_ros.ros.bag_play`, :mod:`~adbsat_ros.ros.bag_record`, :mod:`~adbsat_ros.ros.graph`,
  :mod:`~adbsat_ros.ros.graph_tools`: ``bag play``, ``bag record``, ``param``, ``topic echo``.
- :mod:`~adbsat_ros.ros.demo`, :mod:`~adbsat_ros.ros.demo_report`,
  :mod:`~adbsat_ros.ros.demo_joints`: ``adbsat-ros demo``.
- :mod:`~adbsat_ros.ros.orbit_publisher`, :mod:`~adbsat_ros.ros.entry_points`: a small publisher
  to try the node, and the console scripts.
"""
