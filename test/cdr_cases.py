"""Message contents shared by the codec's and the decoding's tests against rosbags and rclpy."""

import math

import numpy as np

from adbsat_ros.bags import io as bag_io

FRAMES = ("", "b", "eci", "body", "sat_body_frame", "frame_ñ")  # every length mod 8, and UTF-8
STAMPS_NS = (0, 1_767_225_600_123_456_789, 2**31 * 10**9 - 1)
Q = [0.1, -0.2, 0.3, math.sqrt(1 - 0.14)]
POSITION, VELOCITY = (6678137.0, -1.5e-3, 2.5e5), (-0.25, 7725.8, 1e-300)


def odometry(stamp_ns, frame, child):
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
