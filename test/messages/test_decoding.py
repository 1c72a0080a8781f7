"""Decoding input messages with the caller's deserialiser (here rosbags', no ROS): the attitude
by the struct codec first and the deserialiser for the bytes it refuses, the state and the joint
states by the deserialiser, one named error for bytes that are not the message."""

import pytest
from cdr_cases import FRAMES, POSITION, STAMPS_NS, VELOCITY, Q, odometry

from adbsat_ros.bags import io as bag_io
from adbsat_ros.messages.cdr import AttitudeFields, Stamp
from adbsat_ros.messages.decoding import (
    JointStateFields,
    OdometryFields,
    UndecodableMessage,
    decode_attitude,
    decode_joint_state,
    decode_odometry,
)


class Counted:
    """A deserialiser that counts its calls."""

    def __init__(self, deserialize):
        self.deserialize = deserialize
        self.calls = 0

    def __call__(self, raw):
        self.calls += 1
        return self.deserialize(raw)


@pytest.mark.parametrize("little_endian", [True, False])
def test_plain_cdr_attitudes_are_read_without_the_deserialiser(little_endian):
    attitudes = Counted(bag_io.deserialize_attitude)
    for frame in FRAMES:
        msg = bag_io.quaternion_stamped_message(1_767_225_600_000_000_005, frame, Q)
        raw = bytes(
            bag_io.TYPESTORE.serialize_cdr(
                msg, bag_io.QUATERNION_STAMPED, little_endian=little_endian
            )
        )
        assert decode_attitude(raw, attitudes) == AttitudeFields(Stamp(1_767_225_600, 5), Q, frame)
    assert attitudes.calls == 0


def test_attitude_bytes_the_codec_refuses_go_to_the_deserialiser_with_the_same_fields():
    """Trailing bytes (which rosbags accepts up to 3 of) are refused by the struct reader and
    read by the deserialiser, to the fields of the message."""
    attitudes = Counted(bag_io.deserialize_attitude)
    for frame in FRAMES:
        raw = bytes(bag_io.serialize(bag_io.quaternion_stamped_message(10**9 + 7, frame, Q)))
        fields = decode_attitude(raw + bytes(3), attitudes)
        assert fields == (Stamp(1, 7), Q, frame) and isinstance(fields, AttitudeFields)
    assert attitudes.calls == len(FRAMES)


@pytest.mark.parametrize("little_endian", [True, False])
def test_odometry_fields_are_the_messages(little_endian):
    for frame in FRAMES:
        for child in FRAMES:
            for stamp in STAMPS_NS[1:]:
                t = bag_io.time_message(stamp)
                msg = odometry(stamp, frame, child)
                raw = bytes(
                    bag_io.TYPESTORE.serialize_cdr(
                        msg, bag_io.ODOMETRY, little_endian=little_endian
                    )
                )
                fields = decode_odometry(raw, bag_io.deserialize_odometry)
                assert fields == OdometryFields(
                    Stamp(t.sec, t.nanosec), frame, child, POSITION, tuple(Q), VELOCITY
                )
                assert fields == OdometryFields.of_message(msg)


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
def test_joint_state_fields_are_the_messages(little_endian, names, positions, velocities, efforts):
    """Names of every length mod 4, each float64 sequence empty or not, either byte order."""
    for frame in FRAMES:
        for stamp in STAMPS_NS:
            t = bag_io.time_message(stamp)
            msg = bag_io.joint_state_message(stamp, frame, names, positions, velocities, efforts)
            raw = bytes(
                bag_io.TYPESTORE.serialize_cdr(msg, bag_io.JOINT_STATE, little_endian=little_endian)
            )
            fields = decode_joint_state(raw, bag_io.deserialize_joint_state)
            assert fields == JointStateFields(Stamp(t.sec, t.nanosec), names, positions)


def test_joint_states_with_rclpys_tail_are_read():
    """rclpy's serialiser leaves up to 12 bytes after a JointState's last field (a bag recorded
    live has them): read past, up to 15; more is no JointState."""
    msg = bag_io.joint_state_message(10**9 + 3, "body", ("left", "right"), (0.1, 0.2), (), (1, 2))
    raw = bytes(bag_io.serialize(msg))
    expected = JointStateFields(Stamp(1, 3), ("left", "right"), (0.1, 0.2))
    for tail in range(16):
        assert decode_joint_state(raw + b"\x07" * tail, bag_io.deserialize_joint_state) == expected
    with pytest.raises(UndecodableMessage, match="not a sensor_msgs/msg/JointState"):
        decode_joint_state(raw + bytes(16), bag_io.deserialize_joint_state)


def test_joint_torques_are_written_as_rosbags_writes_a_joint_state():
    names, positions, efforts = ("wing_left_hinge", "fin"), (0.1, -0.2), (4.0, -0.0)
    for frame in FRAMES:
        for stamp in STAMPS_NS:
            t = bag_io.time_message(stamp)
            raw = bag_io.joint_state_cdr(Stamp(t.sec, t.nanosec), frame, names, positions, efforts)
            msg = bag_io.joint_state_message(stamp, frame, names, positions, (), efforts)
            assert raw == bytes(bag_io.serialize(msg))


def test_bytes_that_are_not_the_message_raise_one_named_error():
    attitude = bytes(bag_io.serialize(bag_io.quaternion_stamped_message(10**9, "eci", Q)))
    state = bytes(bag_io.serialize(odometry(10**9, "eci", "eci")))
    joints = bytes(bag_io.serialize(bag_io.joint_state_message(10**9, "b", ("a",), (1.0,))))
    xcdr2 = b"\x00\x07" + state[2:]  # XCDR2 little endian, which rosbags does not read
    for raw, decode, deserialise, name in (
        (attitude + bytes(8), decode_attitude, bag_io.deserialize_attitude, "QuaternionStamped"),
        (b"\x00\x01\x00\x00" + b"\xff" * 12, decode_attitude, bag_io.deserialize_attitude, "Qu"),
        (state, decode_attitude, bag_io.deserialize_attitude, "QuaternionStamped"),
        (attitude, decode_odometry, bag_io.deserialize_odometry, "Odometry"),
        (state + bytes(8), decode_odometry, bag_io.deserialize_odometry, "Odometry"),
        (xcdr2, decode_odometry, bag_io.deserialize_odometry, "Odometry"),
        (b"", decode_odometry, bag_io.deserialize_odometry, "Odometry"),
        (joints[:20], decode_joint_state, bag_io.deserialize_joint_state, "JointState"),
        (attitude, decode_joint_state, bag_io.deserialize_joint_state, "JointState"),
    ):
        with pytest.raises(UndecodableMessage) as info:
            decode(raw, deserialise)
        assert name in info.value.message_type and name in str(info.value)
        assert info.value.reason  # what the deserialiser said, "ExceptionName: text"
