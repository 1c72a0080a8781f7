"""Batches of test particles: the picklable problem, one batch's sums, the worker processes.

Batch k draws from ``SeedSequence(seed, spawn_key=(k,))``: the process that runs it does not
change its numbers. Units: SI, mesh frame G.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from adbsat_ros.physics.tpmc.tracing import trace
from adbsat_ros.processes import die_with_parent
from adbsat_ros.shading.rays import ray_scene


@dataclass
class BatchSums:
    """Sums over the molecules of one batch (what a worker sends back)."""

    count: int
    sums: np.ndarray  # (6,): momentum and moment given to the body, per molecule summed
    squares: np.ndarray  # (6, 6): sum of their outer products
    panel_impulse: np.ndarray  # (N, 3)
    panel_hits: np.ndarray  # (N,)
    hits: int
    trapped: int
    exit_momentum: np.ndarray  # (3,): sum of m v on leaving


class Problem:
    """One flow about one body, ready to run batches anywhere; ``moment_point`` [m], G."""

    def __init__(self, mesh, kernel, surface, inflow, moment_point, backend):
        self.mesh, self.kernel, self.surface = mesh, kernel, surface
        self.inflow, self.moment_point, self.backend = inflow, moment_point, backend
        self._scene = None

    def __getstate__(self):
        state = dict(self.__dict__)
        state["_scene"] = None  # an Embree scene does not pickle: each process makes its own
        return state

    def run_batch(self, k: int, seed: int, size: int) -> BatchSums:
        """Molecules of batch ``k`` of the run with ``seed``."""
        if self._scene is None:
            self._scene = ray_scene(self.mesh, self.backend)
        rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(k,)))
        pos, vel, species = self.inflow.sample(size, rng)
        mass = self.inflow.masses[species]
        tally = trace(
            self._scene,
            self.mesh,
            self.kernel,
            self.surface,
            pos,
            vel,
            mass,
            rng,
            self.moment_point,
        )
        y = np.hstack([tally.impulse, tally.moment])
        return BatchSums(
            count=size,
            sums=y.sum(axis=0),
            squares=y.T @ y,
            panel_impulse=tally.panel_impulse,
            panel_hits=tally.panel_hits,
            hits=tally.hits,
            trapped=tally.trapped,
            exit_momentum=mass @ tally.exit_velocity,
        )


_WORKER_PROBLEM: Problem | None = None


def init_worker(problem: Problem, parent: int) -> None:
    """Keep the problem in a worker process that dies with ``parent`` (signals are left to the
    parent)."""
    die_with_parent(parent, stops_to_parent=True)
    global _WORKER_PROBLEM
    _WORKER_PROBLEM = problem


def run_batch(k: int, seed: int, size: int) -> BatchSums:
    """Batch ``k`` of the worker's problem."""
    return _WORKER_PROBLEM.run_batch(k, seed, size)
