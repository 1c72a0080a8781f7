"""Speed of the test-particle Monte Carlo solver.

Three figures (docs/benchmarks.md, "Databases, sweeps and test particles"):

1. molecules per second per core on a sphere of 5,120 faces (one worker, CPU time of the run:
   inflow, tracing, re-emission and sums), and on the concave grooved cylinder, whose molecules
   bounce in its grooves: there also the surface hits per second per core;
2. the time to C_D within 0.3 % at 95 % confidence (standard error <= 0.3 % / 1.96) for the
   example satellite at one attitude, on 2 workers (wall time, and the molecules it took).

The gas: V = 7,800 m/s, T = 1,000 K, 16 amu (speed ratio 7.65), diffuse re-emission at 300 K.
Each figure is the median of --rounds runs; CPU time is this process's plus its workers'.

    python bench/bench_tpmc.py [--rounds 3] [--particles 2000000]
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import time

import trimesh

from adbsat_ros.geometry.loading import resolve_mesh
from adbsat_ros.geometry.mesh import panels_from_arrays
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.tpmc.method import TestParticleMethod

FLOW = FreeStream(speed=7800.0, temperature=1000.0, mean_mass_amu=16.0)


def cpu_seconds() -> float:
    """CPU time of this process and its finished children [s]."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def molecules_per_cpu_second(mesh, particles: int, rounds: int) -> tuple:
    """(molecules per CPU second, hits per CPU second), medians over ``rounds`` runs."""
    method = TestParticleMethod(mesh)
    method.coefficients(FLOW, particles=65_536)  # warm: the scene, the imports
    rates, hit_rates = [], []
    for k in range(rounds):
        start = cpu_seconds()
        r = method.coefficients(FLOW, particles=particles, seed=k)
        spent = cpu_seconds() - start
        rates.append(r.particles / spent)
        hit_rates.append(r.hits / spent)
    return statistics.median(rates), statistics.median(hit_rates)


def time_to_precision(rounds: int) -> tuple:
    """(wall seconds, molecules) to C_D within 0.3 % (95 %) on 2 workers, example satellite."""
    method = TestParticleMethod(resolve_mesh("example"))
    times, counts = [], []
    for k in range(rounds):
        start = time.perf_counter()
        r = method.coefficients(FLOW, tolerance=0.003 / 1.96, seed=k, workers=2)
        times.append(time.perf_counter() - start)
        counts.append(r.particles)
    return statistics.median(times), int(statistics.median(counts))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--particles", type=int, default=2_000_000)
    args = parser.parse_args()
    commit = subprocess.run(
        ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True
    ).stdout.strip()
    print(f"commit {commit}, {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs")
    sphere = trimesh.creation.icosphere(subdivisions=4, radius=0.5)
    sphere = panels_from_arrays(sphere.vertices, sphere.faces)
    rate, hits = molecules_per_cpu_second(sphere, args.particles, args.rounds)
    print(
        f"sphere ({sphere.n_panels} faces): {rate / 1e6:.2f} M molecules/s per core, "
        f"{hits / 1e6:.2f} M hits/s per core"
    )
    grooved = resolve_mesh("grooved-cylinder")
    rate, hits = molecules_per_cpu_second(grooved, args.particles // 4, args.rounds)
    print(
        f"grooved cylinder ({grooved.n_panels} faces): {rate / 1e6:.2f} M molecules/s per "
        f"core, {hits / 1e6:.2f} M hits/s per core"
    )
    seconds, count = time_to_precision(args.rounds)
    print(
        f"example satellite, C_D within 0.3 % (95 %), 2 workers: {seconds:.1f} s, "
        f"{count / 1e6:.2f} M molecules"
    )


if __name__ == "__main__":
    main()
