"""A sweep's result in a Zarr store (xarray, one dimension per axis), written chunk by chunk.

Each chunk's results precede its ``chunk_done`` flag and the store is made under a hidden
temporary name, so a killed run leaves no store or one to take up. docs/sweeps.md.
"""

from __future__ import annotations

import base64
import contextlib
import itertools
import json
import os
import re
import shutil
import tempfile
from pathlib import Path

import numpy as np

from adbsat_ros._version import __version__
from adbsat_ros.sweep.axes import AXES, JOINT_PREFIX
from adbsat_ros.sweep.evaluate import SCALARS, SweepSetup, vector_results
from adbsat_ros.sweep.spec import SweepSpec
from adbsat_ros.validation import foreign_entry, not_an_output

#: The title attribute of every sweep store starts so.
TITLE = "adbsat-ros sweep of "


class StoreError(ValueError):
    """A store that cannot take this sweep (another spec's, or not a sweep); names the path."""


def chunk_shape(shape: tuple, points: int) -> tuple:
    """Chunk sizes along each axis: whole trailing axes first, about ``points`` points."""
    sizes = [1] * len(shape)
    total = 1
    for k in reversed(range(len(shape))):
        sizes[k] = max(1, min(shape[k], points // total))
        total *= sizes[k]
    return tuple(sizes)


def chunk_slices(shape: tuple, sizes: tuple) -> list:
    """Every chunk's ((start, stop) per axis), in C order of the chunk grid."""
    starts = [range(0, n, s) for n, s in zip(shape, sizes)]
    return [
        tuple((a, min(a + s, n)) for a, s, n in zip(corner, sizes, shape))
        for corner in itertools.product(*starts)
    ]


def _unit(axis: str, setup) -> str:
    if axis.startswith(JOINT_PREFIX):
        kind = setup.body.joints[axis[len(JOINT_PREFIX) :]].kind
        return "m" if kind == "prismatic" else "deg"
    if axis == "time":  # (CF conventions: xarray reads it as dates)
        return f"hours since {setup.spec.time}"
    return AXES[axis][1] if axis in AXES else ""  # (scale.SPECIES, mesh: numbers)


class SweepStore:
    """The Zarr store of one sweep (module docstring); open with :meth:`open`."""

    def __init__(self, path, spec: SweepSpec):
        self.path = Path(path)
        self.spec = spec
        self.sizes = chunk_shape(spec.shape, spec.chunk_points)
        self.slices = chunk_slices(spec.shape, self.sizes)
        self._opened = None

    @classmethod
    def open(cls, path, spec: SweepSpec, setup, overwrite: bool = False) -> "SweepStore":
        """The store at ``path`` for ``spec``: made, or taken up where it stopped.

        StoreError: another spec's sweep (without ``overwrite``) or anything but a sweep store.
        """
        store = cls(path, spec)
        path = store.path
        if not (path.exists() or path.is_symlink()):
            store._create(setup, replace=False)
            return store
        foreign = _foreign(path)
        if foreign is not None:
            raise StoreError(not_an_output(foreign, "sweep", "--out"))
        attrs = _sweep_attrs(path)  # (None: an empty directory)
        if attrs is not None and not overwrite:
            if attrs.get("spec_fingerprint") != spec.fingerprint:
                raise StoreError(
                    f"--out {path}: holds another spec's sweep; choose another path, or --overwrite"
                )
            if store._complete():
                return store
        store._create(setup, replace=True)
        return store

    def _complete(self) -> bool:
        """Whether every array of the layout is in the store."""
        import zarr

        group = zarr.open_group(str(self.path), mode="r")
        names = (*vector_results(self.spec), *SCALARS, "chunk_done")
        missing = [name for name in names if name not in group]
        if not missing:
            return True
        if "chunk_done" in group and np.any(group["chunk_done"][:]):
            raise StoreError(
                f"--out {self.path}: holds computed chunks but no {', '.join(missing)}; "
                "choose another path, or --overwrite"
            )
        return False

    def _create(self, setup, replace: bool) -> None:
        """Write the layout under a temporary name, then rename it into place."""
        parent = self.path.parent
        parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{self.path.name}.", suffix=".partial", dir=parent))
        try:
            self._write_layout(tmp, setup)
            old = None
            if replace:
                old = Path(
                    tempfile.mkdtemp(prefix=f".{self.path.name}.", suffix=".old", dir=parent)
                )
                os.replace(self.path, old)  # (a directory: it takes the empty one's place)
            os.replace(tmp, self.path)
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise
        if old is not None:
            shutil.rmtree(old)

    def _write_layout(self, where: Path, setup) -> None:
        """The Dataset's coordinates, attributes and arrays (NaN, no chunk done) at ``where``, as
        xarray's ``to_zarr`` lays them out (``dimension_names``, ``_FillValue``)."""
        import zarr

        spec = self.spec
        method = setup.method
        attrs = {
            "title": f"{TITLE}{spec.mesh}",
            "spec_yaml": spec.text,
            "spec_fingerprint": spec.fingerprint,
            "adbsat_ros_version": __version__,
            "mesh": spec.mesh,
            "mesh_fingerprint": setup.mesh.fingerprint(),
            "n_panels": int(setup.mesh.n_panels),
            "solver": json.dumps(dict(spec.solver), sort_keys=True),
            "model": spec.model,
            "shading": spec.shading,
            "fixed_inputs": json.dumps(spec.fixed, sort_keys=True),
            "atmosphere": "NRLMSISE-00 at a circular orbit's speed, UTC " + spec.time
            if spec.atmosphere
            else "none: the gas as given",
            "reference_area_m2": float(method.reference.area),
            "reference_length_m": float(method.reference.length),
            "moment_point_m": [float(v) for v in method.reference.moment_point],
            "frames": "Cf_G, Cm_G: mesh (body) frame G; Cf_w, Cm_w: wind axes (CD = -Cf_w[0]); "
            "Cm_B: ADBSat's body axes B (docs/physics.md section 2)",
        }
        if spec.meshes:
            attrs["mesh_variants"] = list(spec.meshes)
            attrs["mesh_fingerprints"] = [body.mesh.fingerprint() for body in setup.bodies]
            attrs["n_panels_of_variants"] = [int(body.mesh.n_panels) for body in setup.bodies]
        group = zarr.open_group(str(where), mode="w", zarr_format=3, attributes=attrs)

        def array(name, dims, shape, chunks, dtype=float, **attributes):
            fill = np.nan if dtype is float else 0
            if dtype is float:  # (xarray's mark of the missing value: NaN, base64 of its bytes)
                attributes["_FillValue"] = base64.b64encode(np.float64(fill).tobytes()).decode()
            layout = {"chunks": chunks, "dtype": dtype, "fill_value": fill, "dimension_names": dims}
            return group.create_array(name, shape=shape, attributes=attributes, **layout)

        for name, values in spec.axes.items():
            values = np.asarray(values, dtype=float)
            extra = {"meshes": list(spec.meshes)} if name == "mesh" else {}
            shape = values.shape
            array(name, [name], shape, shape, units=_unit(name, setup), **extra)[:] = values
        dims = list(spec.axes)
        units = {"area_projected": "m^2", "density": "kg/m^3", "gas_temperature": "K"}
        units |= {"gas_speed": "m/s", "gas_mean_mass": "amu"}
        # (no coordinate for the components: a string one has no Zarr 3 data type yet)
        for name in vector_results(spec):
            shape, chunks = (*spec.shape, 3), (*self.sizes, 3)
            array(name, [*dims, "component"], shape, chunks, component="x, y, z")
        for name in SCALARS:
            extra = {"units": units[name]} if name in units else {}
            array(name, dims, spec.shape, self.sizes, **extra)
        array("chunk_done", ["chunk"], (len(self.slices),), (1,), dtype="i1")

    def _arrays(self) -> dict:
        """The store's Zarr arrays by name, opened once (each opening reads its metadata)."""
        if self._opened is None:
            import zarr

            group = zarr.open_group(str(self.path), mode="r+")
            names = (*vector_results(self.spec), *SCALARS, "chunk_done")
            self._opened = {name: group[name] for name in names}
        return self._opened

    def missing(self) -> list:
        """Indices of the chunks not written yet."""
        done = self._arrays()["chunk_done"][:]
        return [int(i) for i in np.flatnonzero(done == 0)]

    def write_results(self, slices, results: dict) -> None:
        """Write the results of the chunk ``slices`` ((start, stop) per axis); its files alone,
        so workers may write their chunks at once."""
        arrays = self._arrays()
        region = tuple(slice(a, b) for a, b in slices)
        for name, values in results.items():
            arrays[name][region + ((slice(None),) if values.ndim > len(region) else ())] = values

    def mark_done(self, index: int) -> None:
        """Flag chunk ``index`` done, once its results are written."""
        self._arrays()["chunk_done"][index] = 1


class SweepChunks:
    """A sweep's chunks where they run: each computed (:class:`SweepSetup`) and, given the store's
    ``path``, written there (local workers share its file system); else returned."""

    def __init__(self, spec: SweepSpec, path=None):
        self.setup = SweepSetup(spec)
        self.store = None if path is None else SweepStore(path, spec)

    def evaluate(self, slices) -> dict | None:
        """The chunk ``slices``'s results, or None once written to the store."""
        results = self.setup.evaluate(slices)
        if self.store is None:
            return results
        self.store.write_results(slices, results)
        return None


_PARTIAL = re.compile(r"\d+\.[0-9a-f]{32}\.partial")


def _zarr_file(parts: tuple) -> bool:
    """Whether a file is one a sweep's Zarr store holds."""
    if parts == ("zarr.json",) or (len(parts) == 2 and parts[1] == "zarr.json"):
        return True
    if len(parts) < 3 or parts[1] != "c" or not all(p.isdigit() for p in parts[2:-1]):
        return False
    # (or the temporary file of a chunk a killed run was writing: <index>.<hex>.partial)
    return parts[-1].isdigit() or _PARTIAL.fullmatch(parts[-1]) is not None


def _sweep_attrs(path: Path) -> dict | None:
    """The attributes of the sweep store at ``path``, or None (not a sweep store's group)."""
    with contextlib.suppress(OSError, ValueError, KeyError, TypeError):
        meta = json.loads((path / "zarr.json").read_text(encoding="utf-8"))
        attrs = meta["attributes"]
        if meta.get("node_type") == "group" and str(attrs["title"]).startswith(TITLE):
            return attrs
    return None


def _foreign(path: Path) -> Path | None:
    """What at ``path`` a sweep did not write; None for a sweep store or empty directory."""
    entry = foreign_entry(path, _zarr_file)
    if entry is None and any(path.iterdir()) and _sweep_attrs(path) is None:
        return path
    return entry
