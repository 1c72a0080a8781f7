"""End-to-end latency and CPU per message of adbsat_node (attitude published -> wrench received)
against echo nodes, and against another tree's adbsat_node.

Usage:
    python bench/bench_node_latency.py [--rates 100,1000] [--duration 10] [--rounds 1] [--soak 60]
        [--max-edge 0.0625] [--shading raycast] [--coefficients-source panel|database]
        [--tumble DEG_PER_S] [--state-rate HZ] [--executor events|single_threaded] [--settle S]
        [--fastdds-profile config/fastdds_localhost.xml] [--echo-work-us US ...] [--echo-panel]
        [--baseline DIR_OR_REV] [--no-echo] [--keep-cpus-busy] [--param NAME:=VALUE ...]
        [--trace [--trace-part module:Class.method ...] [--trace-cpu]]

A/B of the node's CPU per message against an older tree, e.g. (a few rounds, 1 kHz):
    python bench/bench_node_latency.py --baseline ../baseline --rates 1000 --rounds 4 \
        --duration 5 --soak 0

Runs three processes per case: the node under test (adbsat_node on an 11,104-face example satellite,
or bench/echo_node.py), a publisher (Odometry at 10 Hz or --state-rate, QuaternionStamped at the
rate, slowly tumbling at 1 deg/s so the shading cache sees mostly hits, or fixed with --tumble 0)
and a receiver. Latency is receive time minus publish time of the same stamp on the shared
CLOCK_MONOTONIC. With --rounds N each case runs N times, the kinds alternating, and the latencies
are pooled; each echo run and the adbsat run after it are also compared as a pair (the p99 target
on the same spell of this shared machine), and the pooled verdict comes with the share of
bootstrap resamples of those pairs in which it holds (how much it depends on the spells met).

Two echoes, both bench/echo_node.py with rclpy message objects: "bare echo" is the textbook
rclpy node (``rclpy.spin(node)``, rclpy's default SingleThreadedExecutor), the latency reference;
"echo" is the same echo on the node's own executor (``--executor``, rclpy's EventsExecutor by
default), which costs it about half the CPU per message: against it, the target is the node's own
work alone. Every other kind is judged against both.
Reports p50/p99/max, messages dropped, the node's own compute time from /diagnostics, the node
process's CPU time per message answered, the share of attitudes whose flight conditions the node
had prepared ahead, the receiver's own longest hold-up (a thread that sleeps 10 ms at a time: a
stall of the measuring process itself would show there), and for the soak the node's resident
memory at the start and the end. Each case runs in a ROS domain of its own (BENCH_DOMAIN_ID and
up). Latencies of the messages sent in the first WARM_UP_S seconds of a run are left out (the
node's first ray cast); "held" counts the messages that took 100 ms or more after that.

With --echo-panel the rounds also run bench/echo_node.py as the panel method alone (attitudes in
and wrenches out as CDR bytes, the panel method with cached shading at a fixed free stream): what
the node's arithmetic costs in the running process, without its flight conditions, checks and
bookkeeping.

With --baseline DIR_OR_REV the rounds also run adbsat_node of another tree, right after this
tree's in every round: DIR is a checkout holding ``adbsat_ros`` (its package is copied to a
temporary folder), REV a git revision of this repository (extracted with ``git archive``); the
copy is put first on the node process's PYTHONPATH, and the node module is found in its layout
(``adbsat_ros.ros.node``, or ``adbsat_ros.node`` in the older flat one). The node before and
after a change, in the same spells of the machine. At the end, per rate, every kind's CPU time
per message answered and the ratio of this tree's node to the baseline's (pooled, and the median
of the rounds' ratios: each round's two runs met the same spell). --no-echo leaves the echoes
out (only the nodes compared).

With --keep-cpus-busy one busy loop per CPU runs at idle priority (nice 19) for the whole
benchmark: no CPU then sleeps between messages, and none is woken cold by the next one (the other
processes preempt the loops whenever they want the CPU).

With --trace this tree's node runs as bench/traced_node.py, which times its attitude callback's
parts (the decoding, the handler with the estimator inside it, the publishing, the preparing of
the next stamp) and the garbage collections inside the running process; their p50/p90/p99
follow the table. ``--trace-part module:Class.method`` (repeatable) times more functions so,
and with ``--trace-cpu`` each part also shows the CPU time its thread spent in it ("[thread
CPU]").

Middleware: by default every process runs with ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST, i.e.
rmw_fastrtps's own transports (shared memory with Fast DDS's default 1 s port health check, and
UDP). With --fastdds-profile the three processes instead run with
ROS_AUTOMATIC_DISCOVERY_RANGE=SYSTEM_DEFAULT and that Fast DDS XML profile (e.g.
config/fastdds_localhost.xml, which keeps traffic on 127.0.0.1 by itself).
"""

