"""The ROS messages on the wrench's path as bytes; imports no ROS and nothing else of adbsat_ros.

- :mod:`.decoding`: input messages from CDR bytes; :mod:`.encoding`: one wrench's messages.
- :mod:`.cdr`: QuaternionStamped read, WrenchStamped and AccelStamped written with ``struct``.
- :mod:`.stamps`: header stamps as seconds, the next stamp of a stream.
"""
