"""Aerodynamic databases: the panel method swept over a grid of angle of attack and sideslip.

An :class:`AeroDatabase` holds ADBSat's coefficients at every pair (aoa_i, aos_j) of two strictly
increasing angle lists [deg], with the metadata needed to know (and rebuild) what was computed:
mesh (spec, scale, fingerprint), gas-surface model and materials, free stream, reference
quantities, shading, and the stated interpolation error of the grid (see
:mod:`adbsat_ros.database.lookup`).

Coefficient arrays (ADBSat's names and frames; frames in :mod:`adbsat_ros.geometry.frames`):

* ``CD, CL, CY, AreaProj``: shape (na, nb); AreaProj in m^2, the others dimensionless;
* ``Cf_w, Cf_f, Cm_B, Cf_G, Cm_G``: shape (na, nb, 3); force coefficients in wind (W), flight (F)
  and mesh (G) axes, moment coefficients in ADBSat body axes (B) and mesh axes (G) about the
  reference moment point.

Forces are ``q A_ref Cf`` [N] and torques ``q A_ref L_ref Cm`` [N m] with q = rho V^2 / 2.

Files: :meth:`AeroDatabase.save` writes a compressed ``.npz`` (one array per name plus the
metadata as a JSON string under ``"metadata"``), :func:`load_database` reads and validates it;
:meth:`AeroDatabase.save_csv` writes one row per attitude with ``# key: value`` header lines.

:func:`build_database` evaluates the attitudes in chunks on a process pool (every core by
default). Each attitude is computed by the same code whatever the chunking, so the result does
not depend on the number of workers (bit for bit).
"""

from __future__ import annotations

import datetime as _dt
import json
import math
import os
import sys
import zipfile
from dataclasses import dataclass, field

import numpy as np

from adbsat_ros.geometry import frames
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.gsi_models import ModelOptions
from adbsat_ros.geometry.mesh import MeshError, resolve_mesh
from adbsat_ros.physics.panel_method import PanelMethod, Reference
from adbsat_ros.physics.surface import SURFACE_PARAMETERS, MaterialTable, SurfaceProperties

#: Version of the file layout written by :meth:`AeroDatabase.save`; :func:`load_database` reads it.
FORMAT_VERSION = 1

#: Per-attitude scalar arrays, shape (na, nb).
SCALAR_FIELDS = ("CD", "CL", "CY", "AreaProj")
#: Per-attitude vector arrays, shape (na, nb, 3).
VECTOR_FIELDS = ("Cf_w", "Cf_f", "Cm_B", "Cf_G", "Cm_G")
#: Metadata keys every database carries.
REQUIRED_METADATA = (
    "format_version",
    "created_utc",
    "adbsat_ros_version",
    "mesh",
    "model",
    "materials",
    "flow",
    "reference",
    "shading",
    "interpolation_error",
)
#: Largest attitude count of a chunk handed to one worker.
MAX_CHUNK = 64


class DatabaseError(ValueError):
    """A database file (or its metadata) that cannot be used; the message names the file."""


def _package_version() -> str:
    from adbsat_ros import __version__

    return __version__


