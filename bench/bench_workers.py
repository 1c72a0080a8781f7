"""Parallel jobs as whole processes: ``database``, ``sweep`` and ``bag analyze`` with the default
``--workers``, ``--workers 1`` and ``--workers 2``.

Jobs (sentman, ray-cast shading; ``T`` the T-shape of bench_concave_database.py, 864 faces,
``sphere`` an icosphere of 5,120 faces, ``example`` the example satellite, 4,192 faces):

* the small jobs: ``database`` of the sphere and of the T-shape over aoa -180:5:180 x aos
  -90:30:90 (``511``) and aos -90:5:90 (``2701``), and of the example over the 2,701;
* ``db 13357``: ``database`` of the example over aoa -180:1:180 x aos -90:5:90 (13,357
  attitudes, 10 s or more on one worker);
* ``sweep 40515``: ``sweep`` of the example over aoa -180:5:180 x aos -90:5:90 x speed 7200,
  7500, 7800 x alpha 0.6:0.1:1.0 (10 s or more on one worker);
* ``bag 600`` (only if named with ``--job``): ``bag analyze`` of a 600 s flight at 10 Hz (6,000
  attitudes, made once by ``simulate``).

Each variant is a fresh process (its working directory the tree measured, so that tree's package
is imported), after one untimed run of each job (the mesh store filled); rounds interleave the
variants (default, 1, 2; then 1, 2, default; ...) so that a change in the machine's load touches
all alike. Printed per job and variant: the median of
``--rounds`` wall times [s] and of the CPU times (user + system of the process and its workers),
the fastest and slowest wall, and the ratio of the median wall to that of ``--workers 1``; then
per job whether the default is no slower than one worker, and (for a job of 10 s or more on one)
whether two workers are at least 1.7 times as fast. Run::

    python bench/bench_workers.py --rounds 3
    python bench/bench_workers.py --job "db 13357" --rounds 3
"""

from __future__ import annotations

import argparse
import itertools
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import trimesh

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_concave_database import write_t_shape  # noqa: E402

THIS_TREE = Path(__file__).resolve().parents[1]
GAS = ["--speed", "7700", "--temperature", "900", "--mean-mass", "16"]
SWEEP = """mesh: example
model: sentman
shading: raycast
fixed: {temperature: 900, mean_mass_amu: 16}
axes:
  aoa: -180:5:180
  aos: -90:5:90
  speed: [7200, 7500, 7800]
  alpha: [0.6, 0.7, 0.8, 0.9, 1.0]
"""
VARIANTS = {"default": [], "1": ["--workers", "1"], "2": ["--workers", "2"]}


def jobs(folder: Path) -> dict:
    """Each job's command line (``adbsat-ros`` arguments) and the output to remove before it."""
    spec = folder / "sweep.yaml"
    spec.write_text(SWEEP)
    trimesh.creation.icosphere(subdivisions=4, radius=1.0).export(folder / "sphere.stl")
    write_t_shape(folder / "t.obj")
    out, table = folder / "db.npz", {}
    grids = {"511": "--aos=-90:30:90", "2701": "--aos=-90:5:90"}
    bodies = {"sphere": folder / "sphere.stl", "T": folder / "t.obj", "example": "example"}
    for (body, mesh), (size, aos) in itertools.product(bodies.items(), grids.items()):
        if (body, size) != ("example", "511"):
            table[f"db {body} {size}"] = (["database", str(mesh), *GAS, "--aoa=-180:5:180", aos],)
    table["db 13357"] = (["database", "example", *GAS, "--aoa=-180:1:180", "--aos=-90:5:90"],)
    table = {name: ([*argv, "--out", str(out)], out) for name, (argv,) in table.items()}
    table["sweep 40515"] = (
        ["sweep", str(spec), "--out", str(folder / "s.zarr"), "--no-progress"],
        folder / "s.zarr",
    )
    table["bag 600"] = (
        ["bag", "analyze", str(folder / "flight"), "--out", str(folder / "out"), "--overwrite"],
        folder / "out",
    )
    return table


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
        names = args.job or [name for name in table if name != "bag 600"]
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
        for name in names:  # untimed: the mesh store filled, the files and modules read once
            run_once(tree, table[name][0] + VARIANTS["1"], table[name][1])
        times = {(name, v): [] for name in names for v in VARIANTS}
        order = list(VARIANTS)
        for _ in range(args.rounds):
            for name in names:
                argv, output = table[name]
                for variant in order:
                    times[name, variant].append(run_once(tree, argv + VARIANTS[variant], output))
            order = order[1:] + order[:1]  # (each variant first in turn)
        print(
            f"{'job':<16} {'--workers':<10} {'wall s':>8} {'cpu s':>8} {'min':>7} {'max':>7}"
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
                    f"{name:<16} {variant:<10} {wall:8.2f} {cpu:8.2f} {min(walls):7.2f} "
                    f"{max(walls):7.2f} {wall / one:9.2f}"
                )
        for name in names:
            default, one, two = (statistics.median(w for w, _ in times[name, v]) for v in VARIANTS)
            verdict = f"{name:<16} default / 1 {default / one:5.2f} "
            verdict += "(ok)" if default <= one else "(SLOWER)"
            if one >= 10.0:
                verdict += f", 1 / 2 {one / two:5.2f} ({'ok' if one / two >= 1.7 else 'UNDER 1.7'})"
            print(verdict)
        print(f"# load average after: {os.getloadavg()[0]:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
