"""Input messages from their CDR bytes to the estimator's fields, with the caller's deserialiser
(rclpy's or rosbags'); bytes that are not the message raise :class:`UndecodableMessage`.
"""

from __future__ import annotations

from typing import Callable, NamedTuple

from adbsat_ros.messages.cdr import AttitudeFields, Stamp, quaternion_stamped_fields

#: The message types read here (ROS 2 names).
QUATERNION_STAMPED = "geometry_msgs/msg/QuaternionStamped"
ODOMETRY = "nav_msgs/msg/Odometry"
JOINT_STATE = "sensor_msgs/msg/JointState"


class OdometryFields(NamedTuple):
    """What the wrench needs of a nav_msgs/Odometry, named as in the message."""

    stamp: Stamp
    frame_id: str
    """header.frame_id: the frame of the pose (ECI or ECEF for the node)."""
    child_frame_id: str
    """The frame of the twist (Odometry convention)."""
    position: tuple
    """pose.pose.position x, y, z [m] in ``frame_id``."""
    orientation_xyzw: tuple
    """pose.pose.orientation x, y, z, w: the child frame's orientation in ``frame_id``."""
    linear_velocity: tuple
    """twist.twist.linear x, y, z [m/s] in ``child_frame_id``."""

    @classmethod
    def of_message(cls, msg) -> "OdometryFields":
        """The fields of an Odometry message object (rclpy's or rosbags')."""
        p, o, v = msg.pose.pose.position, msg.pose.pose.orientation, msg.twist.twist.linear
        return cls(
            Stamp(msg.header.stamp.sec, msg.header.stamp.nanosec),
            msg.header.frame_id,
            msg.child_frame_id,
            (p.x, p.y, p.z),
            (o.x, o.y, o.z, o.w),
            (v.x, v.y, v.z),
        )


class JointStateFields(NamedTuple):
    """Of a sensor_msgs/JointState: stamp, joint names, and their positions [rad or m]."""

    stamp: Stamp
    names: tuple
    positions: tuple

    @classmethod
    def of_message(cls, msg) -> "JointStateFields":
        """The fields of an rclpy or rosbags JointState message object."""
        stamp = msg.header.stamp
        return cls(
            Stamp(int(stamp.sec), int(stamp.nanosec)),
            tuple(str(n) for n in msg.name),
            tuple(float(x) for x in msg.position),
        )


class UndecodableMessage(Exception):
    """Bytes that are not ``message_type``; ``reason``: ``ExceptionName: text``."""

    def __init__(self, message_type: str, cause: BaseException):
        self.message_type = message_type
        self.reason = f"{type(cause).__name__}: {cause}"
        super().__init__(f"not a {message_type} ({self.reason})")


def decode_attitude(raw, deserialise: Callable) -> AttitudeFields:
    """Stamp and quaternion of a CDR QuaternionStamped (struct, else ``deserialise``)."""
    try:
        return quaternion_stamped_fields(raw)
    except ValueError:
        pass
    return _decode(AttitudeFields, QUATERNION_STAMPED, raw, deserialise)


def decode_odometry(raw, deserialise: Callable) -> OdometryFields:
    """Stamp, frames, pose and linear velocity of a CDR nav_msgs/Odometry."""
    return _decode(OdometryFields, ODOMETRY, raw, deserialise)


def decode_joint_state(raw, deserialise: Callable) -> JointStateFields:
    """Stamp, names and positions of a CDR sensor_msgs/JointState."""
    return _decode(JointStateFields, JOINT_STATE, raw, deserialise)


def _decode(fields, message_type: str, raw, deserialise: Callable):
    """``fields.of_message(deserialise(raw))``, any failure an UndecodableMessage."""
    try:
        return fields.of_message(deserialise(raw))
    except Exception as exc:  # the deserialisers raise many kinds (RuntimeError, struct ...)
        raise UndecodableMessage(message_type, exc) from None
