"""Bag analysis CPU against another tree, interleaved: one process per tree analyses the same
simulated flight (example satellite at 9,600 faces, ray-cast shading, one worker, in process)
once per round, the trees taking turns; the median CPU time of each and their ratio.

Usage:
    python bench/bench_bag_rounds.py --baseline ../base1696 [--rounds 8] [--duration 60]
"""

from __future__ import annotations

import argparse
import itertools
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]


def serve(duration: float) -> None:
    """One tree's side: make the flight, analyse it once, then once per line on stdin."""
    from meshes import write_obj

    from adbsat_ros.bags import io as bag_io
    from adbsat_ros.bags import scenario
    from adbsat_ros.bags.analysis import analyze_bag
    from adbsat_ros.estimator.settings import WrenchSettings
    from adbsat_ros.geometry.example_satellite import example_satellite

    tmp = Path(tempfile.mkdtemp())
    write_obj(example_satellite(max_edge=0.064), tmp / "sat.obj")
    flight = scenario.Scenario(duration_s=duration, rate_hz=100.0, state_rate_hz=10.0)
    bag_io.write_scenario_bag(scenario.generate(flight), tmp / "in", storage="mcap")
    settings = WrenchSettings.from_parameters({"mesh": str(tmp / "sat.obj"), "shading": "raycast"})
    for k, _ in enumerate(itertools.chain(["warm-up"], sys.stdin)):
        t0 = time.process_time()
        out = tmp / f"out{k}"
        analyze_bag(
            tmp / "in",
            models=[("b", settings)],
            out_bag=out,
            out_csv=out.with_suffix(".csv"),
            storage="mcap",
            workers=1,
        )
        if k:
            print(f"{time.process_time() - t0:.4f}", flush=True)
        else:
            print("ready", flush=True)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--baseline", required=True)
    p.add_argument("--rounds", type=int, default=8)
    p.add_argument("--duration", type=float, default=60.0)
    p.add_argument("--serve", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.serve:
        serve(args.duration)
        return 0
    trees = [HERE, Path(args.baseline).resolve()]
    procs = [
        subprocess.Popen(
            [
                sys.executable,
                str(HERE / "bench" / "bench_bag_rounds.py"),
                "--serve",
                "--baseline",
                "-",
                "--duration",
                str(args.duration),
            ],
            cwd=tree,
            env=dict(os.environ, PYTHONPATH=str(tree)),
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
        )
        for tree in trees
    ]
    for proc in procs:
        assert proc.stdout.readline().strip() == "ready"
    cpu = [[], []]
    for r in range(args.rounds):
        for i in (0, 1) if r % 2 == 0 else (1, 0):
            procs[i].stdin.write("go\n")
            procs[i].stdin.flush()
            cpu[i].append(float(procs[i].stdout.readline()))
    for proc in procs:
        proc.stdin.close()
        proc.wait()
    now, before = (statistics.median(c) for c in cpu)
    paired = statistics.median(b / a for a, b in zip(*cpu))
    n = int(args.duration * 100) + 1
    print(
        f"{args.duration:g} s flight, {n} attitudes, CPU per analysis [s]: this tree {now:.3f} "
        f"({min(cpu[0]):.3f}-{max(cpu[0]):.3f}), {args.baseline} {before:.3f} "
        f"({min(cpu[1]):.3f}-{max(cpu[1]):.3f}); rate now / before {before / now:.3f}, "
        f"paired {paired:.3f}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