from __future__ import annotations

import argparse
import gc
import io
import itertools
import json
import math
import os
import shutil
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
REPOSITORY = HERE.parent
# this tree's adbsat_ros before any installed one, here and in the processes started from here
sys.path.insert(0, str(REPOSITORY))
os.environ["PYTHONPATH"] = os.pathsep.join(
    p for p in (str(REPOSITORY), os.environ.get("PYTHONPATH")) if p
)
R_ORBIT = 6378137.0 + 300e3
#: Seconds at the start of each run whose messages are not counted: the node's first ray cast
#: (~40 ms cold) and the messages queued behind it.
WARM_UP_S = 0.2
#: A latency at least this long [ms] is counted as a hold-up.
HELD_MS = 100.0
#: Bootstrap resamples of the round pairs behind the pooled verdict's share (pooled_target).
BOOTSTRAP_RESAMPLES = 1000
#: The latency target: the node's p99 latency under the echo's p99 plus this [ms].
TARGET_MARGIN_MS = 1.0
#: The kind that is the textbook rclpy echo: typed messages, ``rclpy.spin(node)`` (rclpy's default
#: executor). The kind "echo" is the same echo on the node's own executor (``--executor``).
BARE_ECHO = "bare echo"
#: The kinds the others are measured against.
REFERENCES = ("echo", BARE_ECHO)


def target_held(echo_p99_ms: float, other_p99_ms: float) -> bool:
    """Whether a p99 latency [ms] meets the target against the echo's p99 in the same rounds."""
    return other_p99_ms < echo_p99_ms + TARGET_MARGIN_MS


V_ORBIT = math.sqrt(3.986004418e14 / R_ORBIT)
#: The node module of this tree, and of the older flat layout (a baseline's).
NODE_MODULE, FLAT_NODE_MODULE = "adbsat_ros.ros.node", "adbsat_ros.node"


def baseline_package(spec: str) -> tuple:
    """(directory holding a copy of ``adbsat_ros``, its node module) of ``spec``: a checkout
    directory (its ``adbsat_ros`` copied, so nothing is written into it), or a git revision of
    this repository (extracted with ``git archive``)."""
    target = Path(tempfile.mkdtemp(prefix="bench-baseline-"))
    source = Path(spec)
    if (source / "adbsat_ros").is_dir():
        shutil.copytree(
            source / "adbsat_ros",
            target / "adbsat_ros",
            ignore=shutil.ignore_patterns("__pycache__", "*.pyc"),
        )
    else:
        archive = subprocess.run(
            ["git", "-C", str(REPOSITORY), "archive", "--format=tar", spec, "adbsat_ros"],
            check=True,
            capture_output=True,
        ).stdout
        with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
            tar.extractall(target, filter="data")
    package = target / "adbsat_ros"
    if (package / "ros" / "node.py").is_file():
        return str(target), NODE_MODULE
    if (package / "node.py").is_file():
        return str(target), FLAT_NODE_MODULE
    raise SystemExit(f"--baseline {spec}: no adbsat_ros/ros/node.py nor adbsat_ros/node.py in it")


def publisher(
    rate: float,
    duration: float,
    out: str,
    need_state: bool,
    tumble_deg_s: float,
    state_rate: float,
    settle: float,
) -> None:
    import rclpy
    from geometry_msgs.msg import QuaternionStamped
    from nav_msgs.msg import Odometry
    from rclpy.qos import QoSProfile

    rclpy.init()
    node = rclpy.create_node("bench_publisher")
    qos = QoSProfile(depth=100)
    att = node.create_publisher(QuaternionStamped, "attitude", qos)
    st = node.create_publisher(Odometry, "state", qos)
    deadline = time.monotonic() + 30
    ready = Path(out).parent / "receiver-ready"  # written by the receiver once it hears the node
    while (
        att.get_subscription_count() == 0
        or (need_state and st.get_subscription_count() == 0)
        or not ready.exists()
    ) and time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.05)
    time.sleep(settle)
    sent = {}  # stamp [ns] -> send time
    n = int(rate * duration)
    period = 1.0 / rate
    period_ns = round(1e9 / rate)
    start = time.monotonic()
    next_state = 0.0
    q = (
        QuaternionStamped()
    )  # one object refilled (publish serialises at once): little CPU taken from the node
    q.header.frame_id = "eci"
    for k in range(n):
        t = k * period
        # sleep to the absolute send time (no drift); no busy-wait, which would take CPU from the
        # node under test on this 2-core machine (latency is measured from the actual send time)
        delay = start + t - time.monotonic()
        if delay > 0.0:
            time.sleep(delay)
        stamp_ns = k * period_ns  # a regular stream, as a GNC loop stamps it
        sec, nanosec = divmod(stamp_ns, 1_000_000_000)
        if t >= next_state:
            o = Odometry()
            o.header.frame_id = o.child_frame_id = "eci"
            o.header.stamp.sec, o.header.stamp.nanosec = sec, nanosec
            o.pose.pose.position.x = R_ORBIT
            o.twist.twist.linear.y = V_ORBIT
            st.publish(o)
            next_state += 1.0 / state_rate
        angle = math.radians(tumble_deg_s) * t  # tumbling about z
        q.header.stamp.sec, q.header.stamp.nanosec = sec, nanosec
        q.quaternion.z, q.quaternion.w = math.sin(angle / 2), math.cos(angle / 2)
        sent[stamp_ns] = time.monotonic()
        att.publish(q)
    Path(out).write_text(json.dumps(sent))
    node.destroy_node()
    rclpy.try_shutdown()


