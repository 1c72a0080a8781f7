"""The struct-based CDR readers and writer against two independent codecs: rosbags (pure Python)
and rclpy's (the RMW's C typesupport, what the node's peers actually send)."""

import math

import numpy as np
import pytest
from geometry_msgs.msg import Quaternion, QuaternionStamped, WrenchStamped
from rclpy.serialization import deserialize_message, serialize_message

from adbsat_ros import bag_io
from adbsat_ros.stamped_cdr import Stamp, header_stamp, quaternion_stamped_fields, wrench_stamped_cdr

FRAMES = ("", "b", "eci", "body", "sat_body_frame", "frame_ñ")  # every length mod 8, and UTF-8
STAMPS_NS = (0, 1_767_225_600_123_456_789, 2**31 * 10**9 - 1)
Q = [0.1, -0.2, 0.3, math.sqrt(1 - 0.14)]


@pytest.mark.parametrize("little_endian", [True, False])
def test_quaternion_stamped_read_equals_rosbags(little_endian):
    for frame in FRAMES:
        for stamp in STAMPS_NS:
            t = bag_io.time_message(stamp)
            msg = bag_io.quaternion_stamped_message(stamp, frame, Q)
            raw = bytes(bag_io.TYPESTORE.serialize_cdr(msg, bag_io.QUATERNION_STAMPED, little_endian=little_endian))
            assert header_stamp(raw) == Stamp(t.sec, t.nanosec)
            back = bag_io.deserialize(raw, bag_io.QUATERNION_STAMPED)
            q = back.quaternion
            assert quaternion_stamped_fields(raw) == (Stamp(t.sec, t.nanosec), [q.x, q.y, q.z, q.w])


def test_wrench_stamped_write_equals_rosbags_byte_for_byte():
    for frame in FRAMES:
        for stamp in STAMPS_NS:
            t = bag_io.time_message(stamp)
            force, torque = np.array([1.5, -2.0, 3e-300]), [4.0, -0.0, math.nan]
            raw = bytes(bag_io.serialize(bag_io.wrench_stamped_message(stamp, frame, force, torque)))
            assert wrench_stamped_cdr(t.sec, t.nanosec, frame, force, torque) == raw


def test_rclpy_bytes_are_read_and_ours_are_read_by_rclpy():
    for frame in FRAMES:
        msg = QuaternionStamped()
        msg.header.frame_id = frame
        msg.header.stamp.sec, msg.header.stamp.nanosec = 1_767_225_600, 999_999_999
        msg.quaternion = Quaternion(x=Q[0], y=Q[1], z=Q[2], w=Q[3])
        assert quaternion_stamped_fields(serialize_message(msg)) == (Stamp(1_767_225_600, 999_999_999), Q)

        force, torque = [1.0, -2.5, 1e-12], [0.0, 7.25, -3.0]
        back = deserialize_message(wrench_stamped_cdr(-5, 42, frame, force, torque), WrenchStamped)
        assert (back.header.stamp.sec, back.header.stamp.nanosec, back.header.frame_id) == (-5, 42, frame)
        f, m = back.wrench.force, back.wrench.torque
        assert [f.x, f.y, f.z, m.x, m.y, m.z] == force + torque


def test_anything_but_a_plain_cdr_quaternion_stamped_is_refused():
    raw = bytes(bag_io.serialize(bag_io.quaternion_stamped_message(10**9, "eci", Q)))
    wrench = bytes(bag_io.serialize(bag_io.wrench_stamped_message(10**9, "eci", [0, 0, 0], [0, 0, 0])))
    xcdr2 = b"\x00\x07" + raw[2:]  # XCDR2 little endian: other alignment rules
    bad_string = raw[:15] + b"\x40" + raw[16:]  # frame_id length past the end
    no_nul = bytearray(raw)
    no_nul[16 + 3] = ord("x")  # the frame_id's NUL overwritten
    for bad in (raw[:-8], raw + b"\x00" * 8, wrench, xcdr2, bad_string, bytes(no_nul), b"", raw[:11]):
        with pytest.raises(ValueError):
            quaternion_stamped_fields(bad)
    for bad in (xcdr2, raw[:11]):
        with pytest.raises(ValueError):
            header_stamp(bad)
