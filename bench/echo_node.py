"""A bare rclpy echo node: republishes each QuaternionStamped on `attitude` as a WrenchStamped on
`wrench` with the same stamp. The latency floor of rclpy on this machine, for bench_node_latency.

With ECHO_WORK_US=N in the environment it first spins for N microseconds in every callback: an
echo that costs as much CPU per message as a node of known cost, for bench_node_latency's
--echo-work-us."""

import os
import sys
import time

import rclpy
from geometry_msgs.msg import QuaternionStamped, WrenchStamped
from rclpy.qos import QoSProfile

from adbsat_ros.node import make_executor, spin_until_shutdown


def main():
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    rclpy.init(args=sys.argv)
    node = rclpy.create_node("echo_node")
    qos = QoSProfile(depth=int(os.environ.get("ECHO_QOS_DEPTH", "10")))
    pub = node.create_publisher(WrenchStamped, "wrench", qos)

    work_s = float(os.environ.get("ECHO_WORK_US", "0")) * 1e-6

    def echo(msg):
        if work_s > 0.0:  # holds the GIL, like Python work would
            done = time.perf_counter() + work_s
            while time.perf_counter() < done:
                pass
        out = WrenchStamped()
        out.header = msg.header
        out.wrench.force.x = msg.quaternion.w
        pub.publish(out)

    node.create_subscription(QuaternionStamped, "attitude", echo, qos)
    executor = make_executor(os.environ.get("ECHO_EXECUTOR", "events"))
    executor.add_node(node)
    try:
        spin_until_shutdown(executor)
    except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
