"""A tiny publisher to try adbsat_node: a circular orbit in ECI and a fixed or turning attitude.

``state`` (nav_msgs/Odometry, ECI, 10 Hz) and ``attitude`` (QuaternionStamped, ``--rate`` Hz),
stamped in seconds since the start (node ``time_mode:=epoch``); prints the ``wrench`` answered.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time

import rclpy
from geometry_msgs.msg import QuaternionStamped, WrenchStamped
from nav_msgs.msg import Odometry
from rclpy.signals import SignalHandlerOptions

from adbsat_ros.physics.constants import EARTH_MU
from adbsat_ros.processes import run_until_stopped, stop_on_signals

#: Equatorial radius of WGS-84 [m]: the orbit's radius is this plus the altitude.
EARTH_RADIUS = 6378137.0


def main(argv=None) -> int:
    """Console script ``adbsat_orbit_publisher``; the exit status (0 also after SIGINT/SIGTERM)."""
    return run_until_stopped("adbsat_orbit_publisher", _main, argv)


def _main(argv=None) -> int:
    parser = argparse.ArgumentParser(
        prog="adbsat_orbit_publisher", description=__doc__.splitlines()[0]
    )
    parser.add_argument(
        "--altitude", type=float, default=300.0, help="orbit altitude [km] (default 300)"
    )
    parser.add_argument("--rate", type=float, default=10.0, help="attitude rate [Hz] (default 10)")
    parser.add_argument("--duration", type=float, default=5.0, help="seconds to run (default 5)")
    parser.add_argument("--yaw-rate", type=float, default=0.0, help="body rotation about z [deg/s]")
    args, ros_args = parser.parse_known_args(argv)
    if not (0 < args.altitude <= 1000 and args.rate > 0 and args.duration > 0):
        parser.error("--altitude must be in (0, 1000] km, --rate and --duration > 0")
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")  # read by rclpy.init
    rclpy.init(args=[sys.argv[0], *ros_args], signal_handler_options=SignalHandlerOptions.NO)
    node = None
    try:
        node = rclpy.create_node("orbit_publisher")
        with stop_on_signals() as stop:
            _publish(node, args, stop)
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0


def _publish(node, args, stop) -> None:
    """Publish the orbit and attitude for ``args.duration`` s, or until ``stop``."""
    attitude = node.create_publisher(QuaternionStamped, "attitude", 10)
    state = node.create_publisher(Odometry, "state", 10)

    def show(msg):
        f, t = msg.wrench.force, msg.wrench.torque
        print(
            f"t={msg.header.stamp.sec + 1e-9 * msg.header.stamp.nanosec:7.2f} s  "
            f"force [N] ({f.x:+.3e}, {f.y:+.3e}, {f.z:+.3e})  "
            f"torque [N m] ({t.x:+.3e}, {t.y:+.3e}, {t.z:+.3e})",
            flush=True,
        )

    node.create_subscription(WrenchStamped, "wrench", show, 10)
    r = EARTH_RADIUS + 1e3 * args.altitude
    v = math.sqrt(EARTH_MU / r)
    w = v / r
    start = time.monotonic()
    next_state = 0.0
    k = 0
    while (t := k / args.rate) <= args.duration and not stop.is_set():
        while time.monotonic() - start < t and not stop.is_set():
            rclpy.spin_once(node, timeout_sec=0.002)
        stamp = node.get_clock().now().to_msg()
        stamp.sec, stamp.nanosec = int(t), int(round((t % 1.0) * 1e9)) % 1_000_000_000
        if t >= next_state:
            o = Odometry()
            o.header.stamp, o.header.frame_id, o.child_frame_id = stamp, "eci", "eci"
            cos, sin = math.cos(w * t), math.sin(w * t)
            o.pose.pose.position.x, o.pose.pose.position.y = r * cos, r * sin
            o.twist.twist.linear.x, o.twist.twist.linear.y = -v * sin, v * cos
            state.publish(o)
            next_state += 0.1
        # body x along the velocity (+90 deg about z from ECI x at t = 0), plus the yaw rate
        yaw = math.pi / 2 + w * t + math.radians(args.yaw_rate) * t
        q = QuaternionStamped()
        q.header.stamp, q.header.frame_id = stamp, "eci"
        q.quaternion.z, q.quaternion.w = math.sin(yaw / 2), math.cos(yaw / 2)
        attitude.publish(q)
        k += 1
    end = time.monotonic() + 0.5
    while time.monotonic() < end and not stop.is_set():
        rclpy.spin_once(node, timeout_sec=0.05)


if __name__ == "__main__":
    sys.exit(main())