class _StallMonitor:
    """A thread that sleeps 10 ms at a time and keeps its largest oversleep [ms]: how long this
    process (or its GIL) was held up, to tell a stall of the measuring receiver from one of the
    node or of the transport."""

    def __init__(self):
        import threading

        self.max_ms = 0.0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self):
        while not self._stop.is_set():
            t0 = time.monotonic()
            time.sleep(0.01)
            self.max_ms = max(self.max_ms, 1e3 * (time.monotonic() - t0 - 0.01))

    def stop(self):
        self._stop.set()
        self._thread.join()


def receiver(duration: float, out: str) -> None:
    import rclpy
    from geometry_msgs.msg import WrenchStamped
    from rclpy.qos import QoSProfile

    from adbsat_ros.messages.cdr import header_stamp
    from adbsat_ros.ros.node import make_executor

    rclpy.init()
    node = rclpy.create_node("bench_receiver")
    got = {}
    stalls = _StallMonitor()

    def on_wrench(raw):  # CDR bytes: only the stamp is read, so the receiver takes little CPU
        now = time.monotonic()
        sec, nanosec = header_stamp(raw)
        got[sec * 1_000_000_000 + nanosec] = now

    wrench_sub = node.create_subscription(
        WrenchStamped, "wrench", on_wrench, QoSProfile(depth=100), raw=True
    )
    diagnostics = {}

    def on_diagnostics(msg):
        for status in msg.status:
            diagnostics.update({kv.key: kv.value for kv in status.values})

    from diagnostic_msgs.msg import DiagnosticArray

    node.create_subscription(DiagnosticArray, "/diagnostics", on_diagnostics, 10)
    executor = make_executor("events")
    executor.add_node(node)
    end = time.monotonic() + duration
    ready = Path(out).parent / "receiver-ready"
    while time.monotonic() < end and wrench_sub.get_publisher_count() == 0:
        executor.spin_once(timeout_sec=0.1)
    ready.touch()  # matched with the node's publisher: the publisher may start
    while time.monotonic() < end:
        executor.spin_once(timeout_sec=0.1)
    stalls.stop()
    Path(out).write_text(
        json.dumps({"wrench": got, "diagnostics": diagnostics, "receiver_stall_ms": stalls.max_ms})
    )
    node.destroy_node()
    rclpy.try_shutdown()


def rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    return float("nan")