# ---------------------------------------------------------------------------------- the data
@dataclass(eq=False)
class AeroDatabase:
    """Coefficients of one satellite set-up over an (aoa, aos) grid.

    Attributes
    ----------
    aoa_deg : ndarray, shape (na,)
        Angles of attack [deg], strictly increasing.
    aos_deg : ndarray, shape (nb,)
        Sideslip angles [deg], strictly increasing.
    CD, CL, CY : ndarray, shape (na, nb)
        Drag, lift and side-force coefficients (ADBSat's, from Cf_w).
    AreaProj : ndarray, shape (na, nb)
        Lit projected area normal to the flow [m^2].
    Cf_w, Cf_f, Cm_B, Cf_G, Cm_G : ndarray, shape (na, nb, 3)
        Force coefficients in wind, flight and mesh axes; moment coefficients in ADBSat body
        axes and mesh axes, about ``metadata["reference"]["moment_point"]``.
    metadata : dict
        JSON-ready description of the set-up (module docstring, contract in the notes).
    path : str or None
        File the database was loaded from (for messages), else None.
    """

    aoa_deg: np.ndarray
    aos_deg: np.ndarray
    CD: np.ndarray
    CL: np.ndarray
    CY: np.ndarray
    AreaProj: np.ndarray
    Cf_w: np.ndarray
    Cf_f: np.ndarray
    Cm_B: np.ndarray
    Cf_G: np.ndarray
    Cm_G: np.ndarray
    metadata: dict = field(default_factory=dict)
    path: str | None = None

    @property
    def shape(self) -> tuple:
        """Grid shape (na, nb)."""
        return (self.aoa_deg.size, self.aos_deg.size)

    @property
    def n_attitudes(self) -> int:
        """Number of attitudes na * nb."""
        return self.aoa_deg.size * self.aos_deg.size

    @property
    def reference_area(self) -> float:
        """A_ref [m^2]."""
        return float(self.metadata["reference"]["area"])

    @property
    def reference_length(self) -> float:
        """L_ref [m]."""
        return float(self.metadata["reference"]["length"])

    def flow_directions(self) -> np.ndarray:
        """Unit gas-flow directions u_G of the grid, shape (na, nb, 3) (frames module)."""
        a, b = np.meshgrid(np.radians(self.aoa_deg), np.radians(self.aos_deg), indexing="ij")
        return frames.flow_direction(a, b)

    # ------------------------------------------------------------------------------ files
    def save(self, path) -> str:
        """Write a compressed ``.npz`` file; returns the path written.

        Raises
        ------
        ValueError
            If ``path`` does not end in ``.npz`` (numpy would silently append it).
        OSError
            If the file cannot be written.
        """
        path = os.fspath(path)
        if not path.lower().endswith(".npz"):
            raise ValueError(f"{path}: a database file must end in .npz")
        arrays = {"aoa_deg": self.aoa_deg, "aos_deg": self.aos_deg}
        for name in SCALAR_FIELDS + VECTOR_FIELDS:
            arrays[name] = getattr(self, name)
        arrays["metadata"] = np.array(json.dumps(self.metadata, allow_nan=False))
        with open(path, "wb") as stream:
            np.savez_compressed(stream, **arrays)
        return path

    def csv_columns(self) -> list:
        """Column names of :meth:`save_csv`, in order."""
        columns = ["aoa_deg", "aos_deg", "CD", "CL", "CY"]
        for name in VECTOR_FIELDS:
            columns += [f"{name}_{axis}" for axis in "xyz"]
        return columns + ["AreaProj", "Aref", "Lref"]

    def save_csv(self, path) -> str:
        """Write one row per attitude (aoa varies slowest) with ``# key: value`` header lines.

        Values are written with 17 significant digits, so they read back exactly.
        """
        path = os.fspath(path)
        na, nb = self.shape
        a, b = np.meshgrid(self.aoa_deg, self.aos_deg, indexing="ij")
        columns = [a.reshape(-1), b.reshape(-1)]
        columns += [getattr(self, name).reshape(-1) for name in ("CD", "CL", "CY")]
        for name in VECTOR_FIELDS:
            vec = getattr(self, name).reshape(-1, 3)
            columns += [vec[:, 0], vec[:, 1], vec[:, 2]]
        columns.append(self.AreaProj.reshape(-1))
        columns.append(np.full(na * nb, self.reference_area))
        columns.append(np.full(na * nb, self.reference_length))
        table = np.column_stack(columns)
        with open(path, "w", encoding="utf-8", newline="\n") as stream:
            for line in self.header_lines():
                stream.write(f"# {line}\n")
            stream.write(",".join(self.csv_columns()) + "\n")
            np.savetxt(stream, table, delimiter=",", fmt="%.17g")
        return path

    def header_lines(self) -> list:
        """The ``key: value`` lines that head the CSV file (metadata essentials)."""
        m = self.metadata
        mesh, flow, ref, shading = m["mesh"], m["flow"], m["reference"], m["shading"]
        gas = (
            f"mean_mass_amu={flow['mean_mass_amu']}"
            if flow.get("mean_mass_amu") is not None
            else "number_densities=" + json.dumps(flow.get("number_densities"))
        )
        lines = [
            "adbsat_ros aerodynamic database (ADBSat coefficient names; angles in degrees)",
            f"format_version: {m['format_version']}",
            f"created_utc: {m['created_utc']}",
            f"adbsat_ros_version: {m['adbsat_ros_version']}",
            f"mesh: {mesh['spec']} (scale {mesh['scale']}, {mesh['n_panels']} panels, "
            f"fingerprint {mesh['fingerprint']})",
            f"model: {m['model']['name']} (incident_temperature {m['model']['incident_temperature']}, "
            f"adbsat_compat {m['model']['adbsat_compat']})",
            "materials: " + json.dumps(m["materials"]),
            f"flow: speed={flow['speed']} m/s, temperature={flow['temperature']} K, {gas}, "
            f"density={flow.get('density')} kg/m^3, speed_ratio={flow['speed_ratio']:.6g}",
            f"reference: Aref={ref['area']} m^2, Lref={ref['length']} m, moment_point={ref['moment_point']} m",
            f"shading: {shading['mode']} (samples {shading['samples']})",
            f"grid: {self.shape[0]} aoa x {self.shape[1]} aos",
        ]
        err = m["interpolation_error"]
        if err.get("force_coefficient") is not None:
            lines.append(
                f"interpolation_error: |dCf_G| <= {err['force_coefficient']:.3g}, "
                f"|dCm_G| <= {err['moment_coefficient']:.3g} ({err['method']})"
            )
        else:
            lines.append(f"interpolation_error: {err.get('method')}")
        if "conditions" in m:
            lines.append("conditions: " + json.dumps(m["conditions"]))
        return lines


