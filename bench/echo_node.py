"""A bare rclpy echo node: republishes each QuaternionStamped on `attitude` as a WrenchStamped on
`wrench` with the same stamp. The latency floor of rclpy on this machine, for bench_node_latency.

It spins the executor ECHO_EXECUTOR names: ``events`` (the default, rclpy's EventsExecutor, as
adbsat_node spins it), ``single_threaded``, or ``rclpy.spin``: ``rclpy.spin(node)``, the textbook
node on rclpy's default executor (bench_node_latency's "bare echo").

With ECHO_WORK_US=N in the environment it first spins for N microseconds in every callback: an
echo that costs as much CPU per message as a node of known cost, for bench_node_latency's
--echo-work-us.

With ECHO_PANEL_MESH=PATH it is instead the panel method alone, for bench_node_latency's
--echo-panel: the attitudes taken and the wrenches published as CDR bytes (as adbsat_node does),
and for each one the node's model with its default parameters (Model.evaluate: the panel method
and its cached raycast shading) at a fixed free stream, the satellite flying along +y of the
state frame: the node's own arithmetic per message, without its flight conditions, checks,
samples or bookkeeping.
"""

import os
import sys
import time

import numpy as np
import rclpy
from geometry_msgs.msg import QuaternionStamped, WrenchStamped
from rclpy.qos import QoSProfile

from adbsat_ros.ros.executors import make_executor, spin_until_shutdown


def panel_callback(publisher, mesh_path: str):
    """The --echo-panel callback: CDR bytes of an attitude in, of its wrench out."""
    from adbsat_ros.estimator.settings import WrenchSettings, setup_from_settings
    from adbsat_ros.geometry.frames import quaternion_matrix_floats
    from adbsat_ros.messages.cdr import quaternion_stamped_fields, wrench_stamped_cdr
    from adbsat_ros.physics.freestream import FreeStream
    from adbsat_ros.physics.model import build_model

    # the node's model of the mesh with its default parameters (its one shading cache)
    model = build_model(setup_from_settings(WrenchSettings.from_parameters({"mesh": mesh_path})))
    # about 300 km: O and N2 [m^-3], 900 K, 7.7 km/s
    flow = FreeStream(speed=7700.0, temperature=900.0, number_densities={"O": 6e14, "N2": 2e14})
    q = flow.dynamic_pressure()

    def on_attitude(raw):
        stamp, (x, y, z, w) = quaternion_stamped_fields(raw)
        m = quaternion_matrix_floats(x, y, z, w)
        u = np.array(
            [-m[3], -m[4], -m[5]]
        )  # -R^T v / |v| for v along +y: the gas along -y, body axes
        coefficients = model.evaluate(flow, u)
        publisher.publish(
            wrench_stamped_cdr(
                stamp.sec,
                stamp.nanosec,
                "body",
                coefficients.force(q).tolist(),
                coefficients.torque(q).tolist(),
            )
        )

    return on_attitude


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

    mesh_path = os.environ.get("ECHO_PANEL_MESH")
    if mesh_path:
        node.create_subscription(
            QuaternionStamped, "attitude", panel_callback(pub, mesh_path), qos, raw=True
        )
    else:
        node.create_subscription(QuaternionStamped, "attitude", echo, qos)
    executor_kind = os.environ.get("ECHO_EXECUTOR", "events")
    try:
        if executor_kind == "rclpy.spin":  # the textbook node: rclpy's default executor
            rclpy.spin(node)
        else:
            executor = make_executor(executor_kind)
            executor.add_node(node)
            spin_until_shutdown(executor)
    except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
