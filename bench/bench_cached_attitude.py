"""Cost of one attitude on a ~10k-face mesh when the shading comes from the cache.

Usage:
    python bench/bench_cached_attitude.py [--max-edge 0.064] [--repeat 3000]

Cases, on the example satellite refined to ~9,600 faces, sentman, raycast shading cached at
0.25 deg:

* "same cell": consecutive attitudes in one cache cell (a GNC loop at a high rate): the latest
  cell answers, and the panel method's facet sums of its lighting are kept;
* "stored cells": every query in another cell, all already in the cache (the lighting is
  stored; its facet sums are made again when it is not among the latest few);
* "estimator": AeroWrenchEstimator.on_attitude, i.e. the node's whole per-message work
  (flight conditions from the knot grid, rotation, cache, panel method), same cell;
* the same at 100 Hz, sleeping 10 ms before each message (the cost after the CPU idled), without
  and with the flight conditions prepared ahead (``AeroWrenchEstimator.prepare``, as the node
  does right after each wrench).

Prints the median and 99th percentile of each in milliseconds (wall time; for CPU time per
attitude against another source tree see ``bench/bench_estimator.py``).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's adbsat_ros first

from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.geometry import frames
from adbsat_ros.geometry.example_satellite import example_satellite
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.shading.cache import ShadingCache
from adbsat_ros.shading.shader import make_shader


def percentiles(samples_s):
    ms = np.asarray(samples_s) * 1e3
    return float(np.percentile(ms, 50)), float(np.percentile(ms, 99))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-edge", type=float, default=0.064)
    parser.add_argument("--repeat", type=int, default=3000)
    args = parser.parse_args()
    mesh = example_satellite(max_edge=args.max_edge)
    method = PanelMethod(mesh, "sentman")
    flow = FreeStream(speed=7726.0, temperature=934.0, mean_mass_amu=17.9, density=2.4e-11)
    cache = ShadingCache(make_shader(mesh, mode="raycast"), resolution_deg=0.25)
    n = args.repeat
    print(
        f"mesh: example satellite, {mesh.n_panels} faces; sentman; raycast cached at 0.25 deg; "
        f"{n} calls per case"
    )

    # same cell: tiny attitude changes around aoa 10, aos 5 deg
    base = frames.flow_direction(math.radians(10.0), math.radians(5.0))
    centre = cache.centre(cache.key(base))
    directions = [centre + 1e-5 * np.array([math.sin(k), math.cos(k), 0.0]) for k in range(n)]
    cache.lighting(centre)
    times = []
    for u in directions:
        t0 = time.perf_counter()
        method.coefficients(flow, flow_direction=u, lighting=cache.lighting(u))
        times.append(time.perf_counter() - t0)
    same = percentiles(times)

    # stored cells: cycle through 64 cached cells so each query unpacks the store
    cells = [
        frames.flow_direction(math.radians(10.0 + 0.5 * k), math.radians(5.0)) for k in range(64)
    ]
    cache.precompute(np.array(cells))
    times = []
    for k in range(n):
        u = cells[k % 64]
        t0 = time.perf_counter()
        method.coefficients(flow, flow_direction=u, lighting=cache.lighting(u))
        times.append(time.perf_counter() - t0)
    stored = percentiles(times)

    # the node's whole per-message work, fixed attitude (cache hits)
    settings = WrenchSettings.from_parameters(dict(PARAMETER_DEFAULTS, time_mode="epoch"))
    est = AeroWrenchEstimator(settings, mesh)
    r = 6378137.0 + 300e3
    v = math.sqrt(3.986004418e14 / r)
    times = []
    for k in range(n):
        t = 1e-3 * k
        if k % 100 == 0:
            est.on_state(t, [r, v * t, 0.0], [0.0, v, 0.0])
        t0 = time.perf_counter()
        est.on_attitude(t, (0.0, 0.0, 0.0, 1.0))
        times.append(time.perf_counter() - t0)
    whole = percentiles(times[100:])

    # the same after 10 ms of idleness before each message (a 100 Hz stream: the CPU has gone
    # idle and the process's code and data are cold), without and with the conditions prepared
    # ahead as the node does right after publishing (AeroWrenchEstimator.prepare)
    cold = {}
    for prepared in (False, True):
        est = AeroWrenchEstimator(settings, mesh)
        times = []
        for k in range(300):
            t = 0.01 * k
            if k % 10 == 0:
                est.on_state(t, [r, v * t, 0.0], [0.0, v, 0.0])
            time.sleep(0.01)
            t0 = time.perf_counter()
            est.on_attitude(t, (0.0, 0.0, 0.0, 1.0))
            times.append(time.perf_counter() - t0)
            if prepared:
                est.prepare(t + 0.01)
        cold[prepared] = percentiles(times[20:])

    print(f"{'case':<52} {'p50 ms':>8} {'p99 ms':>8}")
    for name, (p50, p99) in (
        ("cache hit, same cell + coefficients()", same),
        ("cache hit, stored cell (unpacked) + coefficients()", stored),
        ("estimator on_attitude (flight conditions included)", whole),
        ("same, 100 Hz: 10 ms idle before each message", cold[False]),
        ("same, 100 Hz, conditions prepared ahead (the node)", cold[True]),
    ):
        print(f"{name:<52} {p50:8.3f} {p99:8.3f}")
    print(
        f"cache: {cache.hits} hits, {cache.misses} misses; estimator cache: "
        f"{est.model.cache.hits} hits, {est.model.cache.misses} misses"
    )


if __name__ == "__main__":
    main()
