"""The test-particle Monte Carlo solver: the panel method's inputs, its coefficients with a standard
error each. A run stops at a particle budget or, after whole blocks of :data:`BLOCK_BATCHES`
batches, at a tolerance on C_D: a seed gives the same numbers with any number of workers
(docs/physics.md, section 12). Units: SI, mesh frame G; angles in radians."""

from __future__ import annotations

import math
import os
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.gsi_models import canonical_model_name
from adbsat_ros.physics.surface import MaterialTable
from adbsat_ros.physics.tpmc.batches import BatchSums, Problem, init_worker, run_batch
from adbsat_ros.physics.tpmc.inflow import InflowBox
from adbsat_ros.physics.tpmc.kernels import KERNEL_OF_MODEL
from adbsat_ros.physics.tpmc.results import TpmcCoefficients
from adbsat_ros.processes import pool_context, worker_count
from adbsat_ros.shading.lighting import lit_projected_area
from adbsat_ros.shading.rays import resolve_backend
from adbsat_ros.shading.shader import shade

#: Molecules per batch: numpy's per-call costs vanish, and a run can stop soon after its target.
BATCH_SIZE = 65_536
#: The run checks its precision after every this many batches (the same for any worker count).
BLOCK_BATCHES = 4
#: Molecules traced when neither a budget nor a tolerance is given.
DEFAULT_PARTICLES = 1_000_000