# ---------------------------------------------------------------------------------- loading
def _fail(path, message):
    raise DatabaseError(f"{path}: {message}")


def load_database(path) -> AeroDatabase:
    """Read and validate a database written by :meth:`AeroDatabase.save`.

    Raises
    ------
    DatabaseError
        Naming the file and what is wrong: unreadable, not an npz, missing arrays or metadata,
        unsupported format version, inconsistent shapes, non-increasing angles, non-finite values.
    """
    path = os.fspath(path)
    try:
        with np.load(path, allow_pickle=False) as npz:
            contents = {name: npz[name] for name in npz.files}
    except FileNotFoundError:
        _fail(path, "no such file")
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        _fail(path, f"not a readable database (.npz) file: {exc}")
    if not isinstance(contents, dict):
        _fail(path, "not a database (.npz) file")
    missing = [k for k in ("aoa_deg", "aos_deg", "metadata", *SCALAR_FIELDS, *VECTOR_FIELDS) if k not in contents]
    if missing:
        _fail(path, f"missing arrays {', '.join(missing)}")
    raw = contents["metadata"]
    if raw.shape != () or raw.dtype.kind != "U":
        _fail(path, "metadata is not a JSON string")
    try:
        metadata = json.loads(str(raw))
    except json.JSONDecodeError as exc:
        _fail(path, f"metadata is not valid JSON: {exc}")
    if not isinstance(metadata, dict):
        _fail(path, "metadata is not a JSON object")
    absent = [k for k in REQUIRED_METADATA if k not in metadata]
    if absent:
        _fail(path, f"metadata lacks {', '.join(absent)}")
    version = metadata["format_version"]
    if version != FORMAT_VERSION:
        _fail(path, f"format_version {version!r} is not supported (this version reads {FORMAT_VERSION})")
    for key in ("area", "length", "moment_point"):
        if key not in metadata["reference"]:
            _fail(path, f"metadata reference lacks {key}")
    arrays = {}
    for name in ("aoa_deg", "aos_deg", *SCALAR_FIELDS, *VECTOR_FIELDS):
        value = contents[name]
        if value.dtype.kind not in "fi":
            _fail(path, f"{name} is not numeric (dtype {value.dtype})")
        value = np.asarray(value, dtype=float)
        if not np.all(np.isfinite(value)):
            _fail(path, f"{name} has non-finite values")
        arrays[name] = value
    for name in ("aoa_deg", "aos_deg"):
        a = arrays[name]
        if a.ndim != 1 or a.size == 0:
            _fail(path, f"{name} must be a non-empty 1-D array, got shape {a.shape}")
        if np.any(np.diff(a) <= 0):
            _fail(path, f"{name} is not strictly increasing")
    if arrays["aos_deg"][0] < -90.0 or arrays["aos_deg"][-1] > 90.0:
        _fail(path, "aos_deg outside [-90, 90]")
    grid = (arrays["aoa_deg"].size, arrays["aos_deg"].size)
    for name in SCALAR_FIELDS:
        if arrays[name].shape != grid:
            _fail(path, f"{name} has shape {arrays[name].shape}, expected {grid}")
    for name in VECTOR_FIELDS:
        if arrays[name].shape != grid + (3,):
            _fail(path, f"{name} has shape {arrays[name].shape}, expected {grid + (3,)}")
    return AeroDatabase(**arrays, metadata=metadata, path=path)


