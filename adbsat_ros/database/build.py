"""Building an aerodynamic database: a solver swept over a grid of aoa and sideslip [deg]. Chunks
on :mod:`adbsat_ros.tasks`; the result does not depend on the workers, bit for bit (test
particles: attitude i draws from ``SeedSequence(seed, spawn_key=(i,))``). docs/physics.md 9."""

from __future__ import annotations

import math
import sys
import uuid

import numpy as np
from tqdm import tqdm

from adbsat_ros.database.format import AeroDatabase
from adbsat_ros.database.interpolation import estimate_interpolation_error
from adbsat_ros.database.metadata import describe_setup, material_override_texts
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.model import build_model
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.physics.setup import Setup, ShadingPolicy, SolverSpec
from adbsat_ros.processes import worker_count
from adbsat_ros.tasks import ChunkJob, run_chunks

#: Largest attitude count of a chunk handed to one worker.
MAX_CHUNK = 64


def check_angles(values, name, low, high) -> np.ndarray:
    """The angles [deg] sorted; ValueError naming ``name`` unless finite, distinct, in range."""
    a = np.asarray(values, dtype=float).reshape(-1)
    if a.size == 0:
        raise ValueError(f"{name}: no angles given")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name}: angles must be finite")
    a = np.sort(a)
    if np.any(np.diff(a) <= 0):
        dup = a[1:][np.diff(a) <= 0][0]
        raise ValueError(f"{name}: angle {dup:g} deg is given twice")
    if a[0] < low or a[-1] > high:
        raise ValueError(
            f"{name}: angles must lie in [{low:g}, {high:g}] deg, got {a[0]:g}..{a[-1]:g}"
        )
    return a


#: Columns of a chunk's results: :data:`VECTORS` (3 each), :data:`SCALARS`, and the standard
#: errors (norms) of Cf_G and Cm_G (0 for the panel method).
COLUMNS = 21
VECTORS = ("Cf_G", "Cm_G", "Cf_w", "Cf_f", "Cm_B")
SCALARS = ("AreaProj", "CD", "CL", "CY")


def attitude_seed(seed: int, index: int) -> int:
    """The seed of attitude ``index`` of a test-particle database made with ``seed``."""
    return int(np.random.SeedSequence(seed, spawn_key=(index,)).generate_state(1)[0])


class DatabaseSetup:
    """A build's model (exact shading, or test particles), made where its chunks run: a chunk is
    ``(first, attitudes (K, 2) [deg])``, its result (K, :data:`COLUMNS`)."""

    def __init__(self, setup: Setup, mesh, flow):
        self.model, self.flow = build_model(setup, mesh), flow
        self.seed = setup.solver.seed if self.model.backend == "tpmc" else None

    def evaluate(self, chunk) -> np.ndarray:
        """The coefficients of a chunk ``(first, attitudes)`` (:class:`DatabaseSetup`)."""
        first, attitudes_deg = chunk
        out = np.zeros((len(attitudes_deg), COLUMNS))
        chunk_angles = [(math.radians(a), math.radians(b)) for a, b in attitudes_deg]
        if self.seed is None:
            self.model.prepare(chunk_angles)  # (the chunk's shading in one call)
        for k, angles in enumerate(chunk_angles):
            seed = None if self.seed is None else attitude_seed(self.seed, first + k)
            r = self.model.evaluate(self.flow, angles=angles, seed=seed)
            if seed is not None:
                out[k, 19:21] = np.linalg.norm(r.Cf_G_error), np.linalg.norm(r.Cm_G_error)
            out[k, 0:3], out[k, 3:6], out[k, 6:9] = r.Cf_G, r.Cm_G, r.Cf_w
            out[k, 9:12], out[k, 12:15] = r.Cf_f, r.Cm_B
            out[k, 15:19] = (r.area_projected, r.drag, r.lift, r.side_force)
        return out


def build_setup(method: PanelMethod, shading: str, samples: int, solver: SolverSpec) -> Setup:
    """The set-up of a build of ``method``, shaded offline or solved by ``solver``."""
    ref = method.reference
    return Setup(
        model=method.model,
        options=method.options,
        surface=method.materials.default,
        overrides=tuple(material_override_texts(method.materials)),
        reference=Reference(ref.area, ref.length, tuple(ref.moment_point)),
        shading=ShadingPolicy(shading, samples, exact_offline=1),
        solver=solver,
        labels=(("solver", ""),),
    )


