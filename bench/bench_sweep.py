"""Sweeps on Dask: against the database pool, scaling, overhead per task, a 10^5-point sweep.

Usage:
    python bench/bench_sweep.py [--workers 2] [--baseline TREE] [--rounds 3]
                                [--out-dir /tmp/bench_sweep]

Measured in one run, with the example satellite (4,192 faces), sentman, ray-cast shading:

1. the ``database`` command (aoa -180:5:180 x aos -90:5:90, 2,701 attitudes, ``--workers``
   processes) as a whole process, start-up included: this tree (its task engine)
   against ``--baseline`` (a checkout of an earlier revision), the trees
   interleaved, the median of ``--rounds`` runs each of the wall time and of the CPU time (the
   process and its workers: less moved by a busy host than the wall time), and their ratios;
2. the same grid as a sweep (chunks of the default 256 points) on LocalClusters of 1 and of
   ``--workers`` workers started here (their start-up not counted): scaling;
3. overhead per task: 2,000 points without shading as 2,000 one-point chunks and as 8 chunks of
   250: the difference per task;
4. a 4-axis sweep of 102,960 points (aoa 0:5:355 x aos -90:15:90 x speed 6800:200:8600 (10) x
   alpha 0.5:0.05:1.0 (11), chunks of 256): wall time, points per second, and the largest
   resident memory of a worker process.
"""

from __future__ import annotations

import argparse
import resource
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

THIS_TREE = Path(__file__).resolve().parents[1]


def worker_peak_rss_mb() -> float:
    """The calling process's largest resident set [MB] (run on each worker)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def database_seconds(tree: Path, workers: int, out: Path) -> tuple:
    """Wall time and CPU time (user and system, the process and its workers) [s] of the
    ``database`` command of ``tree`` as a whole process (its working directory the tree, so
    that tree's package is imported): the 73 x 37 grid of the example satellite, sentman,
    ray-cast shading, on ``workers`` processes."""
    command = [sys.executable, "-m", "adbsat_ros.cli", "database", "example"]
    command += ["--speed", "7700", "--temperature", "900", "--mean-mass", "16"]
    command += ["--workers", str(workers), "--out", str(out / "database.npz")]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(command, cwd=tree, check=True, capture_output=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
    return wall, cpu


def sweep_seconds(data: dict, out: Path, address: str) -> float:
    from adbsat_ros.sweep.engine import run_sweep
    from adbsat_ros.sweep.spec import parse_spec

    shutil.rmtree(out, ignore_errors=True)
    spec = parse_spec(data, "")
    t0 = time.perf_counter()
    report = run_sweep(spec, out, scheduler=address)
    assert report.computed == report.chunks
    return time.perf_counter() - t0


def local_cluster(count: int):
    """A running scheduler's stand-in: a LocalCluster of ``count`` single-thread worker processes,
    started without ``MALLOC_TRIM_THRESHOLD_`` (docs/sweeps.md)."""
    import dask
    from distributed import LocalCluster

    environment = dict(dask.config.get("distributed.nanny.pre-spawn-environ", {}))
    environment.pop("MALLOC_TRIM_THRESHOLD_", None)
    with dask.config.set({"distributed.nanny.pre-spawn-environ": environment}):
        return LocalCluster(n_workers=count, threads_per_worker=1, dashboard_address=":0")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out-dir", default="/tmp/bench_sweep")
    parser.add_argument(
        "--baseline", help="a checkout whose database command is compared with this tree's"
    )
    parser.add_argument("--rounds", type=int, default=3, help="database runs per tree")
    args = parser.parse_args()
    from distributed import Client

    out = Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    attitudes = {
        "mesh": "example",
        "shading": "raycast",
        "axes": {"aoa": "-180:5:180", "aos": "-90:5:90"},
    }

    # 1. the database command, this tree against the baseline's, interleaved
    trees = {"this tree": THIS_TREE}
    if args.baseline:
        trees = {"baseline": Path(args.baseline).resolve(), **trees}
    walls = {name: [] for name in trees}
    cpus = {name: [] for name in trees}
    for _ in range(args.rounds):
        for name, tree in trees.items():
            wall, cpu = database_seconds(tree, args.workers, out)
            walls[name].append(wall)
            cpus[name].append(cpu)
    medians = {name: statistics.median(values) for name, values in walls.items()}
    cpu_medians = {name: statistics.median(values) for name, values in cpus.items()}
    for name, median in medians.items():
        spread = f"{min(walls[name]):.2f}..{max(walls[name]):.2f}"
        print(
            f"database, 73 x 37 attitudes, {args.workers} workers, {name} ({trees[name]}): "
            f"median {median:.2f} s over {args.rounds} ({spread}); CPU {cpu_medians[name]:.2f} s"
        )
    if args.baseline:
        print(
            f"ratio this tree / baseline: wall {medians['this tree'] / medians['baseline']:.3f}, "
            f"CPU {cpu_medians['this tree'] / cpu_medians['baseline']:.3f}"
        )

    # 2. the same grid as a sweep, on 1 and on 2 workers
    times = {}
    for n in (1, args.workers):
        with local_cluster(n) as c, Client(c) as client:
            client.wait_for_workers(n)
            times[n] = sweep_seconds(attitudes, out / f"db{n}.zarr", c.scheduler_address)
    print(
        f"73 x 37 attitudes as a sweep: {args.workers} workers {times[args.workers]:.2f} s; "
        f"1 worker {times[1]:.2f} s (speed-up 1 -> {args.workers}: "
        f"{times[1] / times[args.workers]:.2f})"
    )

    # 3. overhead per task
    small = {"mesh": "example", "shading": "none", "axes": {"aoa": "0:0.18:359.82"}}
    with local_cluster(args.workers) as c, Client(c) as client:
        client.wait_for_workers(args.workers)
        one = sweep_seconds({**small, "chunk_points": 1}, out / "one.zarr", c.scheduler_address)
        big = sweep_seconds({**small, "chunk_points": 250}, out / "big.zarr", c.scheduler_address)
    print(
        f"2,000 points, no shading: 2,000 tasks {one:.2f} s, 8 tasks {big:.2f} s: "
        f"{1e3 * (one - big) / (2000 - 8):.2f} ms per task of overhead"
    )

    # 4. 10^5 points
    four = {
        "mesh": "example",
        "shading": "raycast",
        "axes": {
            "aoa": "0:5:355",
            "aos": "-90:15:90",
            "speed": "6800:200:8600",
            "alpha": "0.5:0.05:1.0",
        },
        "chunk_points": 256,
    }
    with local_cluster(args.workers) as c, Client(c) as client:
        client.wait_for_workers(args.workers)
        seconds = sweep_seconds(four, out / "four.zarr", c.scheduler_address)
        peaks = client.run(worker_peak_rss_mb)
    points = 72 * 13 * 10 * 11
    print(
        f"4 axes, {points:,} points: {seconds:.1f} s on {args.workers} workers "
        f"({points / seconds:,.0f} points/s); largest worker resident set "
        f"{max(peaks.values()):.0f} MB; store {du(out / 'four.zarr'):.1f} MB"
    )


def du(path: Path) -> float:
    return sum(p.stat().st_size for p in path.rglob("*") if p.is_file()) / 1e6


if __name__ == "__main__":
    main()
