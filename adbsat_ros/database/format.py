"""The aerodynamic database: coefficient grids over (aoa, aos) [deg] with their set-up, as ``.npz``
(metadata as JSON) or CSV (``# key: value`` header); frames of :mod:`adbsat_ros.geometry.frames`.
Forces ``q A_ref Cf`` [N], torques ``q A_ref L_ref Cm`` [N m]. docs/physics.md, section 9.
"""

from __future__ import annotations

import json
import os
import zipfile
from dataclasses import dataclass, field

import numpy as np

from adbsat_ros.geometry import frames

#: Version of the file layout written and read.
FORMAT_VERSION = 1
#: The first line of a database's CSV file (after "# ").
CSV_TITLE = "adbsat_ros aerodynamic database (columns: docs/outputs.md; angles in degrees)"

#: Per-attitude scalar arrays, shape (na, nb).
SCALAR_FIELDS = ("CD", "CL", "CY", "AreaProj")
#: Per-attitude vector arrays, shape (na, nb, 3).
VECTOR_FIELDS = ("Cf_w", "Cf_f", "Cm_B", "Cf_G", "Cm_G")
#: Every array of a database file but its metadata.
ARRAYS = ("aoa_deg", "aos_deg", *SCALAR_FIELDS, *VECTOR_FIELDS)
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


class DatabaseError(ValueError):
    """A database file (or its metadata) that cannot be used; the message names the file."""


# ---------------------------------------------------------------------------------- the data
@dataclass(eq=False)
class AeroDatabase:
    """Coefficients of one satellite set-up over an (aoa, aos) grid; angles [deg] strictly increase.

    (na, nb): ``CD``, ``CL``, ``CY``, ``AreaProj`` [m^2]; (na, nb, 3): ``Cf_w``, ``Cf_f``, ``Cf_G``
    (wind, flight, mesh axes), ``Cm_B``, ``Cm_G`` about ``metadata["reference"]["moment_point"]``.
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
        """(na, nb)."""
        return (self.aoa_deg.size, self.aos_deg.size)

    @property
    def n_attitudes(self) -> int:
        """na * nb."""
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
        """Unit gas-flow directions u_G of the grid, shape (na, nb, 3)."""
        a, b = np.meshgrid(np.radians(self.aoa_deg), np.radians(self.aos_deg), indexing="ij")
        return frames.flow_direction(a, b)

    # ------------------------------------------------------------------------------ files
    def save(self, path) -> str:
        """Write a compressed ``.npz``; the path.

        ValueError: ``path`` not ending in ``.npz``, or a stopped build.
        """
        path = os.fspath(path)
        if not path.lower().endswith(".npz"):
            raise ValueError(f"{path}: a database file must end in .npz")
        if self.metadata.get("partial"):
            raise ValueError(f"{path}: the build was stopped; a partial grid is not a database")
        arrays = {name: getattr(self, name) for name in ARRAYS}
        arrays["metadata"] = np.array(json.dumps(self.metadata, allow_nan=False))
        with open(path, "wb") as stream:
            np.savez_compressed(stream, **arrays)
        return path

    def csv_columns(self) -> list:
        """Column names of :meth:`save_csv` (docs/outputs.md): Cf_G, Cm_G as ``cf_x``, ``cm_x``."""
        columns = ["aoa_deg", "aos_deg", "drag_coefficient", "lift_coefficient"]
        columns.append("side_force_coefficient")
        for name in VECTOR_FIELDS:
            frame = "" if name.endswith("_G") else name[3:].lower() + "_"
            columns += [f"{name[:2].lower()}_{frame}{axis}" for axis in "xyz"]
        return columns + ["projected_area_m2", "reference_area_m2", "reference_length_m"]

    def save_csv(self, path) -> str:
        """Write one row per attitude (aoa slowest), 17 significant digits."""
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
        table = table[np.isfinite(table[:, 2])]
        with open(path, "w", encoding="utf-8", newline="\n") as stream:
            for line in self.header_lines():
                stream.write(f"# {line}\n")
            stream.write(",".join(self.csv_columns()) + "\n")
            np.savetxt(stream, table, delimiter=",", fmt="%.17g")
        return path

    def header_lines(self) -> list:
        """The ``key: value`` lines that head the CSV file."""
        m = self.metadata
        mesh, flow, ref, shading = m["mesh"], m["flow"], m["reference"], m["shading"]
        model = m["model"]
        gas = (
            f"mean_mass_amu={flow['mean_mass_amu']}"
            if flow.get("mean_mass_amu") is not None
            else "number_densities=" + json.dumps(flow.get("number_densities"))
        )
        lines = [
            CSV_TITLE,
            f"format_version: {m['format_version']}",
            f"created_utc: {m['created_utc']}",
            f"adbsat_ros_version: {m['adbsat_ros_version']}",
            f"mesh: {mesh['spec']} (scale {mesh['scale']}, {mesh['n_panels']} panels, "
            f"fingerprint {mesh['fingerprint']})",
            f"model: {model['name']} (incident_temperature {model['incident_temperature']}, "
            f"adbsat_compat {model['adbsat_compat']})",
            "materials: " + json.dumps(m["materials"]),
            f"flow: speed={flow['speed']} m/s, temperature={flow['temperature']} K, {gas}, "
            f"density={flow.get('density')} kg/m^3, speed_ratio={flow['speed_ratio']:.6g}",
            f"reference: Aref={ref['area']} m^2, Lref={ref['length']} m, "
            f"moment_point={ref['moment_point']} m",
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


def is_database_file(path) -> bool:
    """Whether ``path`` is a file :meth:`AeroDatabase.save` wrote (an .npz of its arrays)."""
    try:
        with zipfile.ZipFile(path) as archive:
            names = set(archive.namelist())
    except (OSError, zipfile.BadZipFile):
        return False
    return {f"{name}.npy" for name in ("aoa_deg", "aos_deg", "metadata", "CD")} <= names


def is_database_csv(path) -> bool:
    """Whether ``path`` is a file :meth:`AeroDatabase.save_csv` wrote (by its first line)."""
    start = f"# {CSV_TITLE[: CSV_TITLE.index('(') + 1]}".encode()  # (any version's title)
    try:
        with open(path, "rb") as stream:
            return stream.read(len(start)) == start
    except OSError:
        return False


# ---------------------------------------------------------------------------------- loading
def _fail(path, message):
    raise DatabaseError(f"{path}: {message}")


def load_database(path) -> AeroDatabase:
    """The :class:`AeroDatabase` of a ``.npz``; DatabaseError naming the file and fault."""
    path = os.fspath(path)
    try:
        with np.load(path, allow_pickle=False) as npz:
            contents = {name: npz[name] for name in npz.files}
    except FileNotFoundError:
        _fail(path, "no such file")
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        _fail(path, f"not a readable database (.npz) file: {exc}")
    missing = [k for k in ("aoa_deg", "aos_deg", "metadata", *ARRAYS[2:]) if k not in contents]
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
        _fail(
            path,
            f"format_version {version!r} is not supported (this version reads {FORMAT_VERSION})",
        )
    for key in ("area", "length", "moment_point"):
        if key not in metadata["reference"]:
            _fail(path, f"metadata reference lacks {key}")
    arrays = {}
    for name in ARRAYS:
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
    for name in ARRAYS[2:]:
        expected = grid + ((3,) if name in VECTOR_FIELDS else ())
        if arrays[name].shape != expected:
            _fail(path, f"{name} has shape {arrays[name].shape}, expected {expected}")
    return AeroDatabase(**arrays, metadata=metadata, path=path)
