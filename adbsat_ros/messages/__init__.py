"""The ROS messages on the wrench's path as bytes: the CDR codec, its fallback, and stamps.

Modules:

- :mod:`~adbsat_ros.messages.cdr`: read QuaternionStamped and Odometry, write WrenchStamped and
  DiagnosticArray, with ``struct`` (tested against rosbags and rclpy).
- :mod:`~adbsat_ros.messages.decoding`: decoding with the codec, then one full deserialiser as the
  fallback (rclpy's in the node, rosbags' in bag analysis).
- :mod:`~adbsat_ros.messages.stamps`: header stamps as seconds, the next stamp of a fixed-rate
  stream.

A bottom layer: it imports no ROS and nothing else of adbsat_ros.
"""
