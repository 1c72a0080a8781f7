"""Coefficients at any attitude from a database: bilinear in (aoa, aos) of Cf_G and Cm_G, CD, CL,
CY by the exact rotation to wind axes. A closed aoa grid wraps around; otherwise a query is
reduced modulo 360 deg into range, else ValueError. docs/physics.md, section 9.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from adbsat_ros.database.format import AeroDatabase, load_database
from adbsat_ros.database.interpolation import bilinear, bilinear_one
from adbsat_ros.database.sweep_reader import is_sweep_store, open_sweep, sweep_database
from adbsat_ros.geometry import frames

#: Angles within this many degrees of the grid's ends count as inside (rounding).
ANGLE_TOLERANCE_DEG = 1e-9


# ---------------------------------------------------------------------------------- results
@dataclass(frozen=True, eq=False)
class InterpolatedCoefficients:
    """Coefficients at one attitude [deg]: Cf_G, Cm_G (mesh frame G, about the database's point),
    ADBSat's CD, CL, CY; reference_area [m^2], reference_length [m].
    """

    aoa_deg: float
    aos_deg: float
    Cf_G: np.ndarray
    Cm_G: np.ndarray
    CD: float
    CL: float
    CY: float
    reference_area: float
    reference_length: float

    def force(self, dynamic_pressure: float) -> np.ndarray:
        """Force [N] in G for dynamic pressure q = rho V^2 / 2 [Pa]."""
        return dynamic_pressure * self.reference_area * self.Cf_G

    def torque(self, dynamic_pressure: float) -> np.ndarray:
        """Torque [N m] in G about the moment point for dynamic pressure q [Pa]."""
        return dynamic_pressure * self.reference_area * self.reference_length * self.Cm_G

    @classmethod
    def of(cls, aoa_deg: float, aos_deg: float, Cf_G, Cm_G, area: float, length: float):
        """The coefficients of body-frame ``Cf_G``, ``Cm_G``; CD, CL, CY by the exact rotation."""
        Cf_w = frames.mesh_to_wind(math.radians(aoa_deg), math.radians(aos_deg)) @ Cf_G
        CD, CY, CL = -float(Cf_w[0]), float(Cf_w[1]), -float(Cf_w[2])
        return cls(aoa_deg, aos_deg, Cf_G, Cm_G, CD, CL, CY, area, length)


# ---------------------------------------------------------------------------------- lookup
class CoefficientLookup:
    """Interpolating lookup of an :class:`AeroDatabase`'s coefficients at any attitude.

    ``aoa_range``, ``aos_range`` [deg]; ``error_bound``: the stated error (:mod:`.interpolation`).
    """

    def __init__(self, database: AeroDatabase):
        self.database = database
        aoa = np.asarray(database.aoa_deg, dtype=float)
        aos = np.asarray(database.aos_deg, dtype=float)
        values = np.concatenate([database.Cf_G, database.Cm_G], axis=-1)
        span = aoa[-1] - aoa[0]
        tol = ANGLE_TOLERANCE_DEG
        self.periodic = False
        if aoa.size >= 2 and abs(span - 360.0) <= tol:
            self.periodic = True
        elif aoa.size >= 2 and span < 360.0 and 360.0 - span <= np.diff(aoa).max() + tol:
            # close the circle: the node after the last is the first one, 360 deg on
            aoa = np.append(aoa, aoa[0] + 360.0)
            values = np.concatenate([values, values[:1]], axis=0)
            self.periodic = True
        self._aoa = aoa
        self._aos = aos
        self._aoa_list = aoa.tolist()
        self._aos_list = aos.tolist()
        self._values = np.ascontiguousarray(values)
        self._rows = self._values.tolist()  # nested lists: the scalar path works on Python floats
        self.aoa_range = (float(aoa[0]), float(aoa[-1]))
        self.aos_range = (float(aos[0]), float(aos[-1]))
        self._area = database.reference_area
        self._length = database.reference_length
        self.error_bound = dict(database.metadata.get("interpolation_error") or {})

    @classmethod
    def load(cls, path, **values) -> "CoefficientLookup":
        """Lookup of the file ``path`` or a sweep store at other axes' values (``speed=7600.0``).

        DatabaseError: an unreadable file. ValueError: an incomplete store or a bad axis value.
        """
        if is_sweep_store(path):
            return cls(sweep_database(open_sweep(path), **values))
        if values:
            raise ValueError(
                f"{path}: a database file has no axes besides aoa and aos; got {sorted(values)}"
            )
        return cls(load_database(path))

    # ------------------------------------------------------------------------------ angles
    def _reduce(self, aoa_deg: float, aos_deg: float):
        if not (math.isfinite(aoa_deg) and math.isfinite(aos_deg)):
            raise ValueError(f"angles must be finite, got aoa {aoa_deg!r}, aos {aos_deg!r} deg")
        tol = ANGLE_TOLERANCE_DEG
        b0, b1 = self.aos_range
        if not -90.0 - tol <= aos_deg <= 90.0 + tol:
            raise ValueError(f"sideslip {aos_deg:g} deg is outside [-90, 90] deg")
        if not b0 - tol <= aos_deg <= b1 + tol:
            raise ValueError(
                f"sideslip {aos_deg:g} deg is outside the database's range [{b0:g}, {b1:g}] deg"
            )
        aos_deg = min(max(aos_deg, b0), b1)
        a0, a1 = self.aoa_range
        if not a0 - tol <= aoa_deg <= a1 + tol:
            wrapped = a0 + (aoa_deg - a0) % 360.0
            if wrapped <= a1 + tol:
                aoa_deg = wrapped
            elif abs(aos_deg) >= 90.0:  # a pole: every aoa is the same flow direction
                aoa_deg = a0
            else:
                why = (
                    ""
                    if self.periodic
                    else " (the grid is not a full circle, so it does not wrap around)"
                )
                raise ValueError(
                    f"angle of attack {aoa_deg:g} deg is outside the database's range "
                    f"[{a0:g}, {a1:g}] deg{why}"
                )
        return min(max(aoa_deg, a0), a1), aos_deg

    # ------------------------------------------------------------------------------ public
    def body_coefficients(self, aoa_deg: float, aos_deg: float):
        """Cf_G and Cm_G (3,) at one attitude [deg]; ValueError naming an angle out of range."""
        row = self._interpolate(float(aoa_deg), float(aos_deg))
        return np.array(row[:3]), np.array(row[3:])

    def _interpolate(self, aoa_deg: float, aos_deg: float) -> list:
        a, b = self._reduce(aoa_deg, aos_deg)
        return bilinear_one(self._aoa_list, self._aos_list, self._rows, a, b)

    def body_coefficients_many(self, aoa_deg, aos_deg):
        """:meth:`body_coefficients` for arrays of angles [deg] (broadcast): Cf_G, Cm_G (..., 3)."""
        aoa, aos = np.broadcast_arrays(np.asarray(aoa_deg, float), np.asarray(aos_deg, float))
        flat = [
            self._reduce(a, b) for a, b in zip(aoa.reshape(-1).tolist(), aos.reshape(-1).tolist())
        ]
        qa = np.array([f[0] for f in flat])
        qb = np.array([f[1] for f in flat])
        row = bilinear(self._aoa, self._aos, self._values, qa, qb).reshape(aoa.shape + (6,))
        return row[..., :3], row[..., 3:]

    def coefficients(
        self, aoa_deg=None, aos_deg=None, *, flow_direction=None
    ) -> InterpolatedCoefficients:
        """Coefficients at angles [deg] or a ``flow_direction`` (gas vs body, frame G)."""
        if flow_direction is not None:
            if aoa_deg is not None or aos_deg is not None:
                raise ValueError("give either aoa_deg/aos_deg or flow_direction, not both")
            u = frames.direction_components(flow_direction, "flow_direction")
            aoa_deg, aos_deg = (math.degrees(x) for x in frames.angles_of_flow(u))
        elif aoa_deg is None or aos_deg is None:
            raise ValueError("give aoa_deg and aos_deg, or flow_direction")
        aoa_deg, aos_deg = float(aoa_deg), float(aos_deg)
        row = self._interpolate(aoa_deg, aos_deg)
        cf, cm = np.array(row[:3]), np.array(row[3:])
        return InterpolatedCoefficients.of(aoa_deg, aos_deg, cf, cm, self._area, self._length)

    __call__ = coefficients