def cpu_seconds(pid: int) -> float:
    """User + system CPU time [s] of a process so far (/proc/PID/stat fields 14 and 15)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def wait_until_idle(pid: int, timeout: float = 60.0) -> None:
    """Return when the process has used under 10 ms of CPU in 0.3 s (start-up done)."""
    deadline = time.monotonic() + timeout
    last = cpu_seconds(pid)
    while time.monotonic() < deadline:
        time.sleep(0.3)
        now = cpu_seconds(pid)
        if now - last < 0.01:
            return
        last = now


_CASE_NUMBERS = itertools.count()


def run_case(
    kind: str,
    rate: float,
    duration: float,
    mesh: str,
    args,
    measure_memory=False,
    echo_work_us: float = 0.0,
    package: tuple | None = None,
) -> dict:
    """One run of ``kind``: "adbsat..." (the node of ``package``, (directory holding
    ``adbsat_ros``, node module), if given, else of this tree), or an echo spinning
    ``echo_work_us`` per message."""
    env = dict(os.environ)
    if args.fastdds_profile:  # the profile keeps discovery on the machine itself
        env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "SYSTEM_DEFAULT"
        env["FASTRTPS_DEFAULT_PROFILES_FILE"] = str(Path(args.fastdds_profile).resolve())
    else:
        env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
        env.pop("FASTRTPS_DEFAULT_PROFILES_FILE", None)
    # every case in a domain of its own: the participants of the case before (stopped a moment
    # ago, still known to discovery) are then never seen by this one
    base = int(env.get("BENCH_DOMAIN_ID", str(40 + os.getpid() % 20)))
    env["ROS_DOMAIN_ID"] = str(base + next(_CASE_NUMBERS) % 40)
    env["ECHO_QOS_DEPTH"] = "100"
    env["ECHO_EXECUTOR"] = "rclpy.spin" if kind == BARE_ECHO else args.executor
    env["ECHO_WORK_US"] = str(echo_work_us)
    env["ECHO_PANEL_MESH"] = mesh if kind == "echo+panel" else ""
    env["TRACED_PARTS"] = ",".join(args.trace_part)
    env["TRACE_CPU"] = "1" if args.trace_cpu else ""
    # The node's package first on its path: a baseline's extracted package, else this tree's own
    # (REPOSITORY). The node runs in a directory of its own: with ``python -m`` the working
    # directory comes before PYTHONPATH, and the tree the bench is started from would shadow a
    # baseline's package.
    node_env = dict(env)
    node_env["PYTHONPATH"] = os.pathsep.join(
        p for p in (package[0] if package else str(REPOSITORY), env.get("PYTHONPATH")) if p
    )
    if not kind.startswith("adbsat"):
        node_cmd = [sys.executable, str(HERE / "echo_node.py")]
    else:
        if package:  # another tree's node, untraced (traced_node wraps this tree's)
            node_program = ["-m", package[1]]
        elif args.trace:
            node_program = [str(HERE / "traced_node.py")]
        else:
            node_program = ["-m", NODE_MODULE]
        node_cmd = [
            sys.executable,
            *node_program,
            "--ros-args",
            "-p",
            f"mesh:={mesh}",
            "-p",
            "time_mode:=epoch",
            "-p",
            f"shading:={args.shading}",
            "-p",
            "qos_depth:=100",
            "-p",
            f"coefficients_source:={args.coefficients_source}",
            "-p",
            f"executor:={args.executor}",
        ]
        if args.database:
            node_cmd += ["-p", f"database_path:={args.database}"]
        if not package:  # (this tree's node: parameters the other tree may not have)
            for item in args.param:
                node_cmd += ["-p", item]
    tmp = Path(tempfile.mkdtemp())
    node_log = open(
        tmp / "node.log", "w"
    )  # a file, not a pipe nobody reads (a full pipe would block the node)
    node = subprocess.Popen(
        node_cmd, env=node_env, cwd=tmp, stdout=node_log, stderr=subprocess.STDOUT
    )
    time.sleep(0.5)
    wait_until_idle(node.pid)
    recv = subprocess.Popen(
        [
            sys.executable,
            __file__,
            "--role",
            "receiver",
            "--duration",
            str(duration + 8 + args.settle),
            "--out",
            str(tmp / "recv.json"),
        ],
        env=env,
    )
    pub = subprocess.Popen(
        [
            sys.executable,
            __file__,
            "--role",
            "publisher",
            "--rate",
            str(rate),
            "--duration",
            str(duration),
            "--out",
            str(tmp / "sent.json"),
            "--tumble",
            str(args.tumble),
            "--state-rate",
            str(args.state_rate),
            "--settle",
            str(args.settle),
        ]
        + (["--need-state"] if kind.startswith("adbsat") else []),
        env=env,
    )
    cpu_start = cpu_seconds(node.pid)  # the node is idle here: set up, waiting for messages
    mem_start = None
    if measure_memory:
        time.sleep(8.0)  # discovery + warm-up
        mem_start = rss_mb(node.pid)
    pub.wait()
    cpu_end = cpu_seconds(node.pid)
    recv.wait()
    mem_end = rss_mb(node.pid) if measure_memory else None
    node.terminate()
    try:
        node.wait(timeout=10)
    except subprocess.TimeoutExpired:
        node.kill()
    node_log.close()
    trace = {}
    for line in (tmp / "node.log").read_text().splitlines():
        if line.startswith("TRACE "):
            trace = json.loads(line[len("TRACE ") :])
    sent = json.loads((tmp / "sent.json").read_text())
    received = json.loads((tmp / "recv.json").read_text())
    got, diagnostics = received["wrench"], received["diagnostics"]
    first = min(sent.values())
    counted = [k for k in sent if sent[k] - first >= WARM_UP_S]
    lat = np.array([got[k] - sent[k] for k in counted if k in got]) * 1e3
    return {
        "kind": kind,
        "rate_hz": rate,
        "sent": len(sent),
        "received": sum(k in got for k in sent),
        "latencies_ms": lat,
        "cpu_s": cpu_end - cpu_start,
        "rss_start_mb": mem_start,
        "rss_end_mb": mem_end,
        "compute_p50_ms": float(diagnostics.get("compute_ms_p50", "nan")),
        "compute_p99_ms": float(diagnostics.get("compute_ms_p99", "nan")),
        "compute_max_ms": float(diagnostics.get("compute_ms_max", "nan")),
        "prepared": float(diagnostics.get("conditions_prepared_used", "nan")),
        "published": float(
            diagnostics.get("published", "nan")
        ),  # wrenches the node made (some may be dropped)
        "receiver_stall_ms": received["receiver_stall_ms"],
        "trace_us": trace,
    }


def pooled(rounds: list) -> dict:
    """One figure set from the rounds of one case: latencies pooled, counts summed, the node's own
    compute p50/p99 averaged over rounds and its maximum kept."""
    warm = np.concatenate([r["latencies_ms"] for r in rounds])
    sent = sum(r["sent"] for r in rounds)
    received = sum(r["received"] for r in rounds)
    return {
        "sent": sent,
        "dropped": sent - received,
        "p50_ms": float(np.percentile(warm, 50)) if warm.size else float("nan"),
        "p99_ms": float(np.percentile(warm, 99)) if warm.size else float("nan"),
        "max_ms": float(warm.max()) if warm.size else float("nan"),
        "compute_p50_ms": float(np.mean([r["compute_p50_ms"] for r in rounds])),
        "compute_p99_ms": float(np.mean([r["compute_p99_ms"] for r in rounds])),
        "compute_max_ms": float(np.max([r["compute_max_ms"] for r in rounds])),
        "held": int(np.count_nonzero(warm >= HELD_MS)),
        "runs_held": sum(int(np.any(r["latencies_ms"] >= HELD_MS)) for r in rounds),
        "cpu_ms_per_message": 1e3 * sum(r["cpu_s"] for r in rounds) / max(received, 1),
        "prepared_share": sum(r["prepared"] for r in rounds)
        / max(sum(r["published"] for r in rounds), 1),
        "receiver_stall_ms": max(r["receiver_stall_ms"] for r in rounds),
        "rss_start_mb": rounds[0]["rss_start_mb"],
        "rss_end_mb": rounds[-1]["rss_end_mb"],
    }


def pooled_target(
    echo_rounds: list, other_rounds: list, resamples: int | None = None, seed: int = 0
) -> tuple:
    """(echo p99, other p99, share): the pooled p99 latencies [ms] of two kinds' rounds, and the
    share of bootstrap resamples in which the other kind's pooled p99 meets the target
    (target_held).

    Each resample draws as many round pairs as were run, with replacement, keeping each echo run
    with the run of the other kind after it (the same spell of the machine), and pools their
    latencies as :func:`pooled` does: how much the pooled verdict depends on which spells the
    rounds happened to meet.
    """
    resamples = BOOTSTRAP_RESAMPLES if resamples is None else resamples
    pairs = [(e["latencies_ms"], o["latencies_ms"]) for e, o in zip(echo_rounds, other_rounds)]
    if not pairs or any(e.size == 0 or o.size == 0 for e, o in pairs):
        return math.nan, math.nan, 0.0

    def p99(arrays) -> float:
        return float(np.percentile(np.concatenate(arrays), 99))

    echo_p99, other_p99 = p99([e for e, _ in pairs]), p99([o for _, o in pairs])
    rng = np.random.default_rng(seed)
    held = 0
    for _ in range(resamples):
        chosen = rng.integers(0, len(pairs), size=len(pairs))
        held += target_held(p99([pairs[i][0] for i in chosen]), p99([pairs[i][1] for i in chosen]))
    return echo_p99, other_p99, held / resamples


def build_node_database(mesh_path: Path) -> str:
    """A database (aoa -180:5:180 x aos -90:5:90, raycast) for the node's default set-up on the
    mesh."""
    from adbsat_ros.database.build import build_database
    from adbsat_ros.estimator.estimator import AeroWrenchEstimator
    from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS
    from adbsat_ros.estimator.settings import WrenchSettings
    from adbsat_ros.physics.freestream import FreeStream

    settings = WrenchSettings.from_parameters(
        dict(PARAMETER_DEFAULTS, mesh=str(mesh_path), shading="none")
    )
    method = AeroWrenchEstimator(settings).method
    flow = FreeStream(speed=7726.0, temperature=934.0, mean_mass_amu=17.9, density=2.4e-11)
    t0 = time.perf_counter()
    db = build_database(
        method,
        flow,
        np.arange(-180.0, 180.1, 5.0),
        np.arange(-90.0, 90.1, 5.0),
        shading="raycast",
        mesh_spec=str(mesh_path),
        progress=False,
    )
    path = str(mesh_path.with_suffix(".npz"))
    db.save(path)
    print(
        f"database: {db.n_attitudes} attitudes built in {time.perf_counter() - t0:.1f} s -> {path}"
    )
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--role", choices=["main", "publisher", "receiver"], default="main")
    parser.add_argument("--rate", type=float, default=100.0)
    parser.add_argument("--rates", default="100,1000")
    parser.add_argument("--duration", type=float, default=10.0)
    parser.add_argument("--soak", type=float, default=60.0)
    parser.add_argument(
        "--max-edge",
        type=float,
        default=0.0625,
        help="longest edge [m] of the example satellite's triangles (0.0625: 11,104 faces)",
    )
    parser.add_argument("--shading", default="raycast")
    parser.add_argument(
        "--param",
        action="append",
        default=[],
        metavar="NAME:=VALUE",
        help="a parameter of this tree's node only, e.g. shading_interpolation:=false to compare "
        "with a tree that had no interpolation",
    )
    parser.add_argument("--coefficients-source", default="panel")
    parser.add_argument("--database", default="")
    parser.add_argument(
        "--tumble",
        type=float,
        default=1.0,
        help="attitude rotation rate [deg/s] about z; 0 = fixed attitude (cache hits only)",
    )
    parser.add_argument(
        "--executor",
        default="events",
        choices=["events", "single_threaded"],
        help="rclpy executor of the node under test and of the echo node",
    )
    parser.add_argument(
        "--state-rate", type=float, default=10.0, help="Odometry messages per second [Hz]"
    )
    parser.add_argument(
        "--rounds",
        type=int,
        default=1,
        help="runs of each case (echo and adbsat alternating) pooled into one figure set",
    )
    parser.add_argument(
        "--settle",
        type=float,
        default=0.5,
        help="seconds between the receiver matching and the first message",
    )
    parser.add_argument(
        "--fastdds-profile",
        default="",
        help="Fast DDS XML profile for all three processes (with "
        "ROS_AUTOMATIC_DISCOVERY_RANGE=SYSTEM_DEFAULT); default: rmw_fastrtps's "
        "LOCALHOST set-up",
    )
    parser.add_argument(
        "--echo-work-us",
        type=float,
        action="append",
        default=[],
        metavar="US",
        help="also run an echo that spins US microseconds per message (repeatable): "
        "a node of known CPU cost beside adbsat, in the same rounds",
    )
    parser.add_argument(
        "--echo-panel",
        action="store_true",
        help="also run an echo that computes the panel method per message (raw CDR in and "
        "out, cached shading, a fixed free stream): the node's arithmetic alone",
    )
    parser.add_argument(
        "--baseline",
        metavar="DIR_OR_REV",
        help="also run the adbsat_node of another tree in the same rounds: a checkout directory "
        "holding adbsat_ros (flat or subpackage layout), or a git revision of this repository",
    )
    parser.add_argument(
        "--no-echo",
        action="store_true",
        help="run no echo node: only this tree's node (and the baseline's)",
    )
    parser.add_argument(
        "--keep-cpus-busy",
        action="store_true",
        help="run one idle-priority (nice 19) busy loop per CPU for the whole benchmark, so that "
        "no CPU sleeps between messages (the cost of a CPU woken from idle, "
        "docs/benchmarks.md); every process then gets the CPU whenever it wants it",
    )
    parser.add_argument(
        "--trace",
        action="store_true",
        help="time the adbsat node's callback parts in the running process (bench/traced_node.py)",
    )
    parser.add_argument(
        "--trace-part",
        action="append",
        default=[],
        metavar="MODULE:QUALNAME",
        help="with --trace, also time this function (e.g. adbsat_ros.physics.panel_method:"
        "PanelMethod.coefficients); repeatable",
    )
    parser.add_argument(
        "--trace-cpu",
        action="store_true",
        help="with --trace, also record each part's thread CPU time (wall time above it is "
        "time the node's thread waited: preempted, or on a lock)",
    )
    parser.add_argument("--out", default="")
    parser.add_argument(
        "--need-state", action="store_true", help="(publisher) wait for a state subscriber"
    )
    args = parser.parse_args()
    if args.role in ("publisher", "receiver"):
        # the measuring processes: no garbage collection pauses of their own in the figures
        # (a run allocates little that lives; everything is freed at exit)
        gc.disable()
    if args.role == "publisher":
        return publisher(
            args.rate,
            args.duration,
            args.out,
            args.need_state,
            args.tumble,
            args.state_rate,
            args.settle,
        )
    if args.role == "receiver":
        return receiver(args.duration, args.out)

    from meshes import write_obj

    from adbsat_ros.geometry.example_satellite import example_satellite

    mesh = example_satellite(max_edge=args.max_edge)
    mesh_path = Path(tempfile.mkdtemp()) / "satellite.obj"
    write_obj(mesh, mesh_path)
    if args.coefficients_source == "database" and not args.database:
        args.database = build_node_database(mesh_path)
    middleware = (
        f"profile {args.fastdds_profile}" if args.fastdds_profile else "rmw_fastrtps LOCALHOST"
    )
    print(
        f"mesh: example satellite, {mesh.n_panels} faces; shading {args.shading}; "
        f"coefficients {args.coefficients_source}; attitude tumbling at {args.tumble:g} deg/s; "
        f"middleware: {middleware}"
    )
    # the kinds of node, each with the work [us] its echo spins per message (none for a node);
    # in each round the bare echo right before adbsat (each reference beside a run after it),
    # and a baseline's node right after it
    echo_work = {} if args.no_echo else {"echo": 0.0, BARE_ECHO: 0.0}
    echo_work["adbsat"] = 0.0
    packages = {}  # kind -> (package directory, node module), for nodes of other trees
    if args.baseline:
        package = baseline_package(args.baseline)
        kind = f"adbsat@{Path(args.baseline).name[:12] or args.baseline[:7]}"
        print(f"baseline {args.baseline}: node module {package[1]} from {package[0]}")
        packages[kind] = package
        echo_work[kind] = 0.0
    if not args.no_echo:
        echo_work.update({f"echo+{us:g}us": us for us in args.echo_work_us})
        if args.echo_panel:
            echo_work["echo+panel"] = 0.0
    print(TABLE_HEADER)
    spinners = (
        [
            subprocess.Popen([sys.executable, "-c", "import os\nos.nice(19)\nwhile True: pass"])
            for _ in range(os.cpu_count() or 1)
        ]
        if args.keep_cpus_busy
        else []
    )
    try:
        run_all(args, str(mesh_path), echo_work, packages)
    finally:
        for spinner in spinners:
            spinner.kill()
            spinner.wait()


TABLE_HEADER = (
    f"{'node':>15} {'rate Hz':>8} {'sent':>7} {'dropped':>8} {'p50 ms':>8} {'p99 ms':>8}"
    f" {'max ms':>8} {'held':>5} {'runs held':>9} {'compute p50':>12} {'compute p99':>12}"
    f" {'compute max':>12} {'CPU/msg ms':>11} {'prepared':>9} {'recv hold-up':>12}"
)


def table_line(kind: str, rate: float, runs: list) -> str:
    """The figures of one kind's runs at one rate (see TABLE_HEADER)."""
    r = pooled(runs)
    return (
        f"{kind:>15} {rate:8.0f} {r['sent']:7d} {r['dropped']:8d} {r['p50_ms']:8.3f}"
        f" {r['p99_ms']:8.3f} {r['max_ms']:8.2f} {r['held']:5d} {r['runs_held']:4d} of"
        f" {len(runs):<2d} {r['compute_p50_ms']:12.3f} {r['compute_p99_ms']:12.3f}"
        f" {r['compute_max_ms']:12.3f} {r['cpu_ms_per_message']:11.3f}"
        f" {r['prepared_share']:9.1%} {r['receiver_stall_ms']:12.1f}"
    )


