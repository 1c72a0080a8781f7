"""ROS 2: the node, the live bag tools and the demo; the only part of adbsat_ros importing rclpy.

- :mod:`.node`, :mod:`.managed_node`, :mod:`.node_core`: the wrench node and its lifecycle form;
  helpers :mod:`.executors`, :mod:`.log_throttle`, :mod:`.node_help`, :mod:`.parameter_values`,
  :mod:`.message_info`, :mod:`.readers`, :mod:`.panel_marker`, :mod:`.qos`.
- :mod:`.bag_play`, :mod:`.bag_record`, :mod:`.graph`, :mod:`.graph_tools`: ``bag play``,
  ``bag record``, ``param``, ``topic echo``.
- :mod:`.demo`, :mod:`.demo_report`, :mod:`.demo_joints`: ``adbsat-ros demo``.
- :mod:`.orbit_publisher`, :mod:`.entry_points`: a small publisher and the console scripts.
"""