# ---------------------------------------------------------------------------------- metadata
def surface_values(props: SurfaceProperties) -> dict:
    """Every surface parameter of ``props`` as a float, by name (how the metadata records them)."""
    return {name: float(getattr(props, name)) for name in SURFACE_PARAMETERS}


def material_override_texts(materials: MaterialTable) -> list:
    """``NAME:key=value,...`` texts (every parameter, exact floats) that rebuild ``materials``
    with :meth:`MaterialTable.from_texts` and the same default."""
    texts = []
    for name, props in materials.materials.items():
        items = ",".join(f"{k}={v!r}" for k, v in surface_values(props).items())
        texts.append(f"{name}:{items}")
    return texts


def _flow_dict(flow: FreeStream) -> dict:
    return {
        "speed": float(flow.speed),
        "temperature": float(flow.temperature),
        "mean_mass_amu": None if flow.mean_mass_amu is None else float(flow.mean_mass_amu),
        "number_densities": None if flow.number_densities is None else dict(flow.number_densities),
        "density": None if flow.density is None else float(flow.density),
        "speed_ratio": float(flow.speed_ratio),
    }


def _mesh_spec_checked(method: PanelMethod, mesh_spec, mesh_scale) -> str | None:
    """The spec to record: given specs must reload to the method's mesh (same fingerprint)."""
    from adbsat_ros.geometry.example_satellite import EXAMPLE_MESH_NAME

    if mesh_spec is None:
        return None
    mesh_spec = os.fspath(mesh_spec)
    try:
        reloaded = resolve_mesh(mesh_spec, scale=mesh_scale).fingerprint()
    except MeshError as exc:
        raise ValueError(f"mesh_spec {mesh_spec!r}: {exc}") from None
    if reloaded != method.mesh.fingerprint():
        if mesh_spec == EXAMPLE_MESH_NAME:  # the default: the mesh was built some other way
            return None
        raise ValueError(
            f"mesh_spec {mesh_spec!r} (scale {mesh_scale}) does not load the method's mesh "
            "(fingerprints differ)"
        )
    return mesh_spec


