"""Cost of one attitude of the panel method: bare, and with the shading from the cache.

Usage::

    python bench/bench_panel_method.py [--model sentman] [--repeat 200]
    python bench/bench_panel_method.py --cached [--baseline ../baseline] [--rounds 6]

Without ``--cached``: per sphere of about 1k, 10k and 100k faces (no shading), the median wall time
of ``PanelMethod.coefficients`` (the full public call) and of the bare ``panel_coefficients +
integrate`` hot path, in milliseconds, measured in the same run.

With ``--cached``: CPU time per attitude (``time.thread_time``) of a shading-cache hit plus the
panel method, as the ROS node does per message, on the 11,104-face example satellite
(``example_satellite(max_edge=0.0625)``), sentman, raycast shading cached at 0.25 deg:

* ``same cell``: consecutive unit flow directions inside one cache cell;
* ``4 cells``, ``64 cells``: every query in another cell, the cells all stored, cycling
  through 4 or 64 of them;
* ``cache hit only``: the shading-cache lookup alone, same cell.

Two variants: ``Model.evaluate`` (the node's path: the cell's facet sums are made once, with
its lighting) and ``coefficients(lighting=)`` (the kernel given the cell's lighting, summed at
every call). This tree and the tree at ``--baseline`` (a checkout of another commit, e.g.
../baseline) each run in a worker process of their own, alternately (ABAB...) for ``--rounds``
rounds; the table gives the median over the rounds in microseconds. A tree without
``Model.evaluate`` is measured through the kernel alone.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import trimesh

TREE = Path(__file__).resolve().parents[1]
SPECIES = {
    "He": 2.1e12,
    "O": 4.3e15,
    "N2": 6.9e14,
    "O2": 2.1e13,
    "Ar": 3.7e10,
    "H": 1.2e11,
    "N": 3.5e13,
}
CASES = ("same cell", "4 cells", "64 cells", "cache hit only")


# ---------------------------------------------------------------------------------- spheres
def sphere_with_faces(target: int):
    """A UV sphere of radius 1 m with about ``target`` triangular faces."""
    n = max(int(round(math.sqrt(target / 4.0))), 4)  # uv_sphere has about 4 n^2 faces
    return trimesh.creation.uv_sphere(radius=1.0, count=[n, n])


def median_ms(fn, repeat: int) -> float:
    for _ in range(5):
        fn()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return 1e3 * statistics.median(times)


def spheres(model: str, repeat: int) -> None:
    # adbsat_ros is imported where it is used: the workers of --cached import one tree or the
    # other (their PYTHONPATH), in either layout
    from adbsat_ros import FreeStream, PanelMethod, panels_from_trimesh
    from adbsat_ros.geometry.frames import flow_direction

    flow = FreeStream(7700.0, 900.0, number_densities=SPECIES)
    print(f"model {model}, one attitude, no shading, median of {repeat} calls")
    print(f"{'faces':>8} {'coefficients() ms':>18} {'hot path ms':>12}")
    rng = np.random.default_rng(1)
    for target in (1_000, 10_000, 100_000):
        mesh = panels_from_trimesh(sphere_with_faces(target))
        method = PanelMethod(mesh, model)
        aoa, aos = rng.uniform(-1, 1, 2)
        u = flow_direction(aoa, aos)

        def full():
            method.coefficients(flow, aoa, aos)

        def hot():
            c, s, cp, ct = method.panel_coefficients(u, flow)
            method.integrate(u, c, s, cp, ct)

        full_ms, hot_ms = median_ms(full, repeat), median_ms(hot, repeat)
        print(f"{mesh.n_panels:8d} {full_ms:18.3f} {hot_ms:12.3f}")


# ---------------------------------------------------------------------------------- cached
def worker(calls: int, blocks: int) -> dict:
    """CPU microseconds per attitude of each case and variant in the tree on sys.path."""
    # imported here: the tree is the one on PYTHONPATH
    from adbsat_ros.geometry import frames
    from adbsat_ros.geometry.example_satellite import example_satellite
    from adbsat_ros.physics.freestream import FreeStream
    from adbsat_ros.physics.panel_method import PanelMethod
    from adbsat_ros.shading.cache import ShadingCache
    from adbsat_ros.shading.shader import make_shader

    mesh = example_satellite(max_edge=0.0625)
    flow = FreeStream(speed=7726.0, temperature=934.0, mean_mass_amu=17.9, density=2.4e-11)
    cache = ShadingCache(make_shader(mesh, mode="raycast"), resolution_deg=0.25)
    base = frames.flow_direction(math.radians(10.0), math.radians(5.0))
    centre = cache.centre(cache.key(base))
    rng = np.random.default_rng(5)
    same = centre + 1e-5 * rng.normal(size=(calls, 3))
    same /= np.linalg.norm(same, axis=1, keepdims=True)
    cells = np.array(
        [frames.flow_direction(math.radians(10.0 + 0.5 * k), math.radians(5.0)) for k in range(64)]
    )
    directions = np.vstack([cells, centre])
    cache.precompute(directions)
    streams = {
        "same cell": list(same),
        "4 cells": [cells[k % 4] for k in range(calls)],
        "64 cells": [cells[k % 64] for k in range(calls)],
    }

    method = PanelMethod(mesh, "sentman")

    def kernel(u):
        method.coefficients(flow, flow_direction=u, lighting=cache.lighting(u))

    variants = {"coefficients(lighting=)": kernel}
    model = _model(mesh)
    if model is not None:
        model.cache.precompute(directions)
        variants["Model.evaluate"] = lambda u: model.evaluate(flow, u)

    def run(call, directions):
        t0 = time.thread_time()
        for u in directions:
            call(u)
        return time.thread_time() - t0

    results = {}
    for _ in range(blocks):  # variants and cases interleaved, block after block
        for case, directions in streams.items():
            for name, call in variants.items():
                run(call, directions[:50])  # warm
                seconds = run(call, directions)
                results.setdefault(f"{case} | {name}", []).append(1e6 * seconds / calls)
        t0 = time.thread_time()
        for u in streams["same cell"]:
            cache.lighting(u)
        results.setdefault("cache hit only | ShadingCache.lighting", []).append(
            1e6 * (time.thread_time() - t0) / calls
        )
    return {key: statistics.median(values) for key, values in results.items()}


def _model(mesh):
    """The node's model of ``mesh`` (raycast cached at 0.25 deg, cells not interpolated), or
    None in a tree without :meth:`Model.evaluate`."""
    try:
        from adbsat_ros.physics.model import Model, build_model
        from adbsat_ros.physics.setup import Setup, ShadingPolicy
    except ImportError:
        return None
    if not hasattr(Model, "evaluate"):
        return None
    policy = ShadingPolicy(cache_resolution_deg=0.25, interpolation=False)
    return build_model(Setup(shading=policy), mesh)


def cached(baseline: str, rounds: int, calls: int, blocks: int) -> None:
    trees = {"this tree": str(TREE), "baseline": baseline}
    runs: dict = {}
    for r in range(rounds):
        order = list(trees.items()) if r % 2 == 0 else list(trees.items())[::-1]
        for label, path in order:
            env = dict(os.environ, PYTHONPATH=path)
            command = [
                sys.executable,
                __file__,
                "--worker",
                f"--calls={calls}",
                f"--blocks={blocks}",
            ]
            out = subprocess.run(command, env=env, cwd=path, capture_output=True, text=True)
            if out.returncode:
                raise SystemExit(f"{label} worker failed:\n{out.stderr}")
            for key, value in json.loads(out.stdout.splitlines()[-1]).items():
                runs.setdefault((label, key), []).append(value)
    print(
        "CPU per attitude [us], median of "
        f"{rounds} rounds (ABAB), {blocks} blocks of {calls} calls each: shading-cache hit + "
        "panel method, example satellite 11,104 faces, sentman, raycast cached at 0.25 deg"
    )
    print(f"{'tree':<10} {'case':<15} {'variant':<36} {'us':>8}")
    for (label, key), values in sorted(runs.items(), key=lambda kv: (kv[0][1], kv[0][0])):
        case, name = key.split(" | ")
        print(f"{label:<10} {case:<15} {name:<36} {statistics.median(values):8.1f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--model", default="sentman")
    parser.add_argument("--repeat", type=int, default=200)
    parser.add_argument("--cached", action="store_true", help="shading-cache hit + panel method")
    parser.add_argument("--baseline", default="../baseline", help="tree to compare with")
    parser.add_argument("--rounds", type=int, default=6)
    parser.add_argument("--calls", type=int, default=2000)
    parser.add_argument("--blocks", type=int, default=3)
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        print(json.dumps(worker(args.calls, args.blocks)))
    elif args.cached:
        cached(args.baseline, args.rounds, args.calls, args.blocks)
    else:
        spheres(args.model, args.repeat)


if __name__ == "__main__":
    main()
