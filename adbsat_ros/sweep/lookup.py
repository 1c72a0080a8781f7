"""Coefficients anywhere inside a sweep, by interpolation: bilinear in attitude, linear in the
other axes.

For each grid point of the other axes (speed, alpha, altitude, joint positions ...) the sweep's
(aoa, aos) slice is a database that :class:`~adbsat_ros.database.lookup.CoefficientLookup`
interpolates as it does a database file (body-frame vectors, the aoa circle closed when the grid
goes round, the poles). Along the other axes the query is bracketed by two grid values and the
corners' results are blended linearly (multilinear over several axes). A query outside an axis's
range is refused with the axis and its range; an axis with one value takes only that value.
"""

from __future__ import annotations

import bisect
import itertools

import numpy as np

from adbsat_ros.database.format import AeroDatabase
from adbsat_ros.database.lookup import CoefficientLookup, InterpolatedCoefficients
from adbsat_ros.geometry import frames
from adbsat_ros.lru import LruStore

#: Values within this much of an axis's ends count as inside (rounding).
TOLERANCE = 1e-9


class SweepLookup:
    """Interpolated coefficients of a sweep store (module docstring).

    Parameters
    ----------
    dataset : xarray.Dataset
        A sweep's result (``xarray.open_zarr(path)``), complete.

    Attributes
    ----------
    axes : dict of str to ndarray
        The axes other than aoa and aos, and their values.
    slices : LruStore
        The attitude lookups of the other axes' grid points made so far.
    """

    def __init__(self, dataset):
        if "chunk_done" in dataset and not bool(dataset["chunk_done"].values.all()):
            raise ValueError("the sweep is not complete: run it again to compute the rest")
        self._ds = dataset
        self.axes = {
            name: np.asarray(dataset[name].values, dtype=float)
            for name in dataset["Cf_G"].dims
            if name not in ("aoa", "aos", "component")
        }
        self._reference = {
            "area": float(dataset.attrs["reference_area_m2"]),
            "length": float(dataset.attrs["reference_length_m"]),
        }
        self.slices = LruStore(4096)

    @classmethod
    def open(cls, path) -> "SweepLookup":
        """The lookup of the sweep store at ``path``."""
        import xarray as xr

        return cls(xr.open_zarr(path, consolidated=False))

    def _slice(self, index: tuple) -> CoefficientLookup:
        def make():
            point = dict(zip(self.axes, index))
            database = AeroDatabase(
                aoa_deg=np.asarray(self._ds["aoa"].values, dtype=float),
                aos_deg=np.asarray(self._ds["aos"].values, dtype=float),
                **{
                    name: np.asarray(self._ds[source].isel(point).values, dtype=float)
                    for name, source in (
                        ("CD", "CD"),
                        ("CL", "CL"),
                        ("CY", "CY"),
                        ("AreaProj", "area_projected"),
                        ("Cf_w", "Cf_w"),
                        ("Cf_f", "Cf_w"),  # (not read by the lookup)
                        ("Cm_B", "Cm_B"),
                        ("Cf_G", "Cf_G"),
                        ("Cm_G", "Cm_G"),
                    )
                },
                metadata={"reference": self._reference},
            )
            return CoefficientLookup(database)

        return self.slices.get(index, make)

    def _bracket(self, name: str, value: float) -> list:
        """``[(index, weight), ...]`` of the grid values around ``value`` on axis ``name``."""
        nodes = self.axes[name]
        low, high = float(nodes[0]), float(nodes[-1])
        if not low - TOLERANCE <= value <= high + TOLERANCE:
            raise ValueError(f"{name} {value!r} is outside the sweep's range [{low:g}, {high:g}]")
        if nodes.size == 1:
            return [(0, 1.0)]
        k = min(max(bisect.bisect_right(nodes.tolist(), value) - 1, 0), nodes.size - 2)
        t = (value - nodes[k]) / (nodes[k + 1] - nodes[k])
        t = min(max(t, 0.0), 1.0)
        return [(k, 1.0 - t), (k + 1, t)]

    def body_coefficients(self, aoa_deg: float, aos_deg: float, **values):
        """Interpolated Cf_G and Cm_G at an attitude [deg] and a value of every other axis.

        Raises
        ------
        ValueError
            An axis not given or unknown, or a value outside its range (named).
        """
        missing = sorted(set(self.axes) - set(values))
        unknown = sorted(set(values) - set(self.axes))
        if missing or unknown:
            raise ValueError(
                f"give a value of every axis of the sweep ({', '.join(self.axes) or 'none'}); "
                f"missing {missing}, unknown {unknown}"
            )
        brackets = [self._bracket(name, float(values[name])) for name in self.axes]
        cf, cm = np.zeros(3), np.zeros(3)
        for corner in itertools.product(*brackets):
            weight = float(np.prod([w for _, w in corner]))
            if weight == 0.0:
                continue
            f, m = self._slice(tuple(i for i, _ in corner)).body_coefficients(aoa_deg, aos_deg)
            cf += weight * f
            cm += weight * m
        return cf, cm

    def coefficients(self, aoa_deg: float, aos_deg: float, **values) -> InterpolatedCoefficients:
        """As :meth:`body_coefficients`, with CD, CL and CY from Cf_G by the exact rotation to
        wind axes at the query angles."""
        cf, cm = self.body_coefficients(aoa_deg, aos_deg, **values)
        a, b = np.radians(aoa_deg), np.radians(aos_deg)
        cf_w = frames.body_to_wind(a, b) @ (frames.L_GB @ cf)
        return InterpolatedCoefficients(
            float(aoa_deg),
            float(aos_deg),
            cf,
            cm,
            float(-cf_w[0]),
            float(-cf_w[2]),
            float(cf_w[1]),
            self._reference["area"],
            self._reference["length"],
        )
