"""CDR bytes of the stamped messages on the wrench's hot path, read and written with ``struct``.

The ROS node takes its attitudes and publishes its wrenches as serialised bytes, and the bag
analysis reads and writes the same messages from files; both go through these functions instead
of building message objects. Building them is most of a message's cost in Python
(docs/benchmarks.md, messages). sensor_msgs/JointState is read so too.

Layout (OMG CDR, "plain" XCDR1, what rclpy, Fast DDS and rosbags write): a 4-byte encapsulation
header (0x00 0x00 big endian, 0x00 0x01 little endian, then two option bytes), then the fields in
order, each aligned to its own size counted from the end of the encapsulation header. A message
that opens with a std_msgs/Header starts with the stamp (int32 sec, uint32 nanosec) and the
frame_id string (uint32 length including the NUL, bytes, NUL). Anything else (XCDR2, another
type) is refused with ValueError, and callers then decode it with a full codec, which either
understands it or says what is wrong.
"""

from __future__ import annotations

import functools
import struct
from typing import NamedTuple

#: CDR encapsulation header of little-endian plain CDR (what rosbags and rclpy write).
CDR_LE_HEADER = b"\x00\x01\x00\x00"


class Stamp(NamedTuple):
    """A builtin_interfaces/Time as two integers (the fields of the message of that name)."""

    sec: int
    nanosec: int


def header_stamp(raw) -> Stamp:
    """The header stamp of a CDR-serialised stamped message.

    Reads 12 bytes instead of decoding the message: valid for every message whose first field is
    a std_msgs/Header (Odometry, QuaternionStamped, WrenchStamped ...).

    Raises
    ------
    ValueError
        If ``raw`` is too short or not plain CDR.
    """
    if len(raw) < 12 or raw[0] != 0 or raw[1] not in (0, 1):
        raise ValueError("not a plain-CDR stamped message")
    return Stamp._make(struct.unpack_from("<iI" if raw[1] == 1 else ">iI", raw, 4))


class AttitudeFields(NamedTuple):
    """What the wrench needs of a geometry_msgs/QuaternionStamped (field names as in it)."""

    stamp: Stamp
    """header.stamp."""
    quaternion_xyzw: list
    """quaternion x, y, z, w as sent (float64): the body's orientation in the state frame."""

    @classmethod
    def of_message(cls, msg) -> "AttitudeFields":
        """The fields of a QuaternionStamped message object (rclpy's or rosbags')."""
        q = msg.quaternion
        return cls(Stamp(msg.header.stamp.sec, msg.header.stamp.nanosec), [q.x, q.y, q.z, q.w])


def quaternion_stamped_fields(raw) -> AttitudeFields:
    """Header stamp and quaternion of a CDR-serialised geometry_msgs/QuaternionStamped.

    Returns
    -------
    AttitudeFields
        The stamp, and the four float64 values of the quaternion as sent, order x, y, z, w.

    Raises
    ------
    ValueError
        If ``raw`` is not exactly a plain-CDR QuaternionStamped.
    """
    if len(raw) < 16 or raw[0] != 0 or raw[1] not in (0, 1):
        raise ValueError("not a plain-CDR stamped message")
    order = "<" if raw[1] == 1 else ">"
    sec, nanosec, length = struct.unpack_from(order + "iII", raw, 4)
    end = 16 + length  # after frame_id (length counts its NUL)
    start = end + (-(end - 4) % 8)  # the float64s align to 8 from the end of the encapsulation
    if length < 1 or len(raw) != start + 32 or raw[end - 1] != 0:
        raise ValueError("not a QuaternionStamped")
    return AttitudeFields(Stamp(sec, nanosec), list(struct.unpack_from(order + "4d", raw, start)))


class OdometryFields(NamedTuple):
    """What the wrench needs of a nav_msgs/Odometry (the covariances and the angular rate are
    left out). Field names follow the message."""

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


#: float64 values after Odometry's two strings: pose (position 3, orientation 4, covariance 36),
#: twist (linear 3, angular 3, covariance 36).
_ODOMETRY_FLOAT64S = 85
#: Index of twist.twist.linear.x among them.
_ODOMETRY_LINEAR = 43


def _cdr_string(raw, order: str, pos: int) -> tuple[str, int]:
    """The CDR string whose length field is at ``pos`` rounded up to a multiple of 4 (counted
    from the end of the encapsulation header), and the position after its NUL."""
    pos += -(pos - 4) % 4
    if pos + 4 > len(raw):
        raise ValueError("message ends inside a string length")
    (length,) = struct.unpack_from(order + "I", raw, pos)
    end = pos + 4 + length
    if length < 1 or end > len(raw) or raw[end - 1] != 0:
        raise ValueError("not a NUL-terminated CDR string")
    return raw[pos + 4 : end - 1].decode("utf-8"), end


