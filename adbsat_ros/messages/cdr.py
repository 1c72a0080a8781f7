"""The one hand-made codec, with ``struct``: CDR bytes of QuaternionStamped in, WrenchStamped and
AccelStamped out, without message objects (docs/benchmarks.md). Plain CDR (XCDR1): a 4-byte
encapsulation header, fields aligned to their size from its end; a std_msgs/Header is int32 sec,
uint32 nanosec, frame_id (uint32 length with the NUL, bytes, NUL). Else ValueError (full codec)."""

from __future__ import annotations

import struct
from typing import NamedTuple

#: CDR encapsulation header of little-endian plain CDR (what rosbags and rclpy write).
CDR_LE_HEADER = b"\x00\x01\x00\x00"


class Stamp(NamedTuple):
    """A builtin_interfaces/Time as two integers (the fields of the message of that name)."""

    sec: int
    nanosec: int


def header_stamp(raw) -> Stamp:
    """The header stamp of a CDR message starting with a std_msgs/Header; ValueError if not one."""
    if len(raw) < 12 or raw[0] != 0 or raw[1] not in (0, 1):
        raise ValueError("not a plain-CDR stamped message")
    return Stamp._make(struct.unpack_from("<iI" if raw[1] == 1 else ">iI", raw, 4))


class AttitudeFields(NamedTuple):
    """What the wrench needs of a geometry_msgs/QuaternionStamped (field names as in it)."""

    stamp: Stamp
    """header.stamp."""
    quaternion_xyzw: list
    """quaternion x, y, z, w as sent (float64): the body's orientation in the state frame."""
    frame_id: str = ""
    """header.frame_id: the frame the orientation is given in (the state frame)."""

    @classmethod
    def of_message(cls, msg) -> "AttitudeFields":
        """The fields of a QuaternionStamped message object (rclpy's or rosbags')."""
        q, header = msg.quaternion, msg.header
        stamp = Stamp(header.stamp.sec, header.stamp.nanosec)
        return cls(stamp, [q.x, q.y, q.z, q.w], header.frame_id)


def quaternion_stamped_fields(raw) -> AttitudeFields:
    """Stamp, quaternion (x, y, z, w as sent) of a plain-CDR QuaternionStamped; else ValueError."""
    if len(raw) < 16 or raw[0] != 0 or raw[1] not in (0, 1):
        raise ValueError("not a plain-CDR stamped message")
    order = "<" if raw[1] == 1 else ">"
    sec, nanosec, length = struct.unpack_from(order + "iII", raw, 4)
    end = 16 + length  # after frame_id (length counts its NUL)
    start = end + (-(end - 4) % 8)  # the float64s align to 8 from the end of the encapsulation
    if length < 1 or len(raw) != start + 32 or raw[end - 1] != 0:
        raise ValueError("not a QuaternionStamped")
    frame = bytes(raw[16 : end - 1]).decode("utf-8", "replace")
    quaternion = list(struct.unpack_from(order + "4d", raw, start))
    return AttitudeFields(Stamp(sec, nanosec), quaternion, frame)


def wrench_stamped_cdr(sec: int, nanosec: int, frame_id: str, force, torque) -> bytes:
    """CDR bytes (little endian) of a geometry_msgs/WrenchStamped, byte for byte as rosbags's.
    sec, nanosec: header stamp; force [N], torque [N m] (or coefficients): 3 floats each."""
    name = frame_id.encode("utf-8") + b"\x00"
    # encapsulation (4) + sec, nanosec (8) + string length (4) + name; the six float64 start on a
    # multiple of 8 counted from the end of the encapsulation header
    pad = -(12 + len(name)) % 8
    layout = f"<4siII{len(name)}s{pad}x6d"
    return struct.pack(layout, CDR_LE_HEADER, sec, nanosec, len(name), name, *force, *torque)


def accel_stamped_cdr(sec: int, nanosec: int, frame_id: str, linear, angular) -> bytes:
    """CDR bytes of a geometry_msgs/AccelStamped (linear [m/s^2], angular [rad/s^2]): a Wrench's."""
    return wrench_stamped_cdr(sec, nanosec, frame_id, linear, angular)


def joint_state_cdr(stamp: Stamp, frame_id: str, names, positions, efforts) -> bytes:
    """CDR bytes (little endian) of a sensor_msgs/JointState without velocities, byte for byte
    as rosbags's: the joint torques. ``stamp``: header stamp; ``names`` (J,) str; ``positions``
    [rad or m] and ``efforts`` [N m or N]: J floats each (or none)."""
    layout, values, offset = ["<4siI"], [CDR_LE_HEADER, stamp.sec, stamp.nanosec], 8
    for k, text in enumerate((frame_id, *names)):
        if k == 1:  # the names' count follows the frame_id
            offset = _field(layout, values, offset, 4, "I", 4, len(names))
        data = text.encode("utf-8") + b"\x00"
        offset = _field(layout, values, offset, 4, f"I{len(data)}s", 4 + len(data), len(data), data)
    if not names:
        offset = _field(layout, values, offset, 4, "I", 4, 0)
    for floats in (positions, (), efforts):
        floats = [float(x) for x in floats]
        offset = _field(layout, values, offset, 4, "I", 4, len(floats))
        if floats:
            offset = _field(layout, values, offset, 8, f"{len(floats)}d", 8 * len(floats), *floats)
    return struct.pack("".join(layout), *values)


def _field(layout: list, values: list, offset: int, alignment: int, code, size, *items) -> int:
    """Add a field aligned to ``alignment`` (from the encapsulation's end) at ``offset``; the
    offset after it."""
    pad = -offset % alignment
    layout.append(f"{pad}x{code}")
    values.extend(items)
    return offset + pad + size