def describe_setup(method: PanelMethod, flow: FreeStream, *, shading, samples, mesh_spec, mesh_scale,
                   materials_texts=None) -> dict:
    """Metadata of a set-up (everything but the grid results and the interpolation error)."""
    texts = material_override_texts(method.materials)
    if materials_texts:
        given = MaterialTable.from_texts(method.materials.default, materials_texts)
        rebuilt = MaterialTable.from_texts(method.materials.default, texts)
        if {k: surface_values(v) for k, v in given.materials.items()} != {
            k: surface_values(v) for k, v in rebuilt.materials.items()
        }:
            raise ValueError("materials_texts do not describe the method's materials")
    mesh = method.mesh
    ref = method.reference
    return {
        "format_version": FORMAT_VERSION,
        "created_utc": _dt.datetime.now(_dt.timezone.utc).replace(microsecond=0).isoformat(),
        "adbsat_ros_version": _package_version(),
        "mesh": {
            "spec": _mesh_spec_checked(method, mesh_spec, mesh_scale),
            "scale": float(mesh_scale),
            "source": str(mesh.source),
            "n_panels": int(mesh.n_panels),
            "fingerprint": mesh.fingerprint(),
        },
        "model": {
            "name": method.model,
            "incident_temperature": method.options.incident_temperature,
            "adbsat_compat": bool(method.options.adbsat_compat),
        },
        "materials": {"default": surface_values(method.materials.default), "overrides": texts},
        "flow": _flow_dict(flow),
        "reference": {
            "area": float(ref.area),
            "length": float(ref.length),
            "moment_point": [float(v) for v in ref.moment_point],
        },
        "shading": {"mode": str(shading), "samples": int(samples)},
    }


def method_from_metadata(metadata: dict, path=None):
    """Rebuild the set-up of a database: ``(PanelMethod, FreeStream, shader or None)``.

    The mesh is reloaded from ``metadata["mesh"]["spec"]`` and ``scale`` and must have the
    recorded fingerprint.

    Raises
    ------
    DatabaseError
        If the mesh cannot be reloaded (no spec, missing file, changed geometry) or the
        metadata is incomplete; names ``path`` when given.
    """
    where = path or "database"
    try:
        mesh_meta = metadata["mesh"]
        spec = mesh_meta["spec"]
        if spec is None:
            _fail(where, "the mesh was built in code (no mesh spec recorded), so it cannot be reloaded")
        try:
            mesh = resolve_mesh(spec, scale=float(mesh_meta["scale"]))
        except MeshError as exc:
            _fail(where, f"cannot reload the mesh {spec!r}: {exc}")
        if mesh.fingerprint() != mesh_meta["fingerprint"]:
            _fail(
                where,
                f"the mesh {spec!r} has changed since the database was built "
                f"(fingerprint {mesh.fingerprint()}, recorded {mesh_meta['fingerprint']})",
            )
        mat = metadata["materials"]
        materials = MaterialTable.from_texts(SurfaceProperties(**mat["default"]), mat["overrides"])
        model = metadata["model"]
        options = ModelOptions(
            incident_temperature=model["incident_temperature"], adbsat_compat=bool(model["adbsat_compat"])
        )
        ref = metadata["reference"]
        reference = Reference(area=ref["area"], length=ref["length"], moment_point=tuple(ref["moment_point"]))
        method = PanelMethod(mesh, model["name"], materials, options=options, reference=reference)
        f = metadata["flow"]
        flow = FreeStream(
            speed=f["speed"],
            temperature=f["temperature"],
            number_densities=f.get("number_densities"),
            mean_mass_amu=f.get("mean_mass_amu"),
            density=f.get("density"),
        )
        shading = metadata["shading"]
        shader = None
        if shading["mode"] != "none":
            from adbsat_ros.shading.shader import make_shader

            shader = make_shader(mesh, mode=shading["mode"], samples=int(shading["samples"]))
    except DatabaseError:
        raise
    except (KeyError, TypeError, ValueError) as exc:
        _fail(where, f"metadata does not describe a set-up: {type(exc).__name__}: {exc}")
    return method, flow, shader


