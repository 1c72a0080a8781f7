"""A sweep's Zarr store read as databases: its (aoa, aos) grid at any point of the other axes,
the slices around it blended multilinearly. docs/sweeps.md.
"""

from __future__ import annotations

import itertools
import os

import numpy as np

from adbsat_ros.database.format import SCALAR_FIELDS, VECTOR_FIELDS, AeroDatabase
from adbsat_ros.database.interpolation import cell, estimate_interpolation_error
from adbsat_ros.geometry import frames

#: Values within this much of an axis's ends count as inside (rounding).
TOLERANCE = 1e-9
#: The database's arrays and the sweep's variables they are read from (Cf_f is made from Cf_G).
FIELDS = tuple(
    (name, "area_projected" if name == "AreaProj" else name)
    for name in SCALAR_FIELDS + VECTOR_FIELDS
    if name != "Cf_f"
)


def is_sweep_store(path) -> bool:
    """Whether ``path`` is a directory holding a Zarr group."""
    path = os.fspath(path)
    return os.path.isdir(path) and any(
        os.path.exists(os.path.join(path, name)) for name in ("zarr.json", ".zgroup")
    )


def open_sweep(path):
    """The xarray Dataset of the complete sweep store ``path``, else ValueError naming it."""
    import xarray as xr

    try:
        # (time stays hours after the epoch: every axis is a number here)
        dataset = xr.open_zarr(os.fspath(path), consolidated=False, decode_times=False)
    except Exception as exc:  # (zarr and xarray raise many kinds for a non-store)
        raise ValueError(f"{path}: not a sweep store ({type(exc).__name__})") from None
    if "Cf_G" not in dataset or "reference_area_m2" not in dataset.attrs:
        raise ValueError(f"{path}: not a sweep store (no Cf_G or reference quantities)")
    if "chunk_done" in dataset and not bool(dataset["chunk_done"].values.all()):
        raise ValueError(f"{path}: the sweep is not complete: run it again to compute the rest")
    return dataset


def other_axes(dataset) -> dict:
    """The sweep's axes other than aoa and aos: name -> values."""
    return {
        name: np.asarray(dataset[name].values, dtype=float)
        for name in dataset["Cf_G"].dims
        if name not in ("aoa", "aos", "component")
    }


def bracket(nodes: np.ndarray, name: str, value: float) -> list:
    """``[(index, weight), ...]`` of the grid values of axis ``name`` around ``value``."""
    low, high = float(nodes[0]), float(nodes[-1])
    if not low - TOLERANCE <= value <= high + TOLERANCE:
        raise ValueError(f"{name} {value!r} is outside the sweep's range [{low:g}, {high:g}]")
    if nodes.size == 1:
        return [(0, 1.0)]
    k, k1, t = cell(nodes.tolist(), value)
    t = min(max(t, 0.0), 1.0)
    return [(k, 1.0 - t), (k1, t)]


def corners(axes: dict, values: dict) -> list:
    """``[(index, weight), ...]`` around ``values``; ValueError naming a bad axis."""
    missing = sorted(set(axes) - set(values))
    unknown = sorted(set(values) - set(axes))
    if missing or unknown:
        raise ValueError(
            f"give a value of every axis of the sweep besides aoa and aos "
            f"({', '.join(axes) or 'none'}); missing {missing}, unknown {unknown}"
        )
    brackets = [bracket(axes[name], name, float(values[name])) for name in axes]
    out = []
    for corner in itertools.product(*brackets):
        weight = float(np.prod([w for _, w in corner]))
        if weight != 0.0:
            out.append((tuple(i for i, _ in corner), weight))
    return out


def slice_database(dataset, index: dict, stated_error: bool = False) -> AeroDatabase:
    """The attitude grid at grid point ``index`` (axis name -> position) of the other axes."""
    return _database(dataset, _arrays(dataset, index), {}, stated_error)


def sweep_database(dataset, **values) -> AeroDatabase:
    """The attitude grid at a value of every other axis; ValueError as :func:`corners`."""
    axes = other_axes(dataset)
    arrays = None
    for corner, weight in corners(axes, values):
        part = _arrays(dataset, dict(zip(axes, corner)), weight)
        arrays = part if arrays is None else {k: arrays[k] + part[k] for k in arrays}
    at = {name: float(values[name]) for name in axes}
    return _database(dataset, arrays, at, stated_error=True)


def _arrays(dataset, index: dict, weight: float = 1.0) -> dict:
    return {
        name: weight * np.asarray(dataset[source].isel(index).values, dtype=float)
        for name, source in FIELDS
    }


def _database(dataset, arrays: dict, at: dict, stated_error: bool) -> AeroDatabase:
    attrs = dataset.attrs
    database = AeroDatabase(
        aoa_deg=np.asarray(dataset["aoa"].values, dtype=float),
        aos_deg=np.asarray(dataset["aos"].values, dtype=float),
        Cf_f=arrays["Cf_G"] @ (frames.L_FB @ frames.L_GB).T,  # (ADBSat's flight axes)
        **arrays,
        metadata={
            "reference": {
                "area": float(attrs["reference_area_m2"]),
                "length": float(attrs["reference_length_m"]),
                "moment_point": [float(v) for v in attrs["moment_point_m"]],
            },
            "sweep": {
                "spec_fingerprint": attrs.get("spec_fingerprint"),
                "mesh": attrs.get("mesh"),
                "model": attrs.get("model"),
                "shading": attrs.get("shading"),
                "at": at,
            },
        },
    )
    if stated_error:
        database.metadata["interpolation_error"] = estimate_interpolation_error(database)
    return database
