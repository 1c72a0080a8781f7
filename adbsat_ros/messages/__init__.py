"""The ROS messages on the wrench's path as bytes: decoding, encoding, the one codec, stamps.

Modules:

- :mod:`~adbsat_ros.messages.decoding`: input messages from CDR bytes to the fields the
  estimator takes, with the caller's deserialiser (rclpy's in the node, rosbags' in bag
  analysis), the attitude by the ``struct`` codec first.
- :mod:`~adbsat_ros.messages.encoding`: the messages of one wrench as CDR bytes, for the node
  and the bag analysis alike.
- :mod:`~adbsat_ros.messages.cdr`: QuaternionStamped read, WrenchStamped and AccelStamped
  written with ``struct`` (tested against rosbags and rclpy), header stamps.
- :mod:`~adbsat_ros.messages.stamps`: header stamps as seconds, the next stamp of a fixed-rate
  stream.

A bottom layer: it imports no ROS and nothing else of adbsat_ros.
"""
