"""CPU time per attitude of the estimator (the node's logic without ROS), one tree against others.

Usage:
    python bench/bench_estimator.py [--tree PATH ...] [--variant LABEL[:NAME=VALUE,...] ...]
        [--rounds 7] [--messages 2000] [--warmup 3000] [--max-edge 0.0625]

Each tree (default: this one; give ``--tree`` once per tree, e.g. ``--tree . --tree
/path/to/old/checkout``) runs in its own worker process that imports that tree's ``adbsat_ros``
(the package layout of either the subpackages or the older flat modules) and builds
``AeroWrenchEstimator`` with the default parameters (sentman, raycast shading cached at
0.25 deg, flight conditions on 10 ms knots, UNIX stamps) on ``example_satellite(max_edge)``
(~11,100 faces at 0.0625 m), or with the parameters of each ``--variant`` changed (e.g.
``--variant nearest:shading_interpolation=false --variant solar:solar_pressure=true``; values
as YAML reads them; every tree runs every variant). The workers then run the same message
stream: attitudes at 1 kHz turning slowly (0.5 deg/s about a tilted axis, so most lookups hit
the shading cache) and a state every 100 ms (``on_state``, a circular orbit at 300 km), with
``--warmup`` messages first.

Rounds are interleaved (ABAB...: each worker in turn runs the next ``--messages`` messages of its
stream), so that every tree sees the same spells of the shared machine. Each ``on_attitude`` call
is timed alone in CPU time of the worker's thread (``time.thread_time_ns``). Printed per tree:
the median over rounds of the round's median CPU time per attitude [us], the median over rounds
of the round's mean (shading-cache misses included) [us], and, against the first tree, the
median over rounds of the paired difference of the medians [us] and their ratio.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
from pathlib import Path

R_ORBIT = 6378137.0 + 300e3
V_ORBIT = math.sqrt(3.986004418e14 / R_ORBIT)
T0_NS = 1_767_225_600_000_000_000  # 2026-01-01T00:00:00Z, UNIX time [ns]
PERIOD_NS = 1_000_000  # 1 kHz attitudes
STATE_EVERY = 100  # a state every 100 attitudes (10 Hz)
TURN_RATE = math.radians(0.5)  # [rad/s]


def attitude(k: int) -> tuple:
    """Quaternion (x, y, z, w) of message k: a slow turn about a fixed tilted axis."""
    angle = 0.2 + TURN_RATE * k * PERIOD_NS * 1e-9
    axis = (0.3, 0.8, 0.52)
    norm = math.sqrt(sum(a * a for a in axis))
    s = math.sin(angle / 2) / norm
    return (axis[0] * s, axis[1] * s, axis[2] * s, math.cos(angle / 2))


def worker(tree: str, max_edge: float, changes: str) -> None:
    """Serve 'run N' requests on stdin with the CPU times [ns] of the next N attitudes."""
    sys.path.insert(0, str(Path(tree).resolve()))
    import time

    try:  # subpackages
        from adbsat_ros.estimator.estimator import AeroWrenchEstimator
        from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS
        from adbsat_ros.estimator.settings import WrenchSettings
        from adbsat_ros.geometry.example_satellite import example_satellite
    except ImportError:  # the flat layout
        from adbsat_ros.aero_wrench import AeroWrenchEstimator
        from adbsat_ros.example_satellite import example_satellite
        from adbsat_ros.wrench_settings import PARAMETER_DEFAULTS, WrenchSettings

    mesh = example_satellite(max_edge=max_edge)
    import yaml

    params = dict(PARAMETER_DEFAULTS)
    for item in filter(None, changes.split(",")):
        name, value = item.split("=", 1)
        params[name] = yaml.safe_load(value)
    estimator = AeroWrenchEstimator(WrenchSettings.from_parameters(params), mesh)
    clock = time.thread_time_ns
    k = 0
    print(json.dumps({"faces": mesh.n_panels}), flush=True)
    for line in sys.stdin:
        n = int(line.split()[1])
        times = []
        for _ in range(n):
            stamp_ns = T0_NS + k * PERIOD_NS
            stamp = stamp_ns * 1e-9
            if k % STATE_EVERY == 0:
                t = k * PERIOD_NS * 1e-9
                angle = V_ORBIT * t / R_ORBIT
                estimator.on_state(
                    stamp,
                    [R_ORBIT * math.cos(angle), R_ORBIT * math.sin(angle), 1e3],
                    [-V_ORBIT * math.sin(angle), V_ORBIT * math.cos(angle), 10.0],
                )
            q = attitude(k)
            t0 = clock()
            estimator.on_attitude(stamp, q)
            times.append(clock() - t0)
            k += 1
        print(json.dumps(times), flush=True)


class Worker:
    """One tree's worker process."""

    def __init__(self, tree: str, max_edge: float, variant: str = ""):
        label, _, changes = variant.partition(":")
        self.tree = f"{tree} {label}".strip()
        env = dict(os.environ, PYTHONPATH="")
        self.process = subprocess.Popen(
            [
                sys.executable,
                __file__,
                "--worker",
                tree,
                "--max-edge",
                str(max_edge),
                "--changes",
                changes,
            ],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
            env=env,
            cwd=str(Path(tree).resolve()),
        )
        self.faces = json.loads(self.process.stdout.readline())["faces"]

    def run(self, n: int) -> list:
        self.process.stdin.write(f"run {n}\n")
        self.process.stdin.flush()
        return json.loads(self.process.stdout.readline())

    def close(self) -> None:
        self.process.stdin.close()
        self.process.wait()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tree", action="append", help="source tree to time (repeatable)")
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--messages", type=int, default=2000, help="attitudes per round")
    parser.add_argument("--warmup", type=int, default=3000, help="attitudes before the rounds")
    parser.add_argument("--max-edge", type=float, default=0.0625)
    parser.add_argument(
        "--variant", action="append", help="LABEL[:NAME=VALUE,...] parameters changed (repeatable)"
    )
    parser.add_argument("--worker", help=argparse.SUPPRESS)
    parser.add_argument("--changes", default="", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        worker(args.worker, args.max_edge, args.changes)
        return
    sources = args.tree or [str(Path(__file__).resolve().parents[1])]
    workers = [
        Worker(tree, args.max_edge, variant) for tree in sources for variant in args.variant or [""]
    ]
    trees = [w.tree for w in workers]
    print(
        f"example satellite, {workers[0].faces} faces; sentman, raycast cached at 0.25 deg; "
        f"1 kHz attitudes, a state every 100 ms; {args.rounds} rounds of {args.messages}"
    )
    for w in workers:
        w.run(args.warmup)
    medians = {w.tree: [] for w in workers}
    means = {w.tree: [] for w in workers}
    for r in range(args.rounds):
        order = workers if r % 2 == 0 else workers[::-1]
        for w in order:
            times = w.run(args.messages)
            medians[w.tree].append(statistics.median(times) * 1e-3)
            means[w.tree].append(statistics.fmean(times) * 1e-3)
    for w in workers:
        w.close()
    first = trees[0]
    print(f"{'tree':<40} {'median us':>10} {'mean us':>10} {'- first us':>11} {'/ first':>8}")
    for tree in trees:
        diff = statistics.median(a - b for a, b in zip(medians[tree], medians[first]))
        ratio = statistics.median(a / b for a, b in zip(medians[tree], medians[first]))
        print(
            f"{tree:<40} {statistics.median(medians[tree]):10.1f} "
            f"{statistics.median(means[tree]):10.1f} {diff:11.1f} {ratio:8.3f}"
        )
    print("per round medians [us]:")
    for tree in trees:
        print(f"  {tree}: " + " ".join(f"{m:.1f}" for m in medians[tree]))


if __name__ == "__main__":
    main()
