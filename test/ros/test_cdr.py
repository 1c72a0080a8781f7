"""The struct codec of the attitude and the wrench against rclpy's codec (the RMW's C typesupport,
what the node's peers actually send), the decoding with rclpy's deserialiser, and the joint
torques as the node serialises them against rosbags' reading."""

import numpy as np
import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

from cdr_cases import FRAMES, POSITION, VELOCITY, Q
from geometry_msgs.msg import AccelStamped, Quaternion, QuaternionStamped, WrenchStamped
from nav_msgs.msg import Odometry
from rclpy.serialization import deserialize_message, serialize_message
from sensor_msgs.msg import JointState

from adbsat_ros.bags import io as bag_io
from adbsat_ros.messages.cdr import (
    AttitudeFields,
    Stamp,
    accel_stamped_cdr,
    joint_state_cdr,
    quaternion_stamped_fields,
    wrench_stamped_cdr,
)
from adbsat_ros.messages.decoding import (
    JointStateFields,
    OdometryFields,
    UndecodableMessage,
    decode_attitude,
    decode_joint_state,
    decode_odometry,
)


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
            frame,
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
        back = deserialize_message(accel_stamped_cdr(7, 8, frame, force, torque), AccelStamped)
        assert back.header.frame_id == frame and back.header.stamp.nanosec == 8
        v, w = back.accel.linear, back.accel.angular
        assert [v.x, v.y, v.z, w.x, w.y, w.z] == force + torque


def test_decoding_with_rclpys_deserialiser():
    """A plain-CDR attitude is read by the struct codec alone, bytes it refuses (trailing bytes)
    by rclpy's deserialiser, to the same fields; a state always by the deserialiser; garbage
    raises UndecodableMessage naming the type."""
    calls = []

    def fallback(message_type):
        def deserialize(raw):
            calls.append(message_type)
            return deserialize_message(raw, message_type)

        return deserialize

    for frame in FRAMES:
        raw = bytes(serialize_message(quaternion_stamped(frame)))
        expected = AttitudeFields(Stamp(1_767_225_600, 999_999_999), Q, frame)
        assert decode_attitude(raw, fallback(QuaternionStamped)) == expected
        assert calls == []
        assert decode_attitude(raw + bytes(8), fallback(QuaternionStamped)) == expected
        assert calls == [QuaternionStamped]
        calls.clear()

        msg = odometry(frame)
        raw = bytes(serialize_message(msg))
        fields = decode_odometry(raw, fallback(Odometry))
        assert fields == OdometryFields(
            Stamp(1_767_225_600, 5), frame, frame[::-1], POSITION, tuple(Q), VELOCITY
        )
        assert decode_odometry(raw + bytes(8), fallback(Odometry)) == fields
        assert calls == [Odometry, Odometry]
        calls.clear()

    garbage = b"\x00\x01\x00\x00" + b"\xff" * 12
    with pytest.raises(UndecodableMessage) as info:
        decode_attitude(garbage, fallback(QuaternionStamped))
    assert info.value.message_type == "geometry_msgs/msg/QuaternionStamped"
    assert "QuaternionStamped" in str(info.value) and info.value.reason
    with pytest.raises(UndecodableMessage) as info:
        decode_odometry(garbage, fallback(Odometry))
    assert info.value.message_type == "nav_msgs/msg/Odometry"


@pytest.mark.parametrize("count", [0, 1, 2, 3, 4, 6])
def test_rclpy_joint_states_are_read_by_either_deserialiser(count):
    """rclpy's serialiser leaves a few bytes after the last field (0, 8 or 12 here): rosbags'
    deserialiser in bag analysis reads past them as rclpy's does in the node."""
    for frame in FRAMES:
        for velocities in (False, True):
            msg = JointState()
            msg.header.frame_id = frame
            msg.header.stamp.sec, msg.header.stamp.nanosec = 1_767_225_600, 7
            msg.name = ["j" * (k + 1) for k in range(count)]
            msg.position = [0.1 * k - 0.2 for k in range(count)]
            msg.velocity = [1.0] * count if velocities else []
            msg.effort = [2.0] * count
            raw = bytes(serialize_message(msg))
            fields = decode_joint_state(raw, bag_io.deserialize_joint_state)
            expected = JointStateFields(
                Stamp(1_767_225_600, 7), tuple(msg.name), tuple(msg.position)
            )
            assert fields == expected
            assert decode_joint_state(raw, lambda b: deserialize_message(b, JointState)) == expected


def test_the_joint_torques_writer_equals_rosbags_byte_for_byte_and_rclpy_reads_it():
    """The joint torques' writer (``messages.cdr``) against rosbags' serialiser and rclpy's
    deserialiser: frames of every length modulo 8, none to three joints, with and without values."""
    joints = [(), ("fin",), ("wing_left_hinge", "fin"), ("a", "bc", "def")]
    for frame in FRAMES:
        for names in joints:
            for stamp in (Stamp(1_767_225_600, 9), Stamp(-3, 999_999_999)):
                positions = np.linspace(-0.2, 0.3, len(names))
                efforts = [4.0, -0.0, 1e-300][: len(names)]
                raw = joint_state_cdr(stamp, frame, names, positions, efforts)
                assert raw == bag_io.joint_state_cdr(stamp, frame, names, positions, efforts)
                msg = deserialize_message(raw, JointState)
                assert (msg.header.stamp.sec, msg.header.stamp.nanosec) == stamp
                assert (msg.header.frame_id, tuple(msg.name)) == (frame, names)
                assert (list(msg.position), list(msg.velocity)) == (positions.tolist(), [])
                assert list(msg.effort) == efforts
                empty = joint_state_cdr(stamp, frame, names, (), ())
                assert empty == bag_io.joint_state_cdr(stamp, frame, names, (), ())