# ---------------------------------------------------------------------------------- building
def _check_angles(values, name, low, high) -> np.ndarray:
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
        raise ValueError(f"{name}: angles must lie in [{low:g}, {high:g}] deg, got {a[0]:g}..{a[-1]:g}")
    return a


# Per-process state of the workers: (method, flow, shader) built once by _init_worker.
_WORKER = None


def _init_worker(method, flow, shading, samples):
    global _WORKER
    shader = None
    if shading != "none":
        from adbsat_ros.shading.shader import make_shader

        shader = make_shader(method.mesh, mode=shading, samples=samples)
        if shader.trivial:  # convex body: nothing is ever occluded
            shader = None
    _WORKER = (method, flow, shader)


def _evaluate_chunk(attitudes_deg):
    """Coefficients of a chunk of attitudes, shape (K, 2) [deg]: array (K, 19) in the order
    Cf_G, Cm_G, Cf_w, Cf_f, Cm_B (3 each), AreaProj, CD, CL, CY."""
    method, flow, shader = _WORKER
    out = np.empty((len(attitudes_deg), 19))
    for k, (a_deg, b_deg) in enumerate(attitudes_deg):
        a, b = math.radians(a_deg), math.radians(b_deg)
        lighting = shader.lighting(frames.flow_direction(a, b)) if shader is not None else None
        r = method.coefficients(flow, a, b, lighting=lighting)
        out[k, 0:3], out[k, 3:6], out[k, 6:9] = r.Cf_G, r.Cm_G, r.Cf_w
        out[k, 9:12], out[k, 12:15] = r.Cf_f, r.Cm_B
        out[k, 15:19] = (r.area_projected, r.drag, r.lift, r.side_force)
    return out


class _Progress:
    """Adapter for the ``progress`` argument of :func:`build_database`."""

    def __init__(self, progress, total):
        self._bar = None
        self._callback = None
        self._done = 0
        self.total = total
        if progress is None:  # a bar only for a person watching a terminal
            progress = hasattr(sys.stderr, "isatty") and sys.stderr.isatty()
        if progress is True:
            from tqdm import tqdm

            self._bar = tqdm(total=total, unit="att", desc="database", file=sys.stderr, leave=False)
            self._own = True
        elif progress is False:
            pass
        elif hasattr(progress, "update"):
            self._bar, self._own = progress, False
        elif callable(progress):
            self._callback = progress
        else:
            raise TypeError("progress must be None, a bool, a callable(done, total) or a tqdm instance")

    def update(self, n):
        self._done += n
        if self._bar is not None:
            self._bar.update(n)
        if self._callback is not None:
            self._callback(self._done, self.total)

    def close(self):
        if self._bar is not None and self._own:
            self._bar.close()


