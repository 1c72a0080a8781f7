"""Decoding input messages: the struct codec first, the caller's full deserialiser for the bytes
it refuses, one named error for bytes neither reads (here with rosbags' deserialiser, no ROS)."""

import pytest
from cdr_cases import FRAMES, Q, odometry

from adbsat_ros.bags import io as bag_io
from adbsat_ros.messages.cdr import AttitudeFields, OdometryFields, Stamp
from adbsat_ros.messages.decoding import UndecodableMessage, decode_attitude, decode_odometry


class Counted:
    """A fallback deserialiser that counts its calls."""

    def __init__(self, deserialize):
        self.deserialize = deserialize
        self.calls = 0

    def __call__(self, raw):
        self.calls += 1
        return self.deserialize(raw)


@pytest.mark.parametrize("little_endian", [True, False])
def test_plain_cdr_is_read_without_the_fallback(little_endian):
    attitudes, odometries = (
        Counted(bag_io.deserialize_attitude),
        Counted(bag_io.deserialize_odometry),
    )
    for frame in FRAMES:
        msg = bag_io.quaternion_stamped_message(1_767_225_600_000_000_005, frame, Q)
        raw = bytes(
            bag_io.TYPESTORE.serialize_cdr(
                msg, bag_io.QUATERNION_STAMPED, little_endian=little_endian
            )
        )
        assert decode_attitude(raw, attitudes) == AttitudeFields(Stamp(1_767_225_600, 5), Q)
        msg = odometry(1_767_225_600_000_000_005, frame, "body")
        raw = bytes(
            bag_io.TYPESTORE.serialize_cdr(msg, bag_io.ODOMETRY, little_endian=little_endian)
        )
        assert decode_odometry(raw, odometries) == OdometryFields.of_message(msg)
    assert attitudes.calls == odometries.calls == 0


def test_bytes_the_codec_refuses_go_to_the_fallback_with_the_same_fields():
    """Trailing bytes (which rosbags accepts up to 3 of) are refused by the struct reader and
    read by the fallback, to the fields of the message."""
    attitudes, odometries = (
        Counted(bag_io.deserialize_attitude),
        Counted(bag_io.deserialize_odometry),
    )
    for frame in FRAMES:
        raw = bytes(bag_io.serialize(bag_io.quaternion_stamped_message(10**9 + 7, frame, Q)))
        fields = decode_attitude(raw + bytes(3), attitudes)
        assert fields == (Stamp(1, 7), Q) and isinstance(fields, AttitudeFields)
        msg = odometry(10**9 + 7, frame, frame)
        raw = bytes(bag_io.serialize(msg))
        assert decode_odometry(raw + bytes(2), odometries) == OdometryFields.of_message(msg)
    assert attitudes.calls == odometries.calls == len(FRAMES)


def test_bytes_neither_reads_raise_one_named_error():
    attitude = bytes(bag_io.serialize(bag_io.quaternion_stamped_message(10**9, "eci", Q)))
    state = bytes(bag_io.serialize(odometry(10**9, "eci", "eci")))
    for raw, decode, fallback, name in (
        (attitude + bytes(8), decode_attitude, bag_io.deserialize_attitude, "QuaternionStamped"),
        (b"\x00\x01\x00\x00" + b"\xff" * 12, decode_attitude, bag_io.deserialize_attitude, "Qu"),
        (state, decode_attitude, bag_io.deserialize_attitude, "QuaternionStamped"),
        (attitude, decode_odometry, bag_io.deserialize_odometry, "Odometry"),
        (b"", decode_odometry, bag_io.deserialize_odometry, "Odometry"),
    ):
        with pytest.raises(UndecodableMessage) as info:
            decode(raw, fallback)
        assert name in info.value.message_type and name in str(info.value)
        assert info.value.reason  # what the deserialiser said, "ExceptionName: text"
