"""``adbsat-ros demo``: the ROS 2 node live on the bundled satellite, in one command (docs/cli.md).

One process: the node on its own rclpy Context under ``/adbsat_demo``, fed a scenario live at
``speedup`` times real time; the wrenches printed and written as a CSV and PNG plots.
"""

from __future__ import annotations

import math
import os
import sys
import threading
import time
from pathlib import Path

import numpy as np
import rclpy
from geometry_msgs.msg import QuaternionStamped, WrenchStamped
from nav_msgs.msg import Odometry
from rclpy.context import Context
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import JointState

from adbsat_ros.bags.io import (
    joint_state_message,
    odometry_message,
    quaternion_stamped_message,
    serialize,
)
from adbsat_ros.bags.scenario import Scenario, generate
from adbsat_ros.environment.space_weather import HistoricalWeather
from adbsat_ros.ros import demo_joints
from adbsat_ros.ros.demo_report import DemoResult, SampleLog, table_rows, vector, write_outputs
from adbsat_ros.ros.executors import make_executor
from adbsat_ros.ros.node import AdbsatNode

#: Attitude messages per second of wall time, whatever the speedup.
WALL_RATE_HZ = 20.0
#: Seconds of wall time between two table lines.
TABLE_PERIOD_S = 0.5
#: Namespace of the demo's node and topics.
NAMESPACE = "/adbsat_demo"
#: Scenario of the demo (UTC epoch of t = 0, orbit).
EPOCH_UTC = "2025-06-21T12:00:00Z"
ALTITUDE_KM = 300.0
INCLINATION_DEG = 51.6
TUMBLE_RATE_DEG_S = 1.0
#: Largest accepted speedup (one attitude message per 30 s of simulated time at 20 Hz).
MAX_SPEEDUP = 600.0
#: Seconds to wait for the last wrenches after the last attitude is published.
DRAIN_TIMEOUT_S = 5.0


def demo_scenario(duration: float, speedup: float, attitude: str):
    """The demo's Scenario: ``duration`` wall seconds at ``speedup``, 20 attitudes a wall second."""
    rate = WALL_RATE_HZ / speedup
    return Scenario(
        epoch_utc=EPOCH_UTC,
        duration_s=duration * speedup,
        rate_hz=rate,
        state_rate_hz=rate,
        altitude_km=ALTITUDE_KM,
        eccentricity=0.0,
        inclination_deg=INCLINATION_DEG,
        attitude=attitude,
        tumble_rate_deg_s=TUMBLE_RATE_DEG_S,
        tumble_axis=(0.3, 1.0, 0.2),
    )


def _events(messages, speedup: float):
    """(wall offset [s], kind, index) in order; a state goes half an attitude period early."""
    t0 = int(messages.attitudes.stamps_ns[0])
    half = 0.5 / WALL_RATE_HZ
    events = [
        ((int(t) - t0) * 1e-9 / speedup - half, 0, i)
        for i, t in enumerate(messages.states.stamps_ns)
    ]
    events += [
        ((int(t) - t0) * 1e-9 / speedup, 1, i) for i, t in enumerate(messages.attitudes.stamps_ns)
    ]
    events.sort()
    start = events[0][0]
    return [(w - start, kind, i) for w, kind, i in events]


