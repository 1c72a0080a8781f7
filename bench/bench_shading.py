"""Benchmark of shading for one flow direction on non-convex scenes of ~5k and ~50k faces.

Scenes (rays are really cast, nothing is convex):

* ``cube+plate``: 1 m cube at x = +2 m in front of a 3 x 3 x 0.1 m plate (faces refined);
* ``satellite``: 1.5 x 1 x 1 m box bus with two 3 x 0.6 m wings behind it, partly in its wake.

For each: Shader build time (Embree), raycast lighting with the Embree and numpy backends,
raycast without the prefilter (every forward panel tested), ADBSat's projection mode, and a
ShadingCache hit. Flow: aoa = 10 deg, aos = 5 deg. Medians of repeated runs, milliseconds.

With ``--accuracy``, also the lit projected area of the cube+plate scene against its exact
value 9 |u_x| + 0.3 (|u_y| + |u_z|) (the cube hides exactly its own projected area; valid while
its shadow stays on the plate front), for several plate refinements and attitudes, with the
default ray-cast settings and with ADBSat's projection method.

Run::

    python bench/bench_shading.py               # timing table
    python bench/bench_shading.py --quick       # fewer repeats
    python bench/bench_shading.py --accuracy    # plus the accuracy table
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's adbsat_ros first

from meshes import grid_box

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.example_satellite import combine
from adbsat_ros.shading.cache import ShadingCache, moved_lit_area
from adbsat_ros.shading.lighting import lit_projected_area
from adbsat_ros.shading.rays import has_embree
from adbsat_ros.shading.shader import make_shader


def cube_plate(plate_div, cube_div):
    return combine(
        [
            grid_box((2.0, 0, 0), (1, 1, 1), (cube_div,) * 3),
            grid_box((0, 0, 0), (0.1, 3, 3), (1, plate_div, plate_div)),
        ],
        "cube+plate",
    )


def satellite(k):
    return combine(
        [
            grid_box((0, 0, 0), (1.5, 1, 1), (3 * k, 2 * k, 2 * k)),
            grid_box((-1.2, 1.8, 0), (0.02, 3.0, 0.6), (1, 6 * k, k)),
            grid_box((-1.2, -1.8, 0), (0.02, 3.0, 0.6), (1, 6 * k, k)),
        ],
        "satellite",
    )


def median_ms(fn, repeats):
    fn()  # warm-up
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return 1e3 * statistics.median(times)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats")
    parser.add_argument("--accuracy", action="store_true", help="also print the accuracy table")
    args = parser.parse_args(argv)
    rep_fast, rep_slow = (5, 3) if args.quick else (21, 7)

    u = frames.flow_direction(math.radians(10.0), math.radians(5.0))
    scenes = [
        ("cube+plate", cube_plate(34, 4)),
        ("satellite", satellite(6)),
        ("cube+plate", cube_plate(110, 8)),
        ("satellite", satellite(21)),
    ]
    have_embree = has_embree
    print(
        f"# python {platform.python_version()}, numpy {np.__version__}, {os.cpu_count()} CPUs, "
        f"embree: {have_embree}"
    )
    print("# flow aoa = 10 deg, aos = 5 deg; times are medians in ms")
    header = (
        f"{'scene':<11} {'faces':>6} {'case':<26} {'median ms':>10} {'rays':>8} {'tested':>7} "
        f"{'partly lit':>10}"
    )
    print(header)
    print("-" * len(header))
    for name, mesh in scenes:
        rows = []
        backend = "embree" if have_embree else "numpy"
        build = median_ms(lambda: make_shader(mesh, backend=backend, topology_store=None), rep_slow)
        rows.append((f"build Shader ({backend})", build, None))
        for be in (["embree"] if have_embree else []) + ["numpy"]:
            sh = make_shader(mesh, backend=be)
            t = median_ms(lambda: sh.lighting(u), rep_fast if be == "embree" else rep_slow)
            rows.append((f"raycast {be}", t, dict(sh.last_stats)))
        sh = make_shader(mesh, backend=backend, prefilter=False)
        t = median_ms(lambda: sh.lighting(u), rep_slow)
        rows.append((f"raycast {backend}, no filter", t, dict(sh.last_stats)))
        sh = make_shader(mesh, mode="projection")
        t = median_ms(lambda: sh.lighting(u), rep_slow)
        rows.append(("projection (ADBSat)", t, {"rays": 0, "tested": "-", "partly_lit": 0}))
        cache = ShadingCache(make_shader(mesh, backend=backend), resolution_deg=1.0)
        cache.lighting(u)
        t = median_ms(lambda: cache.lighting(u), 201)
        rows.append(("cache hit", t, None))
        for case, ms, st in rows:
            st = st or {}
            print(
                f"{name:<11} {mesh.n_panels:>6} {case:<26} {ms:>10.3f} {st.get('rays', ''):>8} "
                f"{st.get('tested', ''):>7} {st.get('partly_lit', ''):>10}"
            )
        sys.stdout.flush()
    if args.accuracy:
        accuracy()


def accuracy():
    """Lit projected area error on cube+plate against the exact value."""
    print()
    print("# lit projected area of cube+plate vs exact 9|u_x| + 0.3(|u_y| + |u_z|)")
    print("# raycast: every panel's rays (convex_shadows=False); exact: the default, where the")
    print("# cube's shadow is clipped exactly (the cube is convex and alone in front of the plate)")
    header = (
        f"{'plate grid':>10} {'faces':>6} {'aoa':>5} {'aos':>5} {'exact m2':>9} "
        f"{'raycast rel err':>16} {'shadow rel err':>15} {'default rel err':>16} "
        f"{'projection rel err':>19}"
    )
    print(header)
    print("-" * len(header))
    worst = 0.0
    for div in (7, 25, 34, 64):
        mesh = cube_plate(div, 2)
        ray = make_shader(mesh, convex_shadows=False)
        default = make_shader(mesh)
        proj = make_shader(mesh, mode="projection")
        for aoa, aos in (
            (0.0, 0.0),
            (3.7, 0.0),
            (10.0, 0.0),
            (17.3, 0.0),
            (10.0, 5.0),
            (-6.0, 12.0),
        ):
            a, b = math.radians(aoa), math.radians(aos)
            u = frames.flow_direction(a, b)
            exact = 9.0 * abs(u[0]) + 0.3 * (abs(u[1]) + abs(u[2]))
            shadow = np.abs(u).sum()  # projected shadow = cube's projected area
            got = lit_projected_area(mesh, u, ray.lighting(u))
            got_d = lit_projected_area(mesh, u, default.lighting(u))
            got_p = lit_projected_area(mesh, u, proj.lighting(u))
            err = (got - exact) / exact
            if div > 7:
                worst = max(worst, abs(err))
            print(
                f"{div:>7}x{div:<2} {mesh.n_panels:>6} {aoa:>5.1f} {aos:>5.1f} {exact:>9.5f} "
                f"{err:>+16.2e} {(got - exact) / shadow:>+15.2e} {(got_d - exact) / exact:>+16.2e} "
                f"{(got_p - exact) / exact:>+19.2e}"
            )
    print(f"# worst raycast relative error for plate grids >= 25x25: {worst:.2e}")

    print()
    print("# ShadingCache on cube+plate (25x25): cached vs exact recompute, 60 random directions")
    print(
        "# E = lit projected area moved [m^2], dA = |AreaProj cached - exact| [m^2], "
        "bound = area_error_bound"
    )
    header = (
        f"{'res deg':>7} {'mean E':>9} {'max E':>9} {'max dA':>9} {'min bound':>10} "
        f"{'max E/bound':>12}"
    )
    print(header)
    print("-" * len(header))
    mesh = cube_plate(25, 2)
    shader = make_shader(mesh)
    for res in (0.25, 1.0, 2.0, 5.0):
        cache = ShadingCache(shader, resolution_deg=res)
        rng = np.random.default_rng(3)
        rows = []
        for k in range(60):
            u = (
                rng.normal(size=3)
                if k % 3 == 0
                else np.array([-1.0, 0.0, 0.0]) + 0.5 * rng.normal(size=3)
            )
            u /= np.linalg.norm(u)
            cached, exact = cache.lighting(u), shader.lighting(u)
            e = moved_lit_area(mesh, u, cached, exact)
            da = abs(lit_projected_area(mesh, u, cached) - lit_projected_area(mesh, u, exact))
            rows.append((e, da, cache.area_error_bound(u, cached)))
        r = np.array(rows)
        print(
            f"{res:>7.2f} {r[:, 0].mean():>9.4f} {r[:, 0].max():>9.4f} {r[:, 1].max():>9.4f} "
            f"{r[:, 2].min():>10.4f} {(r[:, 0] / r[:, 2]).max():>12.3f}"
        )


if __name__ == "__main__":
    main()
