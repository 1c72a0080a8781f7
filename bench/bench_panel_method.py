"""Cost of one attitude of the panel method (no shading) on meshes of about 1k, 10k and 100k faces.

Usage: python bench/bench_panel_method.py [--model sentman] [--repeat 200]

Prints, per mesh, the median wall time of ``PanelMethod.coefficients`` (the full public call:
incidence, model, integration, frame changes and result object) and of the bare
``panel_coefficients + integrate`` hot path, in milliseconds. Both are measured in the same run so
their ratio is meaningful on a noisy machine.
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import numpy as np
import trimesh

from adbsat_ros import FreeStream, PanelMethod, panels_from_trimesh
from adbsat_ros.geometry.frames import flow_direction

SPECIES = {
    "He": 2.1e12,
    "O": 4.3e15,
    "N2": 6.9e14,
    "O2": 2.1e13,
    "Ar": 3.7e10,
    "H": 1.2e11,
    "N": 3.5e13,
}


def sphere_with_faces(target: int) -> trimesh.Trimesh:
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--model", default="sentman")
    parser.add_argument("--repeat", type=int, default=200)
    args = parser.parse_args()
    flow = FreeStream(7700.0, 900.0, number_densities=SPECIES)
    print(f"model {args.model}, one attitude, no shading, median of {args.repeat} calls")
    print(f"{'faces':>8} {'coefficients() ms':>18} {'hot path ms':>12}")
    rng = np.random.default_rng(1)
    for target in (1_000, 10_000, 100_000):
        mesh = panels_from_trimesh(sphere_with_faces(target))
        method = PanelMethod(mesh, args.model)
        aoa, aos = rng.uniform(-1, 1, 2)
        u = flow_direction(aoa, aos)

        def full():
            method.coefficients(flow, aoa, aos)

        def hot():
            c, s, cp, ct = method.panel_coefficients(u, flow)
            method.integrate(u, c, s, cp, ct)

        print(
            f"{mesh.n_panels:8d} {median_ms(full, args.repeat):18.3f} {median_ms(hot, args.repeat):12.3f}"
        )


if __name__ == "__main__":
    main()
