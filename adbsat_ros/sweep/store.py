"""A sweep's result in a Zarr store, written chunk by chunk as the chunks finish.

The store is an xarray Dataset: one dimension per axis (its coordinate in the spec's units, the
unit in the coordinate's attributes), ``component`` (x, y, z: 0, 1, 2) for the vector results, and
``chunk`` for ``chunk_done``, which says which chunks are written. A chunk's results are written
before its flag, so a store that a killed run left behind holds every flagged chunk complete:
running the same spec again computes the others only. The spec (its YAML text and fingerprint),
the body's mesh fingerprint and panel count, the reference quantities and the package version are
the Dataset's attributes. Zarr chunks are the sweep's chunks, so no two writes share one.
"""

from __future__ import annotations

import itertools
import json
import shutil
from pathlib import Path

import numpy as np

from adbsat_ros._version import __version__
from adbsat_ros.sweep.axes import AXES, JOINT_PREFIX
from adbsat_ros.sweep.evaluate import SCALARS, vector_results
from adbsat_ros.sweep.spec import SweepSpec


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

    def __init__(self, path: Path, spec: SweepSpec, sizes: tuple, slices: list):
        self.path = path
        self.spec = spec
        self.sizes = sizes
        self.slices = slices
        self._opened = None

    @classmethod
    def open(cls, path, spec: SweepSpec, setup, overwrite: bool = False) -> "SweepStore":
        """The store at ``path`` for ``spec``: made if it is not there (or ``overwrite``),
        taken up where it stopped if it holds this spec's sweep.

        Raises
        ------
        StoreError
            ``path`` holds something else (another spec's sweep, or not a sweep).
        """
        import xarray as xr

        path = Path(path)
        sizes = chunk_shape(spec.shape, spec.chunk_points)
        slices = chunk_slices(spec.shape, sizes)
        store = cls(path, spec, sizes, slices)
        if path.exists() and overwrite:
            shutil.rmtree(path) if path.is_dir() else path.unlink()
        if path.exists():
            try:
                attrs = xr.open_zarr(path, consolidated=False, decode_times=False).attrs
            except Exception as exc:  # (zarr and xarray raise many kinds for a non-store)
                raise StoreError(
                    f"--out {path}: exists and is not a sweep store ({type(exc).__name__}); "
                    "choose another path, or --overwrite"
                ) from None
            if attrs.get("spec_fingerprint") != spec.fingerprint:
                raise StoreError(
                    f"--out {path}: holds another spec's sweep; choose another path, or --overwrite"
                )
            return store
        store._create(setup)
        return store

    def _create(self, setup) -> None:
        import dask.array as da
        import xarray as xr

        spec = self.spec
        dims = list(spec.axes)
        coords = {
            name: (name, np.asarray(values), {"units": _unit(name, setup)})
            for name, values in spec.axes.items()
        }
        if "mesh" in coords:
            coords["mesh"][2]["meshes"] = list(spec.meshes)
        data = {}
        for name in vector_results(spec):
            shape, chunks = (*spec.shape, 3), (*self.sizes, 3)
            data[name] = ([*dims, "component"], da.full(shape, np.nan, chunks=chunks))
        for name in SCALARS:
            data[name] = (dims, da.full(spec.shape, np.nan, chunks=self.sizes))
        data["chunk_done"] = (["chunk"], da.zeros(len(self.slices), dtype="i1", chunks=1))
        method = setup.method
        attrs = {
            "title": f"adbsat-ros sweep of {spec.mesh}",
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
        dataset = xr.Dataset(data, coords=coords, attrs=attrs)
        dataset["area_projected"].attrs["units"] = "m^2"
        units = (
            ("density", "kg/m^3"),
            ("gas_temperature", "K"),
            ("gas_speed", "m/s"),
            ("gas_mean_mass", "amu"),
        )
        for name, unit in units:
            dataset[name].attrs["units"] = unit
        if spec.meshes:
            attrs = dataset.attrs
            attrs["mesh_variants"] = list(spec.meshes)
            attrs["mesh_fingerprints"] = [body.mesh.fingerprint() for body in setup.bodies]
            attrs["n_panels_of_variants"] = [int(body.mesh.n_panels) for body in setup.bodies]
        # (no coordinate for the components: a string one has no Zarr 3 data type yet)
        for name in vector_results(spec):
            dataset[name].attrs["component"] = "x, y, z"
        dataset.to_zarr(self.path, compute=False, mode="w", consolidated=False)

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

    def write(self, index: int, results: dict) -> None:
        """Write chunk ``index``'s results, then its flag."""
        arrays = self._arrays()
        region = tuple(slice(a, b) for a, b in self.slices[index])
        for name, values in results.items():
            arrays[name][region + ((slice(None),) if values.ndim > len(region) else ())] = values
        arrays["chunk_done"][index] = 1
