"""The struct-based CDR readers and writers against rosbags' pure-Python codec (no ROS needed)."""

import math

import numpy as np
import pytest
from cdr_cases import DIAGNOSTIC_STATUSES, FRAMES, POSITION, STAMPS_NS, VELOCITY, Q, odometry

from adbsat_ros.bags import io as bag_io
from adbsat_ros.messages.cdr import (
    JointStateFields,
    OdometryFields,
    Stamp,
    diagnostic_array_cdr,
    header_stamp,
    joint_state_cdr,
    joint_state_fields,
    odometry_fields,
    quaternion_stamped_fields,
    wrench_stamped_cdr,
)
from adbsat_ros.messages.decoding import UndecodableMessage, decode_joint_state


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
            fields = quaternion_stamped_fields(raw)
            assert fields == (Stamp(t.sec, t.nanosec), [q.x, q.y, q.z, q.w])
            assert (fields.stamp, fields.quaternion_xyzw) == tuple(fields)


def test_wrench_stamped_write_equals_rosbags_byte_for_byte():
    for frame in FRAMES:
        for stamp in STAMPS_NS:
            t = bag_io.time_message(stamp)
            force, torque = np.array([1.5, -2.0, 3e-300]), [4.0, -0.0, math.nan]
            raw = bytes(
                bag_io.serialize(bag_io.wrench_stamped_message(stamp, frame, force, torque))
            )
            assert wrench_stamped_cdr(t.sec, t.nanosec, frame, force, torque) == raw


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


@pytest.mark.parametrize("little_endian", [True, False])
def test_odometry_read_equals_rosbags(little_endian):
    for frame in FRAMES:
        for child in FRAMES:
            for stamp in STAMPS_NS[1:]:
                t = bag_io.time_message(stamp)
                raw = bytes(
                    bag_io.TYPESTORE.serialize_cdr(
                        odometry(stamp, frame, child), bag_io.ODOMETRY, little_endian=little_endian
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


def test_anything_but_a_plain_cdr_odometry_is_refused():
    raw = bytes(bag_io.serialize(odometry(10**9, "eci", "body")))
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


def test_diagnostic_array_write_equals_rosbags_byte_for_byte():
    """Strings of every length mod 4, UTF-8, no values, several statuses, each level."""
    statuses = DIAGNOSTIC_STATUSES
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


@pytest.mark.parametrize(
    "names, positions, efforts",
    [
        ((), (), ()),
        (("hinge",), (0.25,), (-3e-5,)),
        (("wing_left_hinge", "wing_right_hinge", "fin"), (0.1, -0.2, 1e-300), (4.0, -0.0, 2.5)),
    ],
)
def test_joint_state_write_equals_rosbags_byte_for_byte(names, positions, efforts):
    """The joint_torques message: names, positions and efforts, no velocities."""
    for frame in FRAMES:
        for stamp in STAMPS_NS:
            t = bag_io.time_message(stamp)
            msg = bag_io.joint_state_message(stamp, frame, names, positions, (), efforts)
            raw = joint_state_cdr(t.sec, t.nanosec, frame, names, positions, (), efforts)
            assert raw == bytes(bag_io.serialize(msg))
            back = decode_joint_state(raw, bag_io.deserialize_joint_state)
            assert back == JointStateFields(Stamp(t.sec, t.nanosec), names, positions)


def test_bytes_that_are_no_joint_state_are_undecodable():
    raw = bytes(bag_io.serialize(bag_io.quaternion_stamped_message(10**9, "eci", Q)))
    with pytest.raises(UndecodableMessage, match="not a sensor_msgs/msg/JointState"):
        decode_joint_state(raw[:20], bag_io.deserialize_joint_state)


def test_joint_state_with_velocities_equals_rosbags_byte_for_byte():
    names, positions, velocities, efforts = ("a", "bcd"), (0.5, -1.0), (2.0, 3.5), ()
    t = bag_io.time_message(STAMPS_NS[0])
    msg = bag_io.joint_state_message(STAMPS_NS[0], "body", names, positions, velocities, efforts)
    raw = joint_state_cdr(t.sec, t.nanosec, "body", names, positions, velocities, efforts)
    assert raw == bytes(bag_io.serialize(msg))


@pytest.mark.parametrize("little_endian", [True, False])
@pytest.mark.parametrize(
    "names, positions, velocities, efforts",
    [
        ((), (), (), ()),
        (("hinge",), (0.25,), (), ()),
        (("ab", "cde", "fghi", "j"), (0.1, -0.2, 1e-300, 3.0), (1.0, 2.0, 3.0, 4.0), ()),
        (("wing_left_hinge", "wing_right_hinge"), (0.3, -0.3), (), (4.0, -0.0)),
        (("a", "b"), (), (0.5, 0.25), (1.0, 2.0)),  # names without positions
    ],
)
def test_joint_state_read_equals_rosbags(little_endian, names, positions, velocities, efforts):
    """Names of every length mod 4, each float64 sequence empty or not, either byte order."""
    for frame in FRAMES:
        for stamp in STAMPS_NS:
            t = bag_io.time_message(stamp)
            msg = bag_io.joint_state_message(stamp, frame, names, positions, velocities, efforts)
            raw = bytes(
                bag_io.TYPESTORE.serialize_cdr(msg, bag_io.JOINT_STATE, little_endian=little_endian)
            )
            fields = joint_state_fields(raw)
            assert fields == JointStateFields(Stamp(t.sec, t.nanosec), names, positions)
            assert fields == JointStateFields.of_message(bag_io.deserialize_joint_state(raw))


def test_anything_but_a_plain_cdr_joint_state_is_refused_by_the_struct_reader():
    msg = bag_io.joint_state_message(10**9, "body", ("left", "right"), (0.1, 0.2), (), (1.0, 2.0))
    raw = bytes(bag_io.serialize(msg))
    xcdr2 = b"\x00\x07" + raw[2:]
    too_many_names = bytearray(raw)
    too_many_names[24:28] = (10**6).to_bytes(4, "little")  # the name count past the end
    not_utf8 = bytearray(raw)
    not_utf8[32] = 0xFF  # in the first name
    quaternion = bytes(bag_io.serialize(bag_io.quaternion_stamped_message(10**9, "eci", Q)))
    assert joint_state_fields(raw + b"\x00" * 12) == joint_state_fields(raw)  # (rclpy's tail)
    for bad in (
        raw[:-8],
        raw + b"\x00" * 16,
        xcdr2,
        bytes(too_many_names),
        bytes(not_utf8),
        quaternion,
        b"",
        raw[:15],
        raw[:26],
    ):
        with pytest.raises(ValueError):
            joint_state_fields(bad)
    # what the struct reader refuses goes to the full deserialiser, which reads or refuses it
    with pytest.raises(UndecodableMessage, match="not a sensor_msgs/msg/JointState"):
        decode_joint_state(xcdr2, bag_io.deserialize_joint_state)