def cpu_ms_per_message(run: dict) -> float:
    """The node process's CPU time [ms] per wrench received in one run."""
    return 1e3 * run["cpu_s"] / max(run["received"], 1)


def cpu_summary(rate: float, rounds: dict, packages: dict) -> list:
    """Lines: each kind's CPU per message [ms] (pooled, and each round's), and this tree's node
    against each baseline's: the pooled ratio and the median of the rounds' ratios."""
    lines = [f"CPU per message at {rate:.0f} Hz [ms] (pooled; each round):"]
    for kind, runs in rounds.items():
        each = ", ".join(f"{cpu_ms_per_message(r):.3f}" for r in runs)
        lines.append(f"  {kind:>15} {pooled(runs)['cpu_ms_per_message']:8.3f}   ({each})")
    for kind in packages:
        ratios = [
            cpu_ms_per_message(a) / cpu_ms_per_message(b)
            for a, b in zip(rounds["adbsat"], rounds[kind])
        ]
        ratio = (
            pooled(rounds["adbsat"])["cpu_ms_per_message"]
            / pooled(rounds[kind])["cpu_ms_per_message"]
        )
        lines.append(
            f"  node / baseline (adbsat / {kind}): pooled {ratio:.3f}, median of rounds "
            f"{float(np.median(ratios)):.3f} ({', '.join(f'{x:.3f}' for x in ratios)})"
        )
    return lines


