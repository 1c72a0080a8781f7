"""Sweeps on Dask: against the database pool, scaling, overhead per task, a 10^5-point sweep.

Usage:
    python bench/bench_sweep.py [--workers 2] [--out-dir /tmp/bench_sweep]

Measured in one run, on LocalClusters of this machine started here (processes, one thread
each; their start-up is not counted), with the example satellite (4,192 faces), sentman,
ray-cast shading:

1. the 73 x 37 attitude database (aoa -180:5:180, aos -90:5:90) by ``build_database`` (the
   ``database`` command's process pool) and by a sweep of the same axes (chunks of the default
   256 points), both on ``--workers`` processes: wall time and ratio;
2. the same sweep on 1 and on 2 workers: scaling;
3. overhead per task: 2,000 points without shading as 2,000 one-point chunks and as 8 chunks of
   250: the difference per task;
4. a 4-axis sweep of 101,088 points (aoa 0:5:355 x aos -90:15:90 x speed 6800:200:8600 (10) x
   alpha 0.5:0.05:1.0 (11), chunks of 256): wall time, points per second, and the largest
   resident memory of a worker process.
"""

from __future__ import annotations

import argparse
import logging
import resource
import shutil
import time
from pathlib import Path

import numpy as np


def worker_peak_rss_mb() -> float:
    """The calling process's largest resident set [MB] (run on each worker)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def sweep_seconds(data: dict, out: Path, address: str) -> float:
    from adbsat_ros.sweep.engine import run_sweep
    from adbsat_ros.sweep.spec import parse_spec

    shutil.rmtree(out, ignore_errors=True)
    spec = parse_spec(data, "")
    t0 = time.perf_counter()
    report = run_sweep(spec, out, scheduler=address)
    assert report.computed == report.chunks
    return time.perf_counter() - t0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out-dir", default="/tmp/bench_sweep")
    args = parser.parse_args()
    import dask
    from distributed import Client, LocalCluster

    from adbsat_ros.database.build import build_database
    from adbsat_ros.geometry.example_satellite import example_satellite
    from adbsat_ros.physics.freestream import FreeStream
    from adbsat_ros.physics.panel_method import PanelMethod
    from adbsat_ros.sweep.engine import _worker_environment

    out = Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    attitudes = {
        "mesh": "example",
        "shading": "raycast",
        "axes": {"aoa": "-180:5:180", "aos": "-90:5:90"},
    }

    def cluster(n):  # (as run_sweep makes its own: see _worker_environment)
        with dask.config.set({"distributed.nanny.pre-spawn-environ": _worker_environment()}):
            return LocalCluster(
                n_workers=n,
                threads_per_worker=1,
                processes=True,
                dashboard_address=":0",
                silence_logs=logging.ERROR,
            )

    # 1. the database pool against the sweep, same workers
    method = PanelMethod(example_satellite(), "sentman", shading="none")
    flow = FreeStream(7700.0, 900.0, mean_mass_amu=16.0)
    t0 = time.perf_counter()
    build_database(
        method,
        flow,
        np.arange(-180.0, 180.1, 5.0),
        np.arange(-90.0, 90.1, 5.0),
        shading="raycast",
        workers=args.workers,
    )
    pool = time.perf_counter() - t0
    times = {}
    for n in (1, args.workers):
        with cluster(n) as c, Client(c) as client:
            client.wait_for_workers(n)
            times[n] = sweep_seconds(attitudes, out / f"db{n}.zarr", c.scheduler_address)
    print(f"73 x 37 attitudes: database pool ({args.workers} processes) {pool:.2f} s")
    print(
        f"73 x 37 attitudes: sweep on {args.workers} workers {times[args.workers]:.2f} s "
        f"(ratio to the pool {times[args.workers] / pool:.3f}); on 1 worker {times[1]:.2f} s "
        f"(speed-up 1 -> {args.workers}: {times[1] / times[args.workers]:.2f})"
    )

    # 3. overhead per task
    small = {"mesh": "example", "shading": "none", "axes": {"aoa": "0:0.18:359.82"}}
    with cluster(args.workers) as c, Client(c) as client:
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
    with cluster(args.workers) as c, Client(c) as client:
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
