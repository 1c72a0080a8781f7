"""The struct-based CDR readers and writer against two independent codecs: rosbags (pure Python)
and rclpy's (the RMW's C typesupport, what the node's peers actually send)."""

import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

import math

import numpy as np
from geometry_msgs.msg import Quaternion, QuaternionStamped, WrenchStamped
from nav_msgs.msg import Odometry
from rclpy.serialization import deserialize_message, serialize_message

from adbsat_ros.bags import io as bag_io
from adbsat_ros.messages.cdr import (
    DiagnosticFields,
    OdometryFields,
    Stamp,
    diagnostic_array_cdr,
    header_stamp,
    odometry_fields,
    quaternion_stamped_fields,
    wrench_stamped_cdr,
)

FRAMES = ("", "b", "eci", "body", "sat_body_frame", "frame_ñ")  # every length mod 8, and UTF-8
STAMPS_NS = (0, 1_767_225_600_123_456_789, 2**31 * 10**9 - 1)
Q = [0.1, -0.2, 0.3, math.sqrt(1 - 0.14)]


@pytest.mark.parametrize("little_endian", [True, False])
def test_quaternion_stamped_read_equals_rosbags(little_endian):
    for frame in FRAMES:
        for stamp in STAMPS_NS:
            t = bag_io.time_message(stamp)
            msg = bag_io.quaternion_stamped_message(stamp, frame, Q)
            raw = bytes(
                bag_io.TYPESTORE.serialize_cdr(
                    msg, bag_io.QUATERNION_STAMPED, little_endian=little_endian
                )
            )
            assert header_stamp(raw) == Stamp(t.sec, t.nanosec)
            back = bag_io.deserialize(raw, bag_io.QUATERNION_STAMPED)
            q = back.quaternion
            assert quaternion_stamped_fields(raw) == (Stamp(t.sec, t.nanosec), [q.x, q.y, q.z, q.w])


def test_wrench_stamped_write_equals_rosbags_byte_for_byte():
    for frame in FRAMES:
        for stamp in STAMPS_NS:
            t = bag_io.time_message(stamp)
            force, torque = np.array([1.5, -2.0, 3e-300]), [4.0, -0.0, math.nan]
            raw = bytes(
                bag_io.serialize(bag_io.wrench_stamped_message(stamp, frame, force, torque))
            )
            assert wrench_stamped_cdr(t.sec, t.nanosec, frame, force, torque) == raw


def test_rclpy_bytes_are_read_and_ours_are_read_by_rclpy():
    for frame in FRAMES:
        msg = QuaternionStamped()
        msg.header.frame_id = frame
        msg.header.stamp.sec, msg.header.stamp.nanosec = 1_767_225_600, 999_999_999
        msg.quaternion = Quaternion(x=Q[0], y=Q[1], z=Q[2], w=Q[3])
        assert quaternion_stamped_fields(serialize_message(msg)) == (
            Stamp(1_767_225_600, 999_999_999),
            Q,
        )

        force, torque = [1.0, -2.5, 1e-12], [0.0, 7.25, -3.0]
        back = deserialize_message(wrench_stamped_cdr(-5, 42, frame, force, torque), WrenchStamped)
        assert (back.header.stamp.sec, back.header.stamp.nanosec, back.header.frame_id) == (
            -5,
            42,
            frame,
        )
        f, m = back.wrench.force, back.wrench.torque
        assert [f.x, f.y, f.z, m.x, m.y, m.z] == force + torque


def test_anything_but_a_plain_cdr_quaternion_stamped_is_refused():
    raw = bytes(bag_io.serialize(bag_io.quaternion_stamped_message(10**9, "eci", Q)))
    wrench = bytes(
        bag_io.serialize(bag_io.wrench_stamped_message(10**9, "eci", [0, 0, 0], [0, 0, 0]))
    )
    xcdr2 = b"\x00\x07" + raw[2:]  # XCDR2 little endian: other alignment rules
    bad_string = raw[:15] + b"\x40" + raw[16:]  # frame_id length past the end
    no_nul = bytearray(raw)
    no_nul[16 + 3] = ord("x")  # the frame_id's NUL overwritten
    for bad in (
        raw[:-8],
        raw + b"\x00" * 8,
        wrench,
        xcdr2,
        bad_string,
        bytes(no_nul),
        b"",
        raw[:11],
    ):
        with pytest.raises(ValueError):
            quaternion_stamped_fields(bad)
    for bad in (xcdr2, raw[:11]):
        with pytest.raises(ValueError):
            header_stamp(bad)


POSITION, VELOCITY = (6678137.0, -1.5e-3, 2.5e5), (-0.25, 7725.8, 1e-300)


def _odometry(stamp_ns, frame, child):
    """A rosbags Odometry with every field distinct, covariances included."""
    msg = bag_io.odometry_message(stamp_ns, frame, child, POSITION, VELOCITY, orientation_xyzw=Q)
    msg.pose.covariance[:] = np.arange(36.0)
    msg.twist.covariance[:] = -np.arange(36.0)
    msg.twist.twist.angular.x, msg.twist.twist.angular.y, msg.twist.twist.angular.z = (
        1e-3,
        -2e-3,
        3e-3,
    )
    return msg


