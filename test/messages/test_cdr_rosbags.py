"""The struct codec of the attitude and the wrench against rosbags' pure-Python codec (no ROS
needed)."""

import math

import numpy as np
import pytest
from cdr_cases import FRAMES, STAMPS_NS, Q

from adbsat_ros.bags import io as bag_io
from adbsat_ros.messages.cdr import (
    Stamp,
    accel_stamped_cdr,
    header_stamp,
    quaternion_stamped_fields,
    wrench_stamped_cdr,
)


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
            assert fields == (Stamp(t.sec, t.nanosec), [q.x, q.y, q.z, q.w], back.header.frame_id)
            assert (fields.stamp, fields.quaternion_xyzw, fields.frame_id) == tuple(fields)


def vector(xyz):
    x, y, z = (float(v) for v in xyz)
    return bag_io.TYPESTORE.types["geometry_msgs/msg/Vector3"](x=x, y=y, z=z)


def test_wrench_and_accel_stamped_write_equals_rosbags_byte_for_byte():
    for frame in FRAMES:
        for stamp in STAMPS_NS:
            t = bag_io.time_message(stamp)
            force, torque = np.array([1.5, -2.0, 3e-300]), [4.0, -0.0, math.nan]
            raw = bytes(
                bag_io.serialize(bag_io.wrench_stamped_message(stamp, frame, force, torque))
            )
            assert wrench_stamped_cdr(t.sec, t.nanosec, frame, force, torque) == raw
            # an AccelStamped has the layout of a WrenchStamped
            types = bag_io.TYPESTORE.types
            accel = types["geometry_msgs/msg/AccelStamped"](
                header=bag_io.deserialize(raw, bag_io.WRENCH_STAMPED).header,
                accel=types["geometry_msgs/msg/Accel"](
                    linear=vector(force), angular=vector(torque)
                ),
            )
            raw = bytes(bag_io.serialize(accel))
            assert accel_stamped_cdr(t.sec, t.nanosec, frame, force, torque) == raw


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