class TestParticleMethod:
    """A mesh with a gas-surface model and materials, solved by test-particle Monte Carlo.

    model: sentman, dria, maxwell or cll (:data:`~.kernels.KERNEL_OF_MODEL`).
    backend: ``"auto"``, ``"embree"`` or ``"numpy"`` ray casting.
    margin: the inflow box is the bounding box grown by this fraction of its largest side.
    """

    __test__ = False  # (not a pytest class, despite its name)

    def __init__(
        self,
        mesh: PanelMesh,
        model="sentman",
        materials=None,
        reference=None,
        backend="auto",
        margin=0.05,
    ):
        self.mesh = mesh
        self.model = canonical_model_name(model)
        if self.model not in KERNEL_OF_MODEL:
            raise ValueError(
                f"model {self.model!r} has no test-particle kernel; choose one of "
                f"{', '.join(KERNEL_OF_MODEL)}"
            )
        self.kernel = KERNEL_OF_MODEL[self.model]
        self.materials = materials = MaterialTable.of(materials)
        self.surface = materials.expand(mesh.material_names, mesh.material_index)
        self.reference = (reference or Reference()).resolved(mesh)
        self.backend = resolve_backend(backend)
        if not (0.0 < float(margin) <= 1.0):
            raise ValueError(f"margin must be in (0, 1], got {margin!r}")
        self.margin = float(margin)

    def problem(self, flow: FreeStream, u) -> Problem:
        """The inflow and tracing of molecules of ``flow`` moving along unit ``u`` (G)."""
        if flow.has_species:
            masses = flow.species_masses
            fractions = flow.species_number_densities / flow.species_number_densities.sum()
        else:
            masses, fractions = np.array([flow.mean_mass]), np.array([1.0])
        keep = fractions > 0.0
        lower, upper = self.mesh.bounds
        inflow = InflowBox(
            lower,
            upper,
            flow.speed * u,
            flow.temperature,
            masses[keep],
            fractions[keep],
            self.margin,
        )
        return Problem(
            self.mesh, self.kernel, self.surface, inflow, self.reference.moment_point, self.backend
        )

    def coefficients(
        self,
        flow: FreeStream,
        aoa: float | None = None,
        aos: float | None = None,
        *,
        flow_direction=None,
        particles: int | None = None,
        tolerance: float | None = None,
        seed: int = 0,
        workers: int = 1,
        progress=None,
        stop=None,
    ) -> TpmcCoefficients:
        """Coefficients at one attitude, by angles [rad] or by the flow direction (G).

        particles: most molecules to trace, >= 1, rounded up to whole batches.
        tolerance: stop once the standard error of C_D is at most this fraction of C_D, in (0, 1).
        seed: >= 0, the same seed gives the same numbers; workers: processes (at most usable CPUs).
        progress: called with the molecules traced after every block.
        stop: threading.Event checked after every block (the run ends there, ``stopped``).
        """
        u, angles = frames.attitude_flow(aoa, aos, flow_direction)
        budget, tol = run_settings(particles, tolerance, seed)
        workers, _ = worker_count(workers)
        problem = self.problem(flow, u)
        size = min(BATCH_SIZE, budget)
        total = _Totals(self.mesh.n_panels)
        with _Serial(problem) if workers == 1 else _Pool(problem, workers) as runner:
            k = 0
            while total.count < budget:
                block = range(k, k + min(BLOCK_BATCHES, -(-(budget - total.count) // size)))
                for sums in runner.map(block, int(seed), size):
                    total.add(sums)
                k += BLOCK_BATCHES
                if progress is not None:
                    progress(total.count)
                if tol is not None and total.relative_drag_error(problem, flow, self, u) <= tol:
                    break
                if stop is not None and stop.is_set() and total.count < budget:
                    total.stopped = True
                    break
        return total.coefficients(problem, flow, self, u, angles, int(seed))


def run_settings(particles, tolerance, seed) -> tuple:
    """``(particle budget, tolerance or None)`` of a run; ValueError naming a bad one."""
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be a whole number >= 0, got {seed!r}")
    tol = None
    if tolerance is not None:
        tol = float(tolerance)
        if not 0.0 < tol < 1.0:
            raise ValueError(f"tolerance must be in (0, 1), got {tolerance!r}")
    if particles is None:
        return DEFAULT_PARTICLES * (100 if tol is not None else 1), tol
    if isinstance(particles, bool) or not float(particles).is_integer() or particles < 1:
        raise ValueError(f"particles must be a whole number >= 1, got {particles!r}")
    return int(particles), tol


class _Serial:
    """Batches run in this process."""

    def __init__(self, problem: Problem):
        self.problem = problem

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def map(self, block, seed, size) -> list:
        return [self.problem.run_batch(k, seed, size) for k in block]


class _Pool(_Serial):
    """Batches run by worker processes, returned in batch order."""

    def __init__(self, problem: Problem, workers: int):
        super().__init__(problem)
        self.pool = ProcessPoolExecutor(
            max_workers=workers,
            mp_context=pool_context(),
            initializer=init_worker,
            initargs=(problem, os.getpid()),
        )

    def __exit__(self, *exc):
        self.pool.shutdown(cancel_futures=True)
        return False

    def map(self, block, seed, size) -> list:
        n = len(block)
        return list(self.pool.map(run_batch, block, [seed] * n, [size] * n))


class _Totals:
    """The batches' sums, in batch order, and the coefficients they give."""

    def __init__(self, n_panels: int):
        self.count = 0
        self.sums = np.zeros(6)
        self.squares = np.zeros((6, 6))
        self.panel_impulse = np.zeros((n_panels, 3))
        self.panel_hits = np.zeros(n_panels, dtype=np.int64)
        self.hits = self.trapped = 0
        self.exit_momentum = np.zeros(3)
        self.stopped = False

    def add(self, b: BatchSums) -> None:
        self.count += b.count
        self.sums += b.sums
        self.squares += b.squares
        self.panel_impulse += b.panel_impulse
        self.panel_hits += b.panel_hits
        self.hits += b.hits
        self.trapped += b.trapped
        self.exit_momentum += b.exit_momentum

    @staticmethod
    def per_unit_q(problem: Problem, flow: FreeStream, area: float) -> float:
        """rho/n V^2 A_ref / 2: a momentum flux per unit number density over this is a force
        coefficient."""
        inflow = problem.inflow
        rho_over_n = float(inflow.mole_fractions @ inflow.masses)
        return rho_over_n * 0.5 * flow.speed**2 * area

    def scale(self, problem: Problem, flow: FreeStream, method) -> float:
        """R / (rho/n V^2 A_ref / 2): from mean momentum per molecule to a force coefficient."""
        return problem.inflow.rate / self.per_unit_q(problem, flow, method.reference.area)

    def covariance(self, k: float, length: float) -> np.ndarray:
        n = self.count
        mean = self.sums / n
        spread = (self.squares - n * np.outer(mean, mean)) / max(n - 1, 1)
        d = np.array([k, k, k, k / length, k / length, k / length])
        return spread / n * np.outer(d, d)

    def relative_drag_error(self, problem, flow, method, u) -> float:
        k = self.scale(problem, flow, method)
        cov = self.covariance(k, method.reference.length)[:3, :3]
        drag = -k * (self.sums[:3] / self.count) @ u  # C_D is the force along the flow
        return math.sqrt(max(float(u @ cov @ u), 0.0)) / abs(drag) if drag else math.inf

    def coefficients(self, problem, flow, method, u, angles, seed) -> TpmcCoefficients:
        ref = method.reference
        k = self.scale(problem, flow, method)
        n = self.count
        mesh = method.mesh
        cf = k * self.sums[:3] / n
        cm = k * self.sums[3:] / (n * ref.length)
        panel = k * self.panel_impulse / n  # force coefficient of each panel
        normals = mesh.normals
        c = -(normals @ u)
        normal_part = np.einsum("ij,ij->i", panel, normals)
        cp = -normal_part * ref.area / mesh.areas
        tangential = panel - normal_part[:, None] * normals
        sine = np.sqrt(np.maximum(1.0 - c * c, 0.0))
        along = u + c[:, None] * normals
        with np.errstate(divide="ignore", invalid="ignore"):
            shear = np.where(
                sine > 1e-12,
                np.einsum("ij,ij->i", tangential, along) / sine,
                np.linalg.norm(tangential, axis=1),
            )
        ctau = shear * ref.area / mesh.areas
        inflow = problem.inflow
        balance = (inflow.momentum_flux() - inflow.rate * self.exit_momentum / n) / self.per_unit_q(
            problem, flow, ref.area
        )
        area = lit_projected_area(mesh, u, shade(mesh, u, "raycast", topology_store=None))
        return TpmcCoefficients(
            flow_direction=u,
            Cf_G=cf,
            Cm_G=cm,
            reference=ref,
            area_projected=float(area),
            model=method.model,
            panel_values=(c, cp, ctau, None, None),
            angles=angles,
            covariance=self.covariance(k, ref.length),
            particles=n,
            seed=seed,
            hits=self.hits,
            trapped=self.trapped,
            force_balance=balance,
            stopped=self.stopped,
        )
