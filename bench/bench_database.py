"""Benchmark of database builds and of the interpolating lookup.

(a) a 73 x 37 database (aoa -180:5:180, aos -90:5:90, 2701 attitudes) of a ~5k-face sphere
    (icosphere, 5120 faces; convex, so ray-cast shading has nothing to cast), Sentman, raycast,
    with 1 and 2 workers (target: under 10 s on 2 cores);
(b) the same grid on the example satellite (4192 faces, concave: real ray-cast shadows);
(c) the lookup: one scalar call (``CoefficientLookup.coefficients`` and the bare
    ``body_coefficients``) and the vectorised call per attitude.

Each build is timed once: wall clock (including the workers' start) and the CPU time of this
process (with one worker the whole build runs here, so that CPU time is its cost, whatever else
loads the machine); lookups are the median of repeated batches. Run::

    python bench/bench_database.py            # everything
    python bench/bench_database.py --quick    # skip (b)
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import trimesh

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's adbsat_ros first

from adbsat_ros import FreeStream, PanelMethod, panels_from_trimesh
from adbsat_ros.database.build import build_database
from adbsat_ros.database.lookup import CoefficientLookup
from adbsat_ros.geometry.loading import resolve_mesh

AOA = np.arange(-180.0, 180.001, 5.0)
AOS = np.arange(-90.0, 90.001, 5.0)
FLOW = FreeStream(7500.0, 900.0, mean_mass_amu=16.0)


def build(method, workers, spec):
    start, cpu = time.perf_counter(), time.process_time()
    db = build_database(
        method, FLOW, AOA, AOS, shading="raycast", workers=workers, progress=False, mesh_spec=spec
    )
    return db, time.perf_counter() - start, time.process_time() - cpu


def report_build(label, method, spec):
    results = {}
    for workers in (1, 2):
        db, seconds, cpu = build(method, workers, spec)
        results[workers] = db
        err = db.metadata["interpolation_error"]
        print(
            f"{label:<28} workers {workers}: {seconds:6.2f} s  "
            f"({1e3 * seconds / db.n_attitudes:.2f} ms/attitude, CPU of this process {cpu:.2f} s)  "
            f"stated error |dCf_G| {err['force_coefficient']:.2e}, "
            f"|dCm_G| {err['moment_coefficient']:.2e}",
            flush=True,
        )
    same = np.array_equal(results[1].Cf_G, results[2].Cf_G)
    print(f"{'':<28} workers 1 and 2 give identical Cf_G: {same}")
    return results[2]


def per_call_us(fn, calls, repeats=7):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append((time.perf_counter() - start) / calls)
    return 1e6 * statistics.median(times)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="skip the example-satellite build (b)")
    args = parser.parse_args(argv)
    print(f"command: {' '.join([os.path.basename(sys.executable)] + sys.argv)}")
    print(
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}"
    )
    print(
        f"grid: {AOA.size} aoa x {AOS.size} aos = {AOA.size * AOS.size} attitudes, Sentman, "
        "raycast (16 samples)"
    )

    sphere = panels_from_trimesh(trimesh.creation.icosphere(subdivisions=4), source="icosphere")
    db = report_build(f"(a) sphere {sphere.n_panels} faces", PanelMethod(sphere, "sentman"), None)
    if not args.quick:
        sat = resolve_mesh("example")
        db = report_build(
            f"(b) example {sat.n_panels} faces", PanelMethod(sat, "sentman"), "example"
        )

    lookup = CoefficientLookup(db)
    rng = np.random.default_rng(0)
    n = 20000
    a = rng.uniform(-180, 180, n)
    b = np.degrees(np.arcsin(rng.uniform(-1, 1, n)))
    al, bl = a.tolist(), b.tolist()

    def full():
        for x, y in zip(al, bl):
            lookup.coefficients(x, y)

    def body():
        for x, y in zip(al, bl):
            lookup.body_coefficients(x, y)

    u = np.stack(
        [
            -np.cos(np.radians(a)) * np.cos(np.radians(b)),
            np.sin(np.radians(b)),
            np.sin(np.radians(a)) * np.cos(np.radians(b)),
        ],
        axis=-1,
    )
    ul = list(u[:2000])

    def by_direction():
        for v in ul:
            lookup.coefficients(flow_direction=v)

    rows = (
        ("(c) lookup coefficients(aoa, aos) (Cf_G, Cm_G, CD, CL, CY):", full, n),
        ("    lookup coefficients(flow_direction=u_G):", by_direction, len(ul)),
        ("    lookup body_coefficients(aoa, aos) (Cf_G, Cm_G):", body, n),
    )
    for label, fn, calls in rows:
        print(f"{label:<61} {per_call_us(fn, calls, 5):6.1f} us/call")
    print(
        f"    body_coefficients_many, {n} attitudes:             "
        f"{per_call_us(lambda: lookup.body_coefficients_many(a, b), n, 5):6.1f} us/attitude"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