def run_all(args, mesh_path: str, echo_work: dict, packages: dict) -> None:
    """The rounds at every rate, the pairs, the CPU summary and the soak, printed."""
    pairs = []
    summaries = []
    for rate in (float(r) for r in args.rates.split(",")):
        # the kinds alternate, round after round: a slow spell of this shared machine then
        # falls on all of them rather than on one
        rounds = {kind: [] for kind in echo_work}
        for _ in range(args.rounds):
            for kind in rounds:
                rounds[kind].append(
                    run_case(
                        kind,
                        rate,
                        args.duration,
                        mesh_path,
                        args,
                        echo_work_us=echo_work[kind],
                        package=packages.get(kind),
                    )
                )
        for kind in rounds:
            print(table_line(kind, rate, rounds[kind]))
        if args.trace:
            print_trace(rate, rounds)
        summaries.append(cpu_summary(rate, rounds, packages))
        if args.rounds > 1 and not args.no_echo:
            pairs.append((rate, rounds))
    for rate, rounds in pairs:  # each echo run beside the runs after it in its round
        for line in pair_lines(rate, rounds):
            print(line)
    for lines in summaries:
        print("\n".join(lines))
    if args.soak > 0:
        r = pooled([run_case("adbsat", 1000.0, args.soak, mesh_path, args, measure_memory=True)])
        print(
            f"soak {args.soak:.0f} s at 1 kHz: sent {r['sent']}, dropped {r['dropped']}, "
            f"p50 {r['p50_ms']:.3f} ms, p99 {r['p99_ms']:.3f} ms, max {r['max_ms']:.1f} ms, "
            f"RSS {r['rss_start_mb']:.1f} -> {r['rss_end_mb']:.1f} MB "
            f"(growth {r['rss_end_mb'] - r['rss_start_mb']:.1f} MB)"
        )


