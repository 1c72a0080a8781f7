"""Input messages from their CDR bytes: the struct codec, then one full deserialiser as fallback.

The node and the bag analysis read their attitude and state messages the same way: the readers
of :mod:`adbsat_ros.messages.cdr` first (for plain CDR, what rclpy, Fast DDS and
rosbags write), and for bytes those refuse (XCDR2 from another RMW, trailing bytes) a full
deserialiser given by the caller: the node passes rclpy's ``deserialize_message`` with the
message type, the bag analysis the deserialiser of its rosbags type store. Bytes that neither
reads raise :class:`UndecodableMessage`.
"""

from __future__ import annotations

from typing import Callable

from adbsat_ros.messages.cdr import (
    AttitudeFields,
    JointStateFields,
    OdometryFields,
    joint_state_fields,
    odometry_fields,
    quaternion_stamped_fields,
)

#: The message types read here (ROS 2 names).
QUATERNION_STAMPED = "geometry_msgs/msg/QuaternionStamped"
ODOMETRY = "nav_msgs/msg/Odometry"
JOINT_STATE = "sensor_msgs/msg/JointState"


class UndecodableMessage(Exception):
    """Bytes that are not the message they should be.

    Attributes
    ----------
    message_type : str
        The expected type, e.g. ``geometry_msgs/msg/QuaternionStamped``.
    reason : str
        What the full deserialiser said, as ``ExceptionName: text``.
    """

    def __init__(self, message_type: str, cause: BaseException):
        self.message_type = message_type
        self.reason = f"{type(cause).__name__}: {cause}"
        super().__init__(f"not a {message_type} ({self.reason})")


def decode_attitude(raw, fallback: Callable) -> AttitudeFields:
    """Stamp and quaternion of the CDR bytes of a geometry_msgs/QuaternionStamped.

    Parameters
    ----------
    raw : bytes
        The serialised message.
    fallback : callable
        ``fallback(raw)`` returns the message object (fields ``header.stamp``, ``quaternion``) of
        bytes the struct reader refuses, or raises.

    Raises
    ------
    UndecodableMessage
        If neither the struct reader nor ``fallback`` reads ``raw``.
    """
    try:
        return quaternion_stamped_fields(raw)
    except ValueError:
        pass
    try:
        return AttitudeFields.of_message(fallback(raw))
    except Exception as exc:  # the deserialisers raise many kinds (RuntimeError, struct ...)
        raise UndecodableMessage(QUATERNION_STAMPED, exc) from None


def decode_odometry(raw, fallback: Callable) -> OdometryFields:
    """Stamp, frames, pose and linear velocity of the CDR bytes of a nav_msgs/Odometry.

    Parameters
    ----------
    raw : bytes
        The serialised message.
    fallback : callable
        ``fallback(raw)`` returns the Odometry message object of bytes the struct reader refuses,
        or raises.

    Raises
    ------
    UndecodableMessage
        If neither the struct reader nor ``fallback`` reads ``raw``.
    """
    try:
        return odometry_fields(raw)
    except ValueError:
        pass
    try:
        return OdometryFields.of_message(fallback(raw))
    except Exception as exc:  # the deserialisers raise many kinds (RuntimeError, struct ...)
        raise UndecodableMessage(ODOMETRY, exc) from None


def decode_joint_state(raw, deserialise: Callable) -> JointStateFields:
    """Stamp, names and positions of the CDR bytes of a sensor_msgs/JointState: the struct
    reader's, or ``deserialise(raw)``'s (the full deserialiser) where it refuses them.

    Raises
    ------
    UndecodableMessage
        If neither reads ``raw``.
    """
    try:
        return joint_state_fields(raw)
    except ValueError:
        pass
    try:
        return JointStateFields.of_message(deserialise(raw))
    except Exception as exc:  # the deserialisers raise many kinds (RuntimeError, struct ...)
        raise UndecodableMessage(JOINT_STATE, exc) from None
