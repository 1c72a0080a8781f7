"""The rate adbsat_node sustains under a flood of attitudes, and its count of the ones it lost.

Usage:
    python bench/bench_node_flood.py [--attitudes random,smooth] [--rate 2000] [--duration 10]
        [--max-edge 0.0625] [--qos-depth 10] [--executor events|single_threaded]
        [--param NAME:=VALUE ...]

Runs adbsat_node in its own process (this tree's, its default parameters: the 11,104-face
example satellite, raycast shading cached at 0.25 deg, KEEP_LAST ``qos_depth`` 10) and a
publisher process that first sends a state and one attitude (the node's count of lost messages
starts with the first attitude it takes of a publisher, docs/node.md), then floods attitudes at
``--rate`` for ``--duration`` seconds, stamped regularly at 1 / rate, a state with every 100th.
The attitudes are either random (uniform on the sphere of rotations: nearly every flow
direction falls in a new shading-cache cell) or smooth (tumbling at 1 deg/s about z: nearly all
cache hits). This process receives the wrenches and /diagnostics.

Prints per kind of attitude, from the node's /diagnostics once it is quiet: the attitudes sent
in the flood, the wrenches the node published for them, the attitudes it rejected (e.g.
``stale_state`` when the states it needed were lost too), ``attitudes_lost``, whether those
three add up to the attitudes sent ("ok"), ``states_lost``, ``attitudes_missing`` (from the
stamps); then the sustained rate (wrenches received here per second, from the first to the last
wrench of the flood), the shading cache's misses and hits, and the node's compute time p50 / p99.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from bench_node_latency import NODE_MODULE, R_ORBIT, REPOSITORY, V_ORBIT, wait_until_idle

#: Seconds without a wrench after the flood that end a run.
QUIET_S = 3.0


def publisher(attitudes: str, rate: float, duration: float, ready: str, out: str) -> None:
    """Wait for the node (and ``ready``), send a state and one attitude, then the flood."""
    import rclpy
    from geometry_msgs.msg import QuaternionStamped
    from nav_msgs.msg import Odometry
    from rclpy.qos import QoSProfile

    rclpy.init()
    node = rclpy.create_node("bench_flood_publisher")
    qos = QoSProfile(depth=100)
    att = node.create_publisher(QuaternionStamped, "attitude", qos)
    st = node.create_publisher(Odometry, "state", qos)
    deadline = time.monotonic() + 60
    while (
        att.get_subscription_count() == 0
        or st.get_subscription_count() == 0
        or not Path(ready).exists()
    ) and time.monotonic() < deadline:
        time.sleep(0.05)
    q = QuaternionStamped()
    q.header.frame_id = "eci"
    q.quaternion.w = 1.0
    o = Odometry()
    o.header.frame_id = o.child_frame_id = "eci"
    o.pose.pose.position.x = R_ORBIT
    o.twist.twist.linear.y = V_ORBIT
    n = int(rate * duration)
    period_ns = round(1e9 / rate)
    if attitudes == "random":
        quaternions = np.random.default_rng(7).normal(size=(n, 4))
        quaternions /= np.linalg.norm(quaternions, axis=1, keepdims=True)
    else:  # tumbling about z at 1 deg/s
        angle = np.radians(1.0) * np.arange(n) / rate
        quaternions = np.zeros((n, 4))
        quaternions[:, 2], quaternions[:, 3] = np.sin(angle / 2), np.cos(angle / 2)
    st.publish(o)
    time.sleep(0.5)
    att.publish(q)  # the first attitude: the node's count starts with it
    time.sleep(1.0)
    start = time.monotonic()
    for k in range(1, n + 1):
        delay = start + k / rate - time.monotonic()
        if delay > 0.0:
            time.sleep(delay)
        sec, nanosec = divmod(k * period_ns, 1_000_000_000)
        if k % 100 == 0:
            o.header.stamp.sec, o.header.stamp.nanosec = sec, nanosec
            st.publish(o)
        q.header.stamp.sec, q.header.stamp.nanosec = sec, nanosec
        x, y, z, w = quaternions[k - 1].tolist()
        q.quaternion.x, q.quaternion.y, q.quaternion.z, q.quaternion.w = x, y, z, w
        att.publish(q)
    Path(out).write_text(json.dumps({"sent": n, "seconds": time.monotonic() - start}))
    time.sleep(1.0)
    node.destroy_node()
    rclpy.try_shutdown()


def run(attitudes: str, args, mesh: str) -> dict:
    """One flood: the node, the publisher, and the wrenches and diagnostics received here."""
    import rclpy
    from diagnostic_msgs.msg import DiagnosticArray
    from geometry_msgs.msg import WrenchStamped
    from rclpy.qos import QoSProfile

    from adbsat_ros.ros.executors import make_executor

    tmp = Path(tempfile.mkdtemp())
    command = [sys.executable, "-m", NODE_MODULE, "--ros-args", "-p", f"mesh:={mesh}"]
    for item in [
        "time_mode:=epoch",
        f"qos_depth:={args.qos_depth}",
        f"executor:={args.executor}",
        *args.param,
    ]:
        command += ["-p", item]
    with open(tmp / "node.log", "w") as log:
        node_process = subprocess.Popen(command, cwd=tmp, stdout=log, stderr=subprocess.STDOUT)
    time.sleep(0.5)
    wait_until_idle(node_process.pid)
    rclpy.init()
    node = rclpy.create_node("bench_flood_receiver")
    times, diagnostics = [], {}
    wrenches = node.create_subscription(
        WrenchStamped, "wrench", lambda raw: times.append(time.monotonic()), 100, raw=True
    )

    def on_diagnostics(msg):
        for status in msg.status:
            diagnostics.update({kv.key: kv.value for kv in status.values})

    node.create_subscription(DiagnosticArray, "/diagnostics", on_diagnostics, QoSProfile(depth=10))
    executor = make_executor("events")
    executor.add_node(node)
    while wrenches.get_publisher_count() == 0:
        executor.spin_once(timeout_sec=0.1)
    ready, out = tmp / "ready", tmp / "sent.json"
    ready.touch()
    publisher_process = subprocess.Popen(
        [sys.executable, __file__, "--role", "publisher", "--attitudes", attitudes]
        + ["--rate", str(args.rate), "--duration", str(args.duration)]
        + ["--ready", str(ready), "--out", str(out)]
    )
    try:
        while (
            publisher_process.poll() is None or not times or time.monotonic() - times[-1] < QUIET_S
        ):
            executor.spin_once(timeout_sec=0.1)
        diagnostics.clear()  # the first /diagnostics after the node went quiet
        while "messages_lost" not in diagnostics:
            executor.spin_once(timeout_sec=0.1)
    finally:
        node_process.terminate()
        node_process.wait(timeout=30)
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown()
    sent = json.loads(out.read_text())
    flood = np.array(times[1:])  # (the first wrench answers the first attitude)
    lost = int(diagnostics["attitudes_lost"])
    rejected = sum(int(v) for k, v in diagnostics.items() if k.startswith("rejected_"))
    return {
        "attitudes": attitudes,
        "sent": sent["sent"],
        "publish_seconds": sent["seconds"],
        "answered": int(diagnostics["published"]) - 1,  # (the first answers the first attitude)
        "rejected": rejected,
        "states_lost": int(diagnostics["states_lost"]),
        "received": flood.size,
        "lost": lost,
        "missing": int(diagnostics["attitudes_missing"]),
        "rate": (flood.size - 1) / (flood[-1] - flood[0]) if flood.size > 1 else math.nan,
        "misses": int(diagnostics["shading_cache_misses"]),
        "hits": int(diagnostics["shading_cache_hits"]),
        "compute_p50": float(diagnostics["compute_ms_p50"]),
        "compute_p99": float(diagnostics["compute_ms_p99"]),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--role", choices=["main", "publisher"], default="main")
    parser.add_argument("--attitudes", default="random,smooth")
    parser.add_argument("--rate", type=float, default=2000.0)
    parser.add_argument("--duration", type=float, default=10.0)
    parser.add_argument("--max-edge", type=float, default=0.0625)
    parser.add_argument("--qos-depth", type=int, default=10)
    parser.add_argument("--executor", default="events")
    parser.add_argument("--param", action="append", default=[])
    parser.add_argument("--ready", default="")
    parser.add_argument("--out", default="")
    args = parser.parse_args()
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    if args.role == "publisher":
        return publisher(args.attitudes, args.rate, args.duration, args.ready, args.out)
    from meshes import write_obj

    from adbsat_ros.geometry.example_satellite import example_satellite

    mesh = example_satellite(max_edge=args.max_edge)
    mesh_path = Path(tempfile.mkdtemp()) / "satellite.obj"
    write_obj(mesh, mesh_path)
    print(
        f"adbsat_node ({REPOSITORY.name}): example satellite, {mesh.n_panels} faces; "
        f"qos_depth {args.qos_depth}, executor {args.executor}; flood at {args.rate:g} Hz "
        f"for {args.duration:g} s"
    )
    print(
        f"{'attitudes':>9} {'sent':>7} {'wrenches':>8} {'rejected':>8} {'lost':>7} {'sum':>4}"
        f" {'states lost':>11} {'missing':>7} {'rate /s':>7} {'misses':>6} {'hits':>6}"
        f" {'p50 ms':>6} {'p99 ms':>6}"
    )
    for attitudes in args.attitudes.split(","):
        r = run(attitudes, args, str(mesh_path))
        whole = r["answered"] + r["rejected"] + r["lost"] == r["sent"]
        print(
            f"{r['attitudes']:>9} {r['sent']:>7} {r['answered']:>8} {r['rejected']:>8}"
            f" {r['lost']:>7} {'ok' if whole else 'off':>4} {r['states_lost']:>11}"
            f" {r['missing']:>7} {r['rate']:>7.0f} {r['misses']:>6} {r['hits']:>6}"
            f" {r['compute_p50']:>6.2f} {r['compute_p99']:>6.2f}",
            flush=True,
        )


if __name__ == "__main__":
    main()