def odometry_fields(raw) -> OdometryFields:
    """Stamp, frame ids, position, orientation and linear velocity of a CDR-serialised
    nav_msgs/Odometry.

    Raises
    ------
    ValueError
        If ``raw`` is not exactly a plain-CDR Odometry (UnicodeDecodeError, a ValueError, for a
        frame id that is not UTF-8).
    """
    if len(raw) < 16 or raw[0] != 0 or raw[1] not in (0, 1):
        raise ValueError("not a plain-CDR stamped message")
    order = "<" if raw[1] == 1 else ">"
    sec, nanosec = struct.unpack_from(order + "iI", raw, 4)
    frame_id, pos = _cdr_string(raw, order, 12)
    child_frame_id, pos = _cdr_string(raw, order, pos)
    start = pos + (-(pos - 4) % 8)  # the float64s align to 8 from the end of the encapsulation
    if len(raw) != start + 8 * _ODOMETRY_FLOAT64S:
        raise ValueError("not an Odometry")
    pose = struct.unpack_from(order + "7d", raw, start)
    linear = struct.unpack_from(order + "3d", raw, start + 8 * _ODOMETRY_LINEAR)
    return OdometryFields(Stamp(sec, nanosec), frame_id, child_frame_id, pose[:3], pose[3:], linear)


@functools.lru_cache(maxsize=64)
def _wrench_stamped_layout(frame_id: str):
    name = frame_id.encode("utf-8") + b"\x00"
    # encapsulation (4) + sec, nanosec (8) + string length (4) + name; the six float64 start on a
    # multiple of 8 counted from the end of the encapsulation header
    pad = -(12 + len(name)) % 8
    return struct.Struct(f"<4siII{len(name)}s{pad}x6d"), name


def wrench_stamped_cdr(sec: int, nanosec: int, frame_id: str, force, torque) -> bytes:
    """CDR bytes (little endian) of a geometry_msgs/WrenchStamped.

    Byte for byte what rosbags serialises for the same message; rclpy's serialiser differs only
    in the padding bytes before the float64s, which it leaves uninitialised.

    Parameters
    ----------
    sec, nanosec : int
        Header stamp (builtin_interfaces/Time).
    frame_id : str
    force, torque : sequence of 3 float
        Force [N] and torque [N m] (or coefficients), written as float64.
    """
    layout, name = _wrench_stamped_layout(frame_id)
    return layout.pack(CDR_LE_HEADER, sec, nanosec, len(name), name, *force, *torque)


def accel_stamped_cdr(sec: int, nanosec: int, frame_id: str, linear, angular) -> bytes:
    """CDR bytes of a geometry_msgs/AccelStamped: a header and two Vector3 (linear [m/s^2],
    angular [rad/s^2]), the layout of a WrenchStamped, so the same bytes."""
    return wrench_stamped_cdr(sec, nanosec, frame_id, linear, angular)


class DiagnosticFields(NamedTuple):
    """The fields of one diagnostic_msgs/DiagnosticStatus: level (OK 0, WARN 1, ERROR 2, STALE 3),
    name, message, hardware_id, and the values as (key, value) string pairs."""

    level: int
    name: str
    message: str
    hardware_id: str
    values: tuple


def _put_string(parts: list, offset: int, text: str) -> int:
    """Append a CDR string (4-aligned uint32 length including the NUL, bytes, NUL) at ``offset``
    (counted from the end of the encapsulation header); return the offset after it."""
    data = text.encode("utf-8") + b"\x00"
    pad = -offset % 4
    parts.append(b"\x00" * pad + struct.pack("<I", len(data)) + data)
    return offset + pad + 4 + len(data)


def _put_count(parts: list, offset: int, count: int) -> int:
    """Append a 4-aligned CDR uint32 (a sequence length) at ``offset``; return the offset
    after it."""
    pad = -offset % 4
    parts.append(b"\x00" * pad + struct.pack("<I", count))
    return offset + pad + 4


def diagnostic_array_cdr(sec: int, nanosec: int, frame_id: str, statuses) -> bytes:
    """CDR bytes (little endian) of a diagnostic_msgs/DiagnosticArray.

    The node's once-a-second /diagnostics message: building it as rclpy message objects and
    serialising them would hold up the attitude messages behind it at 1 kHz.

    Parameters
    ----------
    sec, nanosec : int
        Header stamp.
    frame_id : str
    statuses : sequence of DiagnosticFields
    """
    parts = [CDR_LE_HEADER, struct.pack("<iI", sec, nanosec)]
    offset = _put_count(parts, _put_string(parts, 8, frame_id), len(statuses))
    for status in statuses:
        parts.append(struct.pack("<B", status.level))  # byte level, then strings (4-aligned)
        offset += 1
        for text in (status.name, status.message, status.hardware_id):
            offset = _put_string(parts, offset, text)
        offset = _put_count(parts, offset, len(status.values))
        for key, value in status.values:
            offset = _put_string(parts, offset, key)
            offset = _put_string(parts, offset, value)
    return b"".join(parts)


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


