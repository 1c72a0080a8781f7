"""Helpers for tests that run the node with real rclpy: a context, a peer node, and waiting."""

from __future__ import annotations

import pytest

pytest.importorskip("rclpy")

import contextlib
import math
import threading
import time

import rclpy
from geometry_msgs.msg import QuaternionStamped, WrenchStamped
from nav_msgs.msg import Odometry
from rclpy.node import Node
from rclpy.qos import QoSProfile
from waiting import HANG_TIMEOUT  # (a message, discovery, a process coming up; re-exported)

EARTH_MU = 3.986004418e14
EARTH_RADIUS_EQ = 6378137.0


def circular_orbit_state(altitude_m: float, t: float = 0.0):
    """Equatorial circular orbit in ECI: position [m] and velocity [m/s] at time t [s]."""
    r = EARTH_RADIUS_EQ + altitude_m
    v = math.sqrt(EARTH_MU / r)
    w = v / r
    return (
        [r * math.cos(w * t), r * math.sin(w * t), 0.0],
        [-v * math.sin(w * t), v * math.cos(w * t), 0.0],
    )


class Peer:
    """A test node that publishes attitude and state and collects wrench, coefficients and
    diagnostics."""

    def __init__(self, context, executor, name="test_peer", namespace="", depth=100):
        self.node = Node(name, context=context, namespace=namespace)
        qos = QoSProfile(depth=depth)  # (messages kept while nobody spins: more are lost)
        self.attitude_pub = self.node.create_publisher(QuaternionStamped, "attitude", qos)
        self.state_pub = self.node.create_publisher(Odometry, "state", qos)
        self.wrenches, self.coefficients, self.diagnostics = [], [], []
        self.node.create_subscription(WrenchStamped, "wrench", self.wrenches.append, qos)
        self.node.create_subscription(WrenchStamped, "coefficients", self.coefficients.append, qos)
        from diagnostic_msgs.msg import DiagnosticArray

        self.node.create_subscription(DiagnosticArray, "/diagnostics", self.diagnostics.append, 10)
        self.executor = executor
        executor.add_node(self.node)

    def send_state(
        self, t, position, velocity, frame="eci", child="eci", orientation=(0.0, 0.0, 0.0, 1.0)
    ):
        msg = Odometry()
        msg.header.stamp = to_stamp(t)
        msg.header.frame_id = frame
        msg.child_frame_id = child
        p = msg.pose.pose.position
        p.x, p.y, p.z = (float(x) for x in position)
        o = msg.pose.pose.orientation
        o.x, o.y, o.z, o.w = (float(x) for x in orientation)
        v = msg.twist.twist.linear
        v.x, v.y, v.z = (float(x) for x in velocity)
        self.state_pub.publish(msg)

    def send_attitude(self, t, q_xyzw, frame="eci"):
        msg = QuaternionStamped()
        msg.header.stamp = to_stamp(t)
        msg.header.frame_id = frame
        q = msg.quaternion
        q.x, q.y, q.z, q.w = (float(x) for x in q_xyzw)
        self.attitude_pub.publish(msg)

    def spin_until(self, predicate, timeout=HANG_TIMEOUT):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=0.01)
            if predicate():
                return True
        return False

    def spin_for(self, seconds):
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=0.01)

    def wait_for_subscribers(self, timeout=HANG_TIMEOUT):
        return self.spin_until(
            lambda: (
                self.attitude_pub.get_subscription_count() > 0
                and self.state_pub.get_subscription_count() > 0
            ),
            timeout,
        )


def to_stamp(t: float):
    from builtin_interfaces.msg import Time

    sec = math.floor(t)
    return Time(sec=int(sec), nanosec=int(round((t - sec) * 1e9)) % 1_000_000_000)


def stamp_to_float(stamp) -> float:
    return stamp.sec + 1e-9 * stamp.nanosec


def make_context(executor: str = "single_threaded"):
    """A fresh rclpy context and an executor of the kind adbsat_node can use (events or
    single_threaded)."""
    from adbsat_ros.ros.node import make_executor

    ctx = rclpy.context.Context()
    rclpy.init(context=ctx)
    return ctx, make_executor(executor, context=ctx)


@contextlib.contextmanager
def spinning(executor, period: float = 0.02):
    """Spin ``executor`` on a background thread for the duration of the ``with`` block."""
    done = threading.Event()

    def spin():
        while not done.is_set():
            executor.spin_once(timeout_sec=period)

    spinner = threading.Thread(target=spin, daemon=True)
    spinner.start()
    try:
        yield
    finally:
        done.set()
        spinner.join(timeout=5)


@contextlib.contextmanager
def node_and_peer(overrides, executor: str = "single_threaded"):
    """adbsat_node with the parameter ``overrides`` (rclpy Parameters) and a :class:`Peer` on a
    fresh context and executor, both discovered; everything taken down after the block."""
    from adbsat_ros.ros.node import AdbsatNode

    ctx, spinner = make_context(executor)
    node = AdbsatNode(context=ctx, parameter_overrides=list(overrides))
    spinner.add_node(node)
    peer = Peer(ctx, spinner)
    try:
        assert peer.wait_for_subscribers()
        yield node, peer
    finally:
        spinner.shutdown()
        peer.node.destroy_node()
        node.destroy_node()
        rclpy.try_shutdown(context=ctx)