@pytest.mark.parametrize("little_endian", [True, False])
def test_odometry_read_equals_rosbags(little_endian):
    for frame in FRAMES:
        for child in FRAMES:
            for stamp in STAMPS_NS[1:]:
                t = bag_io.time_message(stamp)
                raw = bytes(
                    bag_io.TYPESTORE.serialize_cdr(
                        _odometry(stamp, frame, child), bag_io.ODOMETRY, little_endian=little_endian
                    )
                )
                fields = odometry_fields(raw)
                assert fields == OdometryFields.of_message(bag_io.deserialize(raw, bag_io.ODOMETRY))
                assert fields == (
                    Stamp(t.sec, t.nanosec),
                    frame,
                    child,
                    POSITION,
                    tuple(Q),
                    VELOCITY,
                )


def test_odometry_from_rclpy_bytes():
    for frame in FRAMES:
        msg = Odometry()
        msg.header.frame_id, msg.child_frame_id = frame, frame[::-1]
        msg.header.stamp.sec, msg.header.stamp.nanosec = 1_767_225_600, 5
        p, o, v = msg.pose.pose.position, msg.pose.pose.orientation, msg.twist.twist.linear
        p.x, p.y, p.z = POSITION
        o.x, o.y, o.z, o.w = Q
        v.x, v.y, v.z = VELOCITY
        msg.pose.covariance[7] = 9.0
        fields = odometry_fields(serialize_message(msg))
        assert fields == OdometryFields.of_message(msg)
        assert fields.frame_id == frame and fields.child_frame_id == frame[::-1]


def test_anything_but_a_plain_cdr_odometry_is_refused():
    raw = bytes(bag_io.serialize(_odometry(10**9, "eci", "body")))
    xcdr2 = b"\x00\x07" + raw[2:]
    no_nul = bytearray(raw)
    no_nul[16 + 3] = ord("x")  # header.frame_id "eci" loses its NUL
    child_too_long = bytearray(raw)
    child_too_long[20:24] = (10**6).to_bytes(4, "little")  # child_frame_id length past the end
    not_utf8 = bytearray(raw)
    not_utf8[16] = 0xFF
    quaternion = bytes(bag_io.serialize(bag_io.quaternion_stamped_message(10**9, "eci", Q)))
    for bad in (
        raw[:-8],
        raw + b"\x00" * 8,
        xcdr2,
        bytes(no_nul),
        bytes(child_too_long),
        bytes(not_utf8),
        quaternion,
        b"",
        raw[:13],
        raw[:22],
    ):
        with pytest.raises(ValueError):
            odometry_fields(bad)


def test_diagnostic_array_write_equals_rosbags_byte_for_byte_and_reads_back_in_rclpy():
    """Strings of every length mod 4 (their NUL and the padding after them), UTF-8, no values,
    several statuses, each level. (rclpy's own serialiser leaves padding bytes uninitialised, so
    against rclpy the fields are compared after its deserialiser has read our bytes.)"""
    from diagnostic_msgs.msg import DiagnosticArray

    statuses = [
        DiagnosticFields(level, name, message, hardware, values)
        for level, (name, message, hardware, values) in enumerate(
            [
                (
                    "adbsat_node: aerodynamic wrench",
                    "ok",
                    "satellite.obj",
                    (("gsi_model", "sentman"), ("a", "")),
                ),
                ("n", "", "ñ", ()),
                (
                    "",
                    "state is stale (1.5 s old)",
                    "example",
                    (("rejected_non_finite", "12"), ("b", "é")),
                ),
                ("abcd", "abc", "ab", (("k", "v"), ("kk", "vv"), ("kkk", "vvv"))),
            ]
        )
    ]
    for frame in FRAMES:
        for count in range(len(statuses) + 1):
            raw = diagnostic_array_cdr(1_767_225_600, 5, frame, statuses[:count])
            ours = bag_io.diagnostic_array_message(
                1_767_225_600 * 10**9 + 5,
                [
                    bag_io.diagnostic_status(
                        f.level, f.name, f.message, f.hardware_id, dict(f.values)
                    )
                    for f in statuses[:count]
                ],
            )
            ours.header.frame_id = frame
            assert raw == bytes(bag_io.serialize(ours))
            back = deserialize_message(raw, DiagnosticArray)
            assert (back.header.stamp.sec, back.header.stamp.nanosec, back.header.frame_id) == (
                1_767_225_600,
                5,
                frame,
            )
            assert [
                (
                    s.level[0],
                    s.name,
                    s.message,
                    s.hardware_id,
                    tuple((kv.key, kv.value) for kv in s.values),
                )
                for s in back.status
            ] == [tuple(f) for f in statuses[:count]]