def run_demo(
    duration: float = 8.0,
    speedup: float = 10.0,
    out_dir="adbsat_demo",
    attitude: str | None = None,
    out=None,
    articulated: bool = False,
    space_weather: str = "fixed",
) -> DemoResult:
    """Run the demo (module docstring); prints to ``out`` (default stdout).

    duration: wall time of the live part [s] (the node's start-up comes on top).
    speedup: simulated seconds per wall second, in (0, :data:`MAX_SPEEDUP`].
    attitude: ``'tumble'`` (default) or ``'nadir'`` (with ``articulated``).
    articulated: the finned body steering its fins (:mod:`adbsat_ros.ros.demo_joints`).
    space_weather: the node's ``space_weather`` parameter, ``'fixed'`` or ``'historical'``.
    ValueError: a bad duration, speedup or attitude.
    """
    out = out or sys.stdout
    if not (math.isfinite(duration) and 0 < duration <= 3600):
        raise ValueError(f"--duration must be in (0, 3600] s, got {duration!r}")
    if not (math.isfinite(speedup) and 0 < speedup <= MAX_SPEEDUP):
        raise ValueError(f"--speedup must be in (0, {MAX_SPEEDUP:g}], got {speedup!r}")
    attitude = attitude or ("nadir" if articulated else "tumble")
    if attitude not in ("tumble", "nadir"):
        raise ValueError(f"--attitude must be tumble or nadir, got {attitude!r}")
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")

    def say(line=""):
        print(line, file=out, flush=True)

    scenario = demo_scenario(duration, speedup, attitude)
    messages = generate(scenario)
    result = DemoResult()
    motion = (
        f"tumbling at {TUMBLE_RATE_DEG_S:g} deg/s" if attitude == "tumble" else "nadir-pointing"
    )
    fins = f"; {demo_joints.BODY} steering its fins +-{demo_joints.AMPLITUDE_DEG:g} deg"
    say(
        f"adbsat-ros demo: {ALTITUDE_KM:g} km circular orbit, {INCLINATION_DEG:g} deg inclination, "
        f"from {scenario.epoch.isoformat().replace('+00:00', 'Z')}, satellite {motion}; "
        f"{scenario.duration_s:g} s simulated in {duration:g} s ({speedup:g}x real time)"
        + (fins if articulated else "")
    )
    say(
        f"ROS 2: ROS_AUTOMATIC_DISCOVERY_RANGE={os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE']}, "
        f"ROS_DOMAIN_ID={os.environ.get('ROS_DOMAIN_ID', '0 (default)')}, topics under {NAMESPACE}"
    )

    context = Context()
    rclpy.init(context=context)
    node = client = executor = spinner = None
    stop = threading.Event()
    # stamp_ns -> [wrench, coefficients, receive wall time], filled by the executor thread
    received = {}
    lock = threading.Lock()
    latest = [None]  # stamp_ns of the newest wrench received
    sent_wall = {}
    log = None
    timeout = max(1.0, 1.5 / scenario.rate_hz)
    parameters = {"qos_depth": 100, "state_timeout": timeout, "space_weather": space_weather}
    if articulated:
        parameters.update(
            mesh=demo_joints.BODY,
            joint_state_timeout=timeout,
            joint_shading_resolution_deg=demo_joints.SHADING_GRID_DEG,
            joint_shading_interpolation=True,
        )
    t0_ns = int(messages.attitudes.stamps_ns[0])
    try:
        started = time.monotonic()
        node = AdbsatNode(
            context=context,
            namespace=NAMESPACE,
            cli_args=["--ros-args", "-r", f"/diagnostics:={NAMESPACE}/diagnostics"],
            parameter_overrides=[
                Parameter(name, value=value) for name, value in parameters.items()
            ],
        )
        log = SampleLog()
        node.add_sample_listener(log)
        mesh = node.estimator.mesh
        s = node.estimator.settings
        say(
            f"adbsat_node started in {time.monotonic() - started:.2f} s: "
            f"{Path(str(mesh.source)).name}, "
            f"{mesh.n_panels} panels, model {s.gsi_model}, shading {s.shading}"
        )
        if space_weather != "fixed":
            w = HistoricalWeather().at(scenario.epoch)
            say(
                f"space weather {space_weather} at {scenario.epoch.date().isoformat()}: "
                f"F10.7 {w.f107:g} sfu, 81-day F10.7 {w.f107a:g} sfu, Ap {w.ap:g}"
            )

        client = rclpy.create_node("demo_client", namespace=NAMESPACE, context=context)
        qos = QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)
        attitude_pub = client.create_publisher(QuaternionStamped, "attitude", qos)
        state_pub = client.create_publisher(Odometry, "state", qos)
        if articulated:
            joints_pub = client.create_publisher(JointState, "joint_states", qos)

        def on_message(slot):
            def callback(msg):
                key = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
                with lock:
                    entry = received.setdefault(key, [None, None, None])
                    entry[slot] = msg
                    if slot == 0:
                        entry[2] = time.monotonic()
                        latest[0] = key if latest[0] is None else max(key, latest[0])

            return callback

        client.create_subscription(WrenchStamped, "wrench", on_message(0), qos)
        client.create_subscription(WrenchStamped, "coefficients", on_message(1), qos)
        executor = make_executor(node.estimator.settings.executor, context=context)
        executor.add_node(node)
        executor.add_node(client)

        def spin():
            while not stop.is_set() and context.ok():
                executor.spin_once(timeout_sec=0.05)

        spinner = threading.Thread(target=spin, name="adbsat-demo-executor", daemon=True)
        spinner.start()
        deadline = time.monotonic() + 10.0
        while (
            attitude_pub.get_subscription_count() < 1
            or state_pub.get_subscription_count() < 1
            or node.wrench_pub.get_subscription_count() < 1
        ):
            if time.monotonic() > deadline:
                raise RuntimeError(
                    "the demo's publishers and the node did not discover each other in 10 s"
                )
            time.sleep(0.01)

        say()
        say(
            f"{'sim time':>9} {'altitude':>9} {'density':>10} {'C_D':>6} {'|F|':>10} {'|T|':>10} "
            f"{'compute':>8} {'latency':>8}"
            + (f" {demo_joints.TABLE_HEADER[0]}" if articulated else "")
        )
        say(
            f"{'[s]':>9} {'[km]':>9} {'[kg/m^3]':>10} {'[-]':>6} {'[N]':>10} {'[N m]':>10} "
            f"{'[ms]':>8} {'[ms]':>8}" + (f" {demo_joints.TABLE_HEADER[1]}" if articulated else "")
        )

        def table_line():
            with lock:
                key = latest[0]
                if key is None:
                    return
                wrench, _, wall = received[key]
            sample = log.samples.get(key)
            c = sample.conditions if sample is not None else None
            latency = 1e3 * (wall - sent_wall[key]) if key in sent_wall else math.nan
            say(
                f"{(key - t0_ns) * 1e-9:9.1f} "
                f"{(c.altitude * 1e-3 if c else math.nan):9.2f} "
                f"{(c.mass_density if c else math.nan):10.3e} "
                f"{(sample.drag_coefficient if sample else math.nan):6.3f} "
                f"{np.linalg.norm(vector(wrench.wrench.force)):10.3e} "
                f"{np.linalg.norm(vector(wrench.wrench.torque)):10.3e} "
                f"{(1e3 * sample.compute_seconds if sample else math.nan):8.2f} "
                f"{latency:8.2f}" + (f" {demo_joints.table_cells(sample)}" if articulated else "")
            )

        states, attitudes = messages.states, messages.attitudes
        start = time.monotonic()
        next_line = start + TABLE_PERIOD_S
        for wall, kind, i in _events(messages, speedup):
            target = start + wall
            while True:
                now = time.monotonic()
                if now >= next_line:
                    table_line()
                    next_line += TABLE_PERIOD_S
                if now >= target:
                    break
                time.sleep(min(target, next_line) - now)
            if kind == 0:  # (the twist is the ECI velocity)
                position, velocity = states.position_eci[i], states.velocity_eci[i]
                stamp_ns = int(states.stamps_ns[i])
                _send(state_pub, odometry_message(stamp_ns, "eci", "eci", position, velocity))
                result.states_sent += 1
            else:
                stamp_ns = int(attitudes.stamps_ns[i])
                if articulated:  # the fins' positions at this stamp, just before the attitude
                    fins = demo_joints.fin_positions(i / max(1, len(attitudes.stamps_ns) - 1))
                    _send(joints_pub, joint_state_message(stamp_ns, "", demo_joints.JOINTS, fins))
                quaternion = attitudes.quaternion_xyzw[i]
                sent_wall[stamp_ns] = time.monotonic()
                _send(attitude_pub, quaternion_stamped_message(stamp_ns, "eci", quaternion))
                result.attitudes_sent += 1
        deadline = time.monotonic() + DRAIN_TIMEOUT_S
        while time.monotonic() < deadline:
            with lock:
                done = sum(1 for v in received.values() if v[0] is not None and v[1] is not None)
            if done + sum(node.estimator.rejections.values()) >= result.attitudes_sent:
                break
            time.sleep(0.02)
        table_line()
    except KeyboardInterrupt:
        result.interrupted = True
        say("interrupted: stopping and writing what was received")
    finally:
        stop.set()
        if spinner is not None:
            spinner.join(timeout=2.0)
        if executor is not None:
            executor.shutdown(timeout_sec=1.0)
        for n in (client, node):
            if n is not None:
                n.destroy_node()
        rclpy.try_shutdown(context=context)

    samples = log.samples if log is not None else {}
    rows = table_rows(received, samples, sent_wall, t0_ns, result, joints=articulated)
    result.rejected = {
        k: v for k, v in (node.estimator.rejections.items() if node is not None else ()) if v
    }
    say()
    rejected = ", ".join(f"{k} {v}" for k, v in result.rejected.items())
    mismatched = f"; {result.mismatched} wrenches differ from the node's samples"
    say(
        f"published {result.attitudes_sent} attitudes and {result.states_sent} states; received "
        f"{result.wrenches_received} wrenches"
        + (f"; rejected: {rejected}" if result.rejected else "")
        + (mismatched if result.mismatched else "")
    )
    if rows:
        say(
            f"compute time p50 {result.compute_ms_p50:.2f} ms; end-to-end latency (attitude "
            f"published -> wrench received) p50 {result.latency_ms_p50:.2f} ms, "
            f"p99 {result.latency_ms_p99:.2f} ms"
        )
        latest = [s for _, s in sorted(samples.items()) if s.coefficients is not None]
        picture = None
        if latest and node is not None:
            sample = latest[-1]
            model = node.estimator.model
            mesh = model.mesh
            if sample.joints is not None and model.articulated:  # (posed for that wrench)
                mesh = model.body.mesh(dict(zip(sample.joints.names, sample.joints.positions)))
            picture = (model, mesh, sample.conditions.free_stream(), sample.coefficients)
        result.files = write_outputs(rows, Path(out_dir), picture, joints=articulated)
        say("wrote: " + ", ".join(str(p) for p in result.files))
    return result


def _send(publisher, msg) -> None:
    """Publish ``msg`` (built by :mod:`adbsat_ros.bags.io`) as its CDR bytes."""
    publisher.publish(bytes(serialize(msg)))
