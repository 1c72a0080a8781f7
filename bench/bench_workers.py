"""Parallel jobs as whole processes: ``database``, ``sweep`` and ``bag analyze`` with the default
``--workers``, ``--workers 1`` and ``--workers 2``.

Jobs (the example satellite, 4,192 faces, sentman, ray-cast shading unless said):

* ``db 63``: ``database`` over aoa -180:45:180 x aos -90:30:90 (63 attitudes, well under a
  second on one worker);
* ``db 511``: aoa -180:5:180 x aos -90:30:90 (511 attitudes);
* ``db 2701``: aoa -180:5:180 x aos -90:5:90 (2,701 attitudes);
* ``sweep 1110``: ``sweep`` over aoa -180:10:180 x aos -90:30:90 x speed 7200, 7500, 7800,
  x alpha 0.6, 1.0 (chunks of 256 points);
* ``bag 600``: ``bag analyze`` of a 600 s flight at 10 Hz (6,000 attitudes, made once by
  ``simulate``).

Each variant is a fresh process (its working directory the tree measured, so that tree's package
is imported); rounds interleave the variants (default, 1, 2; then 1, 2, default; ...) so that a
change in the machine's load touches all alike. Printed per job and variant: the median of
``--rounds`` wall times [s] and of the CPU times (user + system of the process and its workers),
the fastest and slowest wall, and the ratio of the median wall to that of ``--workers 1``. Run::

    python bench/bench_workers.py --rounds 5
    python bench/bench_workers.py --job "db 2701" --rounds 3
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

THIS_TREE = Path(__file__).resolve().parents[1]
GAS = ["--speed", "7700", "--temperature", "900", "--mean-mass", "16"]
SWEEP = """mesh: example
model: sentman
shading: raycast
fixed: {temperature: 900, mean_mass_amu: 16}
axes:
  aoa: -180:10:180
  aos: -90:30:90
  speed: [7200, 7500, 7800]
  alpha: [0.6, 1.0]
"""
VARIANTS = {"default": [], "1": ["--workers", "1"], "2": ["--workers", "2"]}


def jobs(folder: Path) -> dict:
    """Each job's command line (``adbsat-ros`` arguments) and the output to remove before it."""
    spec = folder / "sweep.yaml"
    spec.write_text(SWEEP)
    db = ["database", "example", *GAS, "--out", str(folder / "db.npz")]
    return {
        "db 63": ([*db, "--aoa=-180:45:180", "--aos=-90:30:90"], folder / "db.npz"),
        "db 511": ([*db, "--aoa=-180:5:180", "--aos=-90:30:90"], folder / "db.npz"),
        "db 2701": ([*db, "--aoa=-180:5:180", "--aos=-90:5:90"], folder / "db.npz"),
        "sweep 1110": (
            ["sweep", str(spec), "--out", str(folder / "s.zarr"), "--no-progress"],
            folder / "s.zarr",
        ),
        "bag 600": (
            ["bag", "analyze", str(folder / "flight"), "--out", str(folder / "out"), "--overwrite"],
            folder / "out",
        ),
    }


def run_once(tree: Path, argv: list, output: Path) -> tuple:
    """Wall and CPU time [s] of one ``adbsat-ros`` process (and its workers)."""
    if output.is_dir():
        shutil.rmtree(output)
    elif output.exists():
        output.unlink()
    command = [sys.executable, "-m", "adbsat_ros.cli", *argv]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(command, cwd=tree, capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed:\n{done.stderr}")
    cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    return wall, cpu


def main() -> int:
    """Run the jobs and print the table; the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tree", type=Path, default=THIS_TREE, help="source tree to measure")
    parser.add_argument("--rounds", type=int, default=3, help="rounds (default 3)")
    parser.add_argument("--job", action="append", help="a job's name (repeat; default all)")
    args = parser.parse_args()
    tree = args.tree.resolve()
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        table = jobs(folder)
        names = args.job or list(table)
        if "bag 600" in names:
            argv = [
                "simulate",
                "--duration",
                "600",
                "--rate",
                "10",
                "--out",
                str(folder / "flight"),
            ]
            run_once(tree, argv, folder / "flight")
        print(
            f"# {tree}, {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f}, "
            f"{args.rounds} rounds"
        )
        times = {(name, v): [] for name in names for v in VARIANTS}
        order = list(VARIANTS)
        for _ in range(args.rounds):
            for name in names:
                argv, output = table[name]
                for variant in order:
                    times[name, variant].append(run_once(tree, argv + VARIANTS[variant], output))
            order = order[1:] + order[:1]  # (each variant first in turn)
        print(
            f"{'job':<12} {'--workers':<10} {'wall s':>8} {'cpu s':>8} {'min':>7} {'max':>7}"
            f" {'wall / 1':>9}"
        )
        for name in names:
            one = statistics.median(w for w, _ in times[name, "1"])
            for variant in VARIANTS:
                walls = [w for w, _ in times[name, variant]]
                wall, cpu = (
                    statistics.median(walls),
                    statistics.median(c for _, c in times[name, variant]),
                )
                print(
                    f"{name:<12} {variant:<10} {wall:8.2f} {cpu:8.2f} {min(walls):7.2f} "
                    f"{max(walls):7.2f} {wall / one:9.2f}"
                )
        print(f"# load average after: {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
