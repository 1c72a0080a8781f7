"""Coefficients anywhere inside a sweep: bilinear in attitude, linear along the other axes;
a query outside an axis's range is refused with the axis and its range.
"""

from __future__ import annotations

import numpy as np

from adbsat_ros.database.lookup import CoefficientLookup, InterpolatedCoefficients
from adbsat_ros.database.sweep_reader import corners, open_sweep, other_axes, slice_database
from adbsat_ros.lru import LruStore


class SweepLookup:
    """Interpolated coefficients of a complete sweep store's ``dataset``; ``axes``: the others."""

    def __init__(self, dataset):
        if "chunk_done" in dataset and not bool(dataset["chunk_done"].values.all()):
            raise ValueError("the sweep is not complete: run it again to compute the rest")
        self._ds = dataset
        self.axes = other_axes(dataset)
        self._area = float(dataset.attrs["reference_area_m2"])
        self._length = float(dataset.attrs["reference_length_m"])
        self.slices = LruStore(4096)

    @classmethod
    def open(cls, path) -> "SweepLookup":
        """The lookup of the sweep store at ``path``."""
        return cls(open_sweep(path))

    def _slice(self, index: tuple) -> CoefficientLookup:
        return self.slices.get(
            index, lambda: CoefficientLookup(slice_database(self._ds, dict(zip(self.axes, index))))
        )

    def body_coefficients(self, aoa_deg: float, aos_deg: float, **values):
        """Cf_G and Cm_G at an attitude [deg] and a value of every other axis.

        ValueError: an axis not given or unknown, or a value outside its range.
        """
        cf, cm = np.zeros(3), np.zeros(3)
        for corner, weight in corners(self.axes, values):
            f, m = self._slice(corner).body_coefficients(aoa_deg, aos_deg)
            cf += weight * f
            cm += weight * m
        return cf, cm

    def coefficients(self, aoa_deg: float, aos_deg: float, **values) -> InterpolatedCoefficients:
        """As :meth:`body_coefficients`, with CD, CL, CY by the rotation to wind axes."""
        cf, cm = self.body_coefficients(aoa_deg, aos_deg, **values)
        a, b = float(aoa_deg), float(aos_deg)
        return InterpolatedCoefficients.of(a, b, cf, cm, self._area, self._length)