def _cdr_count(raw, order: str, pos: int) -> tuple[int, int]:
    """The CDR sequence length (uint32) at ``pos`` rounded up to a multiple of 4 (counted from
    the end of the encapsulation header), and the position after it."""
    pos += -(pos - 4) % 4
    if pos + 4 > len(raw):
        raise ValueError("message ends inside a sequence length")
    return struct.unpack_from(order + "I", raw, pos)[0], pos + 4


def _cdr_doubles(raw, order: str, pos: int) -> tuple[tuple, int]:
    """The CDR float64 sequence at ``pos`` (its 4-aligned length, then 8-aligned values) and
    the position after it."""
    count, pos = _cdr_count(raw, order, pos)
    if count == 0:
        return (), pos
    pos += -(pos - 4) % 8
    end = pos + 8 * count
    if end > len(raw):
        raise ValueError("message ends inside a float64 sequence")
    return struct.unpack_from(f"{order}{count}d", raw, pos), end


def joint_state_fields(raw) -> JointStateFields:
    """Stamp, joint names and positions of a CDR-serialised sensor_msgs/JointState (its
    velocities and efforts are read past, not kept), without rclpy's message object, for a
    joint_states stream as fast as the attitudes.

    Raises
    ------
    ValueError
        If ``raw`` is not a plain-CDR JointState, with at most 15 bytes after its last field
        (UnicodeDecodeError, a ValueError, for a name that is not UTF-8).
    """
    if len(raw) < 16 or raw[0] != 0 or raw[1] not in (0, 1):
        raise ValueError("not a plain-CDR stamped message")
    order = "<" if raw[1] == 1 else ">"
    sec, nanosec = struct.unpack_from(order + "iI", raw, 4)
    _, pos = _cdr_string(raw, order, 12)  # header.frame_id
    count, pos = _cdr_count(raw, order, pos)
    if 4 * count > len(raw) - pos:  # (each name takes four bytes at least)
        raise ValueError("more names than the message holds")
    names = []
    for _ in range(count):
        name, pos = _cdr_string(raw, order, pos)
        names.append(name)
    positions, pos = _cdr_doubles(raw, order, pos)
    _, pos = _cdr_doubles(raw, order, pos)  # velocity
    _, pos = _cdr_doubles(raw, order, pos)  # effort
    if not 0 <= len(raw) - pos < 16:  # (rclpy's serialiser leaves up to 12 bytes after it)
        raise ValueError("not a JointState")
    return JointStateFields(Stamp(sec, nanosec), tuple(names), positions)


def _put_doubles(parts: list, offset: int, values) -> int:
    """Append a CDR float64 sequence (4-aligned count, then 8-aligned values); return the
    offset after it."""
    values = [float(x) for x in values]
    offset = _put_count(parts, offset, len(values))
    if values:
        pad = -offset % 8
        parts.append(b"\x00" * pad + struct.pack(f"<{len(values)}d", *values))
        offset += pad + 8 * len(values)
    return offset


@functools.lru_cache(maxsize=64)
def _joint_state_layout(frame_id: str, names: tuple, positions: int, efforts: int):
    """The struct of a JointState with these frame and names, ``positions`` positions, no
    velocities and ``efforts`` efforts: everything but the stamp and the numbers is fixed."""
    parts = []
    offset = _put_count(parts, _put_string(parts, 8, frame_id), len(names))
    for name in names:
        offset = _put_string(parts, offset, name)
    middle = b"".join(parts)
    fmt = f"<4siI{len(middle)}s"
    for count in (positions, 0, efforts):
        pad = -offset % 4
        fmt += f"{pad}xI"
        offset += pad + 4
        if count:
            pad = -offset % 8
            fmt += f"{pad}x{count}d"
            offset += pad + 8 * count
    return struct.Struct(fmt), middle


def joint_state_cdr(
    sec: int, nanosec: int, frame_id: str, names, positions, velocities, efforts
) -> bytes:
    """CDR bytes (little endian) of a sensor_msgs/JointState.

    The node's joint_torques message, one per wrench: its layout is made once per frame and
    names (:func:`functools.lru_cache`, 64 kept).

    Parameters
    ----------
    sec, nanosec : int
        Header stamp.
    frame_id : str
    names : sequence of str
    positions, velocities, efforts : sequence of float
        Each empty or one per name.
    """
    positions = [float(x) for x in positions]
    velocities = [float(x) for x in velocities]
    efforts = [float(x) for x in efforts]
    if velocities:  # (not what the node sends: the general form)
        parts = [CDR_LE_HEADER, struct.pack("<iI", sec, nanosec)]
        offset = _put_count(parts, _put_string(parts, 8, frame_id), len(names))
        for name in names:
            offset = _put_string(parts, offset, name)
        for values in (positions, velocities, efforts):
            offset = _put_doubles(parts, offset, values)
        return b"".join(parts)
    layout, middle = _joint_state_layout(frame_id, tuple(names), len(positions), len(efforts))
    return layout.pack(
        CDR_LE_HEADER,
        sec,
        nanosec,
        middle,
        len(positions),
        *positions,
        0,
        len(efforts),
        *efforts,
    )