def print_trace(rate: float, rounds: dict) -> None:
    """The traced parts' p50/p90/p99 of this tree's node (--trace)."""
    parts: dict = {}
    for run in rounds["adbsat"]:
        for part, durations in run["trace_us"].items():
            parts.setdefault(part, []).extend(durations)
    for part, durations in parts.items():
        if durations:
            p50, p90, p99 = np.percentile(durations, [50, 90, 99])
            print(
                f"{'adbsat':>15} {rate:8.0f} {part:<34} p50 {p50:7.1f} us  p90 {p90:7.1f} us  "
                f"p99 {p99:7.1f} us  ({len(durations)} calls)"
            )


def pair_lines(rate: float, rounds: dict) -> list:
    """Each reference (echo) run against the runs after it in its round, and pooled."""
    lines = []
    for reference in REFERENCES:
        for other in (kind for kind in rounds if kind not in REFERENCES):
            verdicts = []
            for echo, run in zip(rounds[reference], rounds[other]):
                e, a = (
                    float(np.percentile(r["latencies_ms"], 99))
                    if r["latencies_ms"].size
                    else math.inf
                    for r in (echo, run)
                )
                verdicts.append(f"{e:.2f}/{a:.2f} {'held' if target_held(e, a) else 'MISSED'}")
            held = sum(v.endswith("held") for v in verdicts)
            lines.append(
                f"pairs at {rate:.0f} Hz, p99 ms {reference}/{other}, target {other} < "
                f"{reference} + 1 ms: {'; '.join(verdicts)} -> held in {held} of {len(verdicts)}"
            )
            pooled_echo, pooled_other, share = pooled_target(rounds[reference], rounds[other])
            verdict = "held" if target_held(pooled_echo, pooled_other) else "MISSED"
            lines.append(
                f"pooled at {rate:.0f} Hz, p99 ms {reference}/{other}: {pooled_echo:.2f}/"
                f"{pooled_other:.2f} {verdict}; held in {share:.0%} of {BOOTSTRAP_RESAMPLES} "
                "resamples of the round pairs"
            )
    return lines


if __name__ == "__main__":
    main()