def _pool_context():
    """Fork where available (workers start in milliseconds and inherit the imports)."""
    import multiprocessing

    if "fork" in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("fork")
    return multiprocessing.get_context()


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
    materials_texts=(),
    conditions: dict | None = None,
) -> AeroDatabase:
    """Evaluate the panel method at every (aoa, aos) pair of two angle lists.

    Parameters
    ----------
    method : PanelMethod
        Mesh, gas-surface model, materials and reference quantities.
    flow : FreeStream
        The free stream.
    aoa_deg, aos_deg : array_like
        Angles of attack in [-360, 360] and sideslip angles in [-90, 90] [deg]; sorted here,
        duplicates rejected.
    shading : {"raycast", "projection", "none"}
        Shading mode (:mod:`adbsat_ros.shading.shader`); each worker builds its shader once.
    samples : int
        Rays per panel for raycast shading.
    workers : int, optional
        Processes to use (default ``os.cpu_count()``); 1 computes in this process. The result
        does not depend on it.
    progress : None, bool, callable or tqdm, optional
        None: a tqdm bar on stderr if stderr is a terminal, else nothing; True/False: bar or
        not; a callable is called as ``progress(done, total)``; an object with ``update(n)``
        (a tqdm instance) is updated.
    mesh_spec : str or None
        How the mesh is reloaded (path or ``"example"``), recorded in the metadata and checked
        against the method's mesh; the default ``"example"`` is recorded only if the method's
        mesh is the example (else None: not reloadable).
    mesh_scale : float
        Scale given when loading the mesh file.
    materials_texts : sequence of str
        Override texts the materials were built from (checked against ``method.materials``;
        the metadata always records exact texts derived from the table).
    conditions : dict, optional
        JSON-ready description of the flight conditions the flow came from, recorded as
        ``metadata["conditions"]``.

    Returns
    -------
    AeroDatabase
        With ``metadata["interpolation_error"]`` set (see
        :func:`adbsat_ros.database.lookup.estimate_interpolation_error`).
    """
    from adbsat_ros.database.lookup import estimate_interpolation_error
    from adbsat_ros.shading.shader import MODES

    shading = str(shading).lower()
    if shading not in MODES:
        raise ValueError(f"unknown shading mode {shading!r}; choose one of {', '.join(MODES)}")
    samples = int(samples)
    if samples < 1:
        raise ValueError(f"samples must be >= 1, got {samples}")
    if workers is None:
        workers = os.cpu_count() or 1
    if isinstance(workers, bool) or int(workers) != workers or workers < 1:
        raise ValueError(f"workers must be an integer >= 1, got {workers!r}")
    workers = int(workers)
    aoa = _check_angles(aoa_deg, "aoa_deg", -360.0, 360.0)
    aos = _check_angles(aos_deg, "aos_deg", -90.0, 90.0)
    metadata = describe_setup(
        method, flow, shading=shading, samples=samples, mesh_spec=mesh_spec, mesh_scale=mesh_scale,
        materials_texts=materials_texts,
    )
    if conditions is not None:
        metadata["conditions"] = conditions

    grid_a, grid_b = np.meshgrid(aoa, aos, indexing="ij")
    attitudes = np.column_stack([grid_a.reshape(-1), grid_b.reshape(-1)])
    total = len(attitudes)
    workers = min(workers, total)
    chunk = max(1, min(MAX_CHUNK, math.ceil(total / (8 * workers))))
    starts = range(0, total, chunk)
    results = np.empty((total, 19))
    bar = _Progress(progress, total)
    try:
        if workers == 1:
            global _WORKER
            saved = _WORKER
            _init_worker(method, flow, shading, samples)
            try:
                for s in starts:
                    results[s : s + chunk] = _evaluate_chunk(attitudes[s : s + chunk])
                    bar.update(len(attitudes[s : s + chunk]))
            finally:
                _WORKER = saved
        else:
            from concurrent.futures import ProcessPoolExecutor, as_completed

            with ProcessPoolExecutor(
                max_workers=workers,
                mp_context=_pool_context(),
                initializer=_init_worker,
                initargs=(method, flow, shading, samples),
            ) as pool:
                futures = {pool.submit(_evaluate_chunk, attitudes[s : s + chunk]): s for s in starts}
                for future in as_completed(futures):
                    s = futures[future]
                    block = future.result()
                    results[s : s + len(block)] = block
                    bar.update(len(block))
    finally:
        bar.close()

    shape = (aoa.size, aos.size)
    vec = lambda k: results[:, k : k + 3].reshape(shape + (3,)).copy()  # noqa: E731
    db = AeroDatabase(
        aoa_deg=aoa,
        aos_deg=aos,
        Cf_G=vec(0),
        Cm_G=vec(3),
        Cf_w=vec(6),
        Cf_f=vec(9),
        Cm_B=vec(12),
        AreaProj=results[:, 15].reshape(shape).copy(),
        CD=results[:, 16].reshape(shape).copy(),
        CL=results[:, 17].reshape(shape).copy(),
        CY=results[:, 18].reshape(shape).copy(),
        metadata=metadata,
    )
    db.metadata["interpolation_error"] = estimate_interpolation_error(db)
    return db