def build_database(
    method: PanelMethod,
    flow: FreeStream,
    aoa_deg,
    aos_deg,
    *,
    shading: str = "raycast",
    samples: int = 16,
    workers: int | None = None,
    progress=None,
    mesh_spec="example",
    mesh_scale: float = 1.0,
    conditions: dict | None = None,
    solver: str = "panel",
    particles: int | None = None,
    tolerance: float | None = None,
    seed: int = 0,
    stop=None,
    mesh_joints: dict | None = None,
    scheduler: str | None = None,
    report=None,
) -> AeroDatabase:
    """Evaluate the panel method, or test particles, at every (aoa, aos) pair of two angle lists.
    aoa_deg, aos_deg: angles of attack in [-360, 360], sideslip in [-90, 90] [deg]; no duplicates.
    shading: ``"raycast"``, ``"projection"`` or ``"none"``; ``samples``: rays per panel.
    workers: local processes (default: every usable CPU, once the attitudes left are worth them,
      :func:`adbsat_ros.tasks.run_chunks`; 1: this process); the result is the same.
    progress: None (a bar on a terminal), bool, ``progress(done, total)``, or a tqdm.
    mesh_spec, mesh_joints: how the mesh reloads (path or ``"example"``; joints [rad or m]).
    solver: ``"panel"`` or ``"tpmc"`` (then ``particles``, ``tolerance``, ``seed``; no shading).
    stop: a threading.Event; ends with the chunk that finished, NaN at the rest (partial, no .npz).
    scheduler: a running Dask scheduler's address (``tcp://host:8786``); None: this machine.
    report: a :class:`adbsat_ros.tasks.TaskReport` to fill (where the chunks ran).
    Returns an AeroDatabase; ``metadata["interpolation_error"]`` (tpmc: plus three of the largest
    standard errors; ``solver`` recorded)."""
    shading = str(shading).lower()  # (checked by the set-up)
    samples = int(samples)
    if samples < 1:
        raise ValueError(f"samples must be >= 1, got {samples}")
    if solver not in ("panel", "tpmc"):
        raise ValueError(f"solver must be panel or tpmc, got {solver!r}")
    tpmc = None
    if solver == "tpmc":
        tpmc = {"particles": particles, "tolerance": tolerance, "seed": seed}
    spec = SolverSpec(solver, particles, tolerance, seed) if tpmc else SolverSpec()
    # (checked here, a model without a test-particle kernel refused, before any worker starts)
    model = build_model(build_setup(method, shading, samples, spec), method.mesh)
    count, _ = worker_count(workers)  # (at most the usable CPUs)
    aoa = check_angles(aoa_deg, "aoa_deg", -360.0, 360.0)
    aos = check_angles(aos_deg, "aos_deg", -90.0, 90.0)
    metadata = describe_setup(model, flow, mesh_spec, mesh_scale, mesh_joints)
    if conditions is not None:
        metadata["conditions"] = conditions

    grid_a, grid_b = np.meshgrid(aoa, aos, indexing="ij")
    attitudes = np.column_stack([grid_a.reshape(-1), grid_b.reshape(-1)])
    total = len(attitudes)
    # chunks: about eight per worker (the last ones then finish together), at most MAX_CHUNK
    chunk = max(1, min(MAX_CHUNK, math.ceil(total / (8 * min(count, total)))))
    if tpmc is not None:
        chunk = 1  # (an attitude is a long run already: a stop waits for one at most)
    chunks = {s: (s, attitudes[s : s + chunk]) for s in range(0, total, chunk)}
    results = np.full((total, COLUMNS), np.nan)
    if progress is None:  # a bar only for a person watching a terminal
        progress = hasattr(sys.stderr, "isatty") and sys.stderr.isatty()
    if not (isinstance(progress, bool) or callable(progress) or hasattr(progress, "update")):
        raise TypeError("progress must be None, a bool, a callable(done, total) or a tqdm instance")
    off = progress is not True  # (a bar of its own only for True)
    bar = tqdm(total=total, unit="att", desc="database", file=sys.stderr, leave=False, disable=off)
    done = 0

    def take(first, block):
        nonlocal done
        results[first : first + len(block)] = block
        done += len(block)
        bar.update(len(block))
        if hasattr(progress, "update"):
            progress.update(len(block))
        elif callable(progress):
            progress(done, total)

    job = ChunkJob("database " + uuid.uuid4().hex, DatabaseSetup, (model.setup, model.mesh, flow))
    try:
        run_chunks(
            job, chunks, take, scheduler=scheduler, workers=workers, stop=stop, report=report
        )
    finally:
        bar.close()

    grid = results.reshape(aoa.size, aos.size, COLUMNS)  # (the columns of COLUMNS' comment)
    arrays = {name: grid[..., 3 * k : 3 * k + 3].copy() for k, name in enumerate(VECTORS)}
    arrays.update({name: grid[..., 15 + k].copy() for k, name in enumerate(SCALARS)})
    db = AeroDatabase(aoa_deg=aoa, aos_deg=aos, **arrays, metadata=metadata)
    db.metadata["solver"] = dict(method=solver, **(tpmc or {}))
    done = np.isfinite(results[:, 16])
    if not done.all():  # stopped: no grid to interpolate
        db.metadata["partial"] = {"attitudes_done": int(done.sum()), "attitudes": total}
        db.metadata["interpolation_error"] = {
            "method": "not estimated: the build was stopped",
            "force_coefficient": None,
            "moment_coefficient": None,
        }
        return db
    error = estimate_interpolation_error(db)
    if tpmc is not None:
        force = 3.0 * float(results[:, 19].max())
        moment = 3.0 * float(results[:, 20].max())
        error.update(statistical_force_coefficient=force, statistical_moment_coefficient=moment)
        if error["force_coefficient"] is not None:
            error["force_coefficient"] += force
            error["moment_coefficient"] += moment
            error["method"] += "; plus three times the largest standard error of the particles"
    db.metadata["interpolation_error"] = error
    return db
