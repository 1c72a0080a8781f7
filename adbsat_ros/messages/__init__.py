"""The ROS messages on the wrench's path as bytes: decoding, encoding, the one codec, stamps.

Modules:

- :mod:`~adbsat_ros.messages.decoding`: input messages from CDR bytes to the estimator's fields.
- :mod:`~adbsat_ros.messages.encoding`: the messages of one wrench as CDR bytes.
- :mod:`~adbsat_ros.messages.cdr`: QuaternionStamped read, WrenchStamped and AccelStamped
  written with ``struct``, header stamps.
- :mod:`~adbsat_ros.messages.stamps`: header stamps as seconds, the next stamp of a stream.

A bottom layer: it imports no ROS and nothing else of adbsat_ros.
"""
