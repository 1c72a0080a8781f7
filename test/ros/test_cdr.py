"""The struct-based CDR readers and writers against rclpy's codec (the RMW's C typesupport, what
the node's peers actually send), and the decoding with rclpy's deserialiser as the fallback."""

import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

from cdr_cases import DIAGNOSTIC_STATUSES, FRAMES, POSITION, VELOCITY, Q
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import Quaternion, QuaternionStamped, WrenchStamped
from nav_msgs.msg import Odometry
from rclpy.serialization import deserialize_message, serialize_message
from sensor_msgs.msg import JointState

from adbsat_ros.messages.cdr import (
    AttitudeFields,
    JointStateFields,
    OdometryFields,
    Stamp,
    diagnostic_array_cdr,
    joint_state_fields,
    odometry_fields,
    quaternion_stamped_fields,
    wrench_stamped_cdr,
)
from adbsat_ros.messages.decoding import UndecodableMessage, decode_attitude, decode_odometry


def quaternion_stamped(frame):
    msg = QuaternionStamped()
    msg.header.frame_id = frame
    msg.header.stamp.sec, msg.header.stamp.nanosec = 1_767_225_600, 999_999_999
    msg.quaternion = Quaternion(x=Q[0], y=Q[1], z=Q[2], w=Q[3])
    return msg


def odometry(frame):
    msg = Odometry()
    msg.header.frame_id, msg.child_frame_id = frame, frame[::-1]
    msg.header.stamp.sec, msg.header.stamp.nanosec = 1_767_225_600, 5
    p, o, v = msg.pose.pose.position, msg.pose.pose.orientation, msg.twist.twist.linear
    p.x, p.y, p.z = POSITION
    o.x, o.y, o.z, o.w = Q
    v.x, v.y, v.z = VELOCITY
    msg.pose.covariance[7] = 9.0
    return msg


def test_rclpy_bytes_are_read_and_ours_are_read_by_rclpy():
    for frame in FRAMES:
        msg = quaternion_stamped(frame)
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


def test_odometry_from_rclpy_bytes():
    for frame in FRAMES:
        msg = odometry(frame)
        fields = odometry_fields(serialize_message(msg))
        assert fields == OdometryFields.of_message(msg)
        assert fields.frame_id == frame and fields.child_frame_id == frame[::-1]


def test_decoding_with_rclpy_as_the_fallback():
    """Plain CDR is read by the struct codec alone; bytes it refuses (trailing bytes) by rclpy's
    deserialiser, to the same fields; garbage raises UndecodableMessage naming the type."""
    calls = []

    def fallback(message_type):
        def deserialize(raw):
            calls.append(message_type)
            return deserialize_message(raw, message_type)

        return deserialize

    for frame in FRAMES:
        raw = bytes(serialize_message(quaternion_stamped(frame)))
        expected = AttitudeFields(Stamp(1_767_225_600, 999_999_999), Q)
        assert decode_attitude(raw, fallback(QuaternionStamped)) == expected
        assert calls == []
        assert decode_attitude(raw + bytes(8), fallback(QuaternionStamped)) == expected
        assert calls == [QuaternionStamped]
        calls.clear()

        msg = odometry(frame)
        raw = bytes(serialize_message(msg))
        assert decode_odometry(raw, fallback(Odometry)) == OdometryFields.of_message(msg)
        assert calls == []
        assert decode_odometry(raw + bytes(8), fallback(Odometry)) == OdometryFields.of_message(msg)
        assert calls == [Odometry]
        calls.clear()

    garbage = b"\x00\x01\x00\x00" + b"\xff" * 12
    with pytest.raises(UndecodableMessage) as info:
        decode_attitude(garbage, fallback(QuaternionStamped))
    assert info.value.message_type == "geometry_msgs/msg/QuaternionStamped"
    assert "QuaternionStamped" in str(info.value) and info.value.reason
    with pytest.raises(UndecodableMessage) as info:
        decode_odometry(garbage, fallback(Odometry))
    assert info.value.message_type == "nav_msgs/msg/Odometry"


def test_diagnostic_array_reads_back_in_rclpy():
    """rclpy's own serialiser leaves padding bytes uninitialised, so against rclpy the fields are
    compared after its deserialiser has read our bytes."""
    statuses = DIAGNOSTIC_STATUSES
    for frame in FRAMES:
        for count in range(len(statuses) + 1):
            raw = diagnostic_array_cdr(1_767_225_600, 5, frame, statuses[:count])
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


@pytest.mark.parametrize("count", [0, 1, 2, 3, 4, 6])
def test_rclpy_joint_states_are_read_by_the_struct_reader(count):
    """rclpy's serialiser leaves a few bytes after the last field (0, 8 or 12 here): read past."""
    for frame in FRAMES:
        for velocities in (False, True):
            msg = JointState()
            msg.header.frame_id = frame
            msg.header.stamp.sec, msg.header.stamp.nanosec = 1_767_225_600, 7
            msg.name = ["j" * (k + 1) for k in range(count)]
            msg.position = [0.1 * k - 0.2 for k in range(count)]
            msg.velocity = [1.0] * count if velocities else []
            msg.effort = [2.0] * count
            raw = serialize_message(msg)
            fields = joint_state_fields(raw)
            assert fields == JointStateFields.of_message(deserialize_message(raw, JointState))
            assert fields.names == tuple(msg.name)
