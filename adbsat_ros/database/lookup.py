"""Coefficients at any attitude from an aerodynamic database, by interpolation, with a stated error.

Method: bilinear interpolation in (angle of attack, sideslip) of the mesh-frame (G) force and
moment coefficient vectors Cf_G and Cm_G; CD, CL and CY are then obtained from the interpolated
Cf_G by the exact rotation to wind axes at the query angles (``Cf_w = L_WG Cf_G``).

Why this choice:

* Body-frame vectors are the smooth quantities. Wind-axis coefficients (Cf_w, CL, CY) turn with
  the wind axes and are multivalued at the sideslip poles aos = +/-90 deg, where every aoa is
  the same flow direction u_G = (0, +/-1, 0); Cf_G(u_G) is one value there, so a bilinear
  interpolant of the grid is continuous across the pole (its aoa weights multiply equal values).
* The coefficients are only piecewise smooth in attitude: shading and faces turning to grazing
  put kinks in them (a lit area varies like |sin| of an angle), and ray-cast lit fractions are
  sampled. Higher-order schemes (bicubic, splines) overshoot at kinks and give no better bound
  there; bilinear interpolation is monotone within a cell (it never leaves the range of the
  four corner values), exact at the nodes, and first-order accurate even at kinks.
* Speed: a lookup is one bisection per axis and four weighted rows, a few microseconds, with no
  per-call scipy objects (``bench/bench_database.py`` measures it).

Geometry: when the aoa grid closes the circle (its span is 360 deg, or the gap left is at most its
largest step, e.g. -180:5:175) aoa is periodic and queries wrap around; otherwise a query is first
reduced modulo 360 deg into the grid's range and raises ValueError if it is still outside. The
sideslip must lie in [-90, 90] deg and inside the grid's range. At a pole (|aos| = 90 deg, in the
grid) the aoa does not matter.

Stated error (:func:`estimate_interpolation_error`, computed when the database is built and stored
in ``metadata["interpolation_error"]``): the grid is coarsened by 2 along each axis (every other
node, keeping the last), the coarse grid's bilinear interpolant is compared with the exact values
at every omitted node (edge and cell midpoints of the coarse cells), and the largest Euclidean
error of the vector is stated as the bound for the full grid, without scaling it down. In theory
halving the step divides the error by 4 where the coefficients are smooth and by 2 at kinks; but
near shadow edges that sweep fast (e.g. the body's shadow on the wings near the sideslip poles)
the convergence is not yet asymptotic, and the first-order factor 1/2 was measured to be exceeded
(true error 1.36 x the halved estimate on the example satellite, 5 deg grid). Unscaled, the
bound held with true/stated <= 0.7 in every case measured (example satellite and boxes, sentman
and newton, raycast and no shading, 5 to 30 deg grids, 150 to 1500 random attitudes each). The
bound is on |Cf_G(interpolated) - Cf_G(exact)| (likewise Cm_G), so it bounds every component and,
the rotation being orthogonal, the errors of CD, CL and CY. It is an a-posteriori estimate checked
by the tests against exact panel-method values at random off-grid attitudes, not a proof.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass

import numpy as np

from adbsat_ros.database.format import AeroDatabase, load_database

#: Factor from the coarse-grid error to the stated error of the full grid (module docstring).
ERROR_SCALING = 1.0
#: Angles within this many degrees of the grid's ends count as inside (rounding).
ANGLE_TOLERANCE_DEG = 1e-9
ERROR_METHOD = (
    "coarsen-by-2: bilinear interpolant of every other node vs exact values at the omitted nodes, "
    "max Euclidean vector error, not scaled down"
)


# ---------------------------------------------------------------------------------- bilinear core
def _locate(nodes: np.ndarray, x: np.ndarray):
    """Cell index i (nodes[i] <= x <= nodes[i+1]) and fraction t in [0, 1] for each x."""
    if nodes.size == 1:
        return np.zeros(np.shape(x), dtype=np.intp), np.zeros(np.shape(x))
    i = np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, nodes.size - 2)
    t = (x - nodes[i]) / (nodes[i + 1] - nodes[i])
    return i, t


def bilinear(a_nodes, b_nodes, values, qa, qb) -> np.ndarray:
    """Bilinear interpolation on a rectilinear grid (no wrap-around, no range checks).

    Parameters
    ----------
    a_nodes, b_nodes : ndarray, shape (na,), (nb,)
        Strictly increasing node coordinates (an axis with one node is constant along it).
    values : ndarray, shape (na, nb, k)
        Values at the nodes.
    qa, qb : array_like, shape (M,)
        Query coordinates inside the grid.

    Returns
    -------
    ndarray, shape (M, k)
    """
    qa, qb = np.broadcast_arrays(np.asarray(qa, float), np.asarray(qb, float))
    ia, ta = _locate(a_nodes, qa)
    ib, tb = _locate(b_nodes, qb)
    ia1 = ia + (1 if a_nodes.size > 1 else 0)
    ib1 = ib + (1 if b_nodes.size > 1 else 0)
    ta, tb = ta[..., None], tb[..., None]
    return (1.0 - ta) * ((1.0 - tb) * values[ia, ib] + tb * values[ia, ib1]) + ta * (
        (1.0 - tb) * values[ia1, ib] + tb * values[ia1, ib1]
    )


def _coarse_indices(n: int) -> np.ndarray:
    """Every other index of an axis of n nodes, always keeping the last."""
    return np.unique(np.append(np.arange(0, n, 2), n - 1))


def estimate_interpolation_error(db: AeroDatabase) -> dict:
    """Stated bilinear interpolation error of a database's grid (module docstring).

    Returns
    -------
    dict
        ``force_coefficient`` and ``moment_coefficient``: bounds on the Euclidean norm of the
        interpolation error of Cf_G and Cm_G (None if the grid has fewer than 3 nodes along
        every axis); ``method``, ``scaling``, ``points`` (omitted nodes compared),
        ``coarse_force_error`` and ``coarse_moment_error`` (the unscaled maxima),
        ``max_force_coefficient`` and ``max_moment_coefficient`` (largest |Cf_G|, |Cm_G| of the
        grid, for scale).
    """
    na, nb = db.shape
    out = {
        "method": ERROR_METHOD,
        "scaling": ERROR_SCALING,
        "max_force_coefficient": float(np.linalg.norm(db.Cf_G, axis=-1).max()),
        "max_moment_coefficient": float(np.linalg.norm(db.Cm_G, axis=-1).max()),
    }
    ca = _coarse_indices(na) if na >= 3 else np.arange(na)
    cb = _coarse_indices(nb) if nb >= 3 else np.arange(nb)
    omitted = np.ones((na, nb), dtype=bool)
    omitted[np.ix_(ca, cb)] = False
    if not omitted.any():
        out.update(
            force_coefficient=None,
            moment_coefficient=None,
            points=0,
            coarse_force_error=None,
            coarse_moment_error=None,
            method="unavailable: the grid needs at least 3 nodes along an axis to estimate it",
        )
        return out
    values = np.concatenate([db.Cf_G, db.Cm_G], axis=-1)
    ia, ib = np.nonzero(omitted)
    coarse = bilinear(
        db.aoa_deg[ca], db.aos_deg[cb], values[np.ix_(ca, cb)], db.aoa_deg[ia], db.aos_deg[ib]
    )
    diff = coarse - values[ia, ib]
    force = float(np.linalg.norm(diff[:, :3], axis=-1).max())
    moment = float(np.linalg.norm(diff[:, 3:], axis=-1).max())
    out.update(
        force_coefficient=ERROR_SCALING * force,
        moment_coefficient=ERROR_SCALING * moment,
        points=int(ia.size),
        coarse_force_error=force,
        coarse_moment_error=moment,
    )
    return out


# ---------------------------------------------------------------------------------- results
@dataclass(frozen=True, eq=False)
class InterpolatedCoefficients:
    """Coefficients at one attitude from :class:`CoefficientLookup`.

    Attributes
    ----------
    aoa_deg, aos_deg : float
        The attitude asked for [deg].
    Cf_G : ndarray, shape (3,)
        Force coefficient in the mesh frame G.
    Cm_G : ndarray, shape (3,)
        Moment coefficient in G about the database's moment point.
    CD, CL, CY : float
        Drag, lift and side-force coefficients (ADBSat's, from Cf_w = L_WG Cf_G).
    reference_area, reference_length : float
        A_ref [m^2] and L_ref [m] of the database.
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


# ---------------------------------------------------------------------------------- lookup
class CoefficientLookup:
    """Interpolating lookup of a database's Cf_G, Cm_G (and CD, CL, CY) at any attitude.

    Parameters
    ----------
    database : AeroDatabase

    Attributes
    ----------
    database : AeroDatabase
    periodic : bool
        True if the aoa grid closes the circle (queries wrap around).
    aoa_range, aos_range : tuple of float
        Covered angles [deg] (aoa_range spans 360 deg when periodic).
    error_bound : dict
        The stated interpolation error: ``force_coefficient`` and ``moment_coefficient``
        (bounds on the Euclidean norm of the error of Cf_G and Cm_G, hence of each component and
        of CD, CL, CY), ``method`` and the other fields of
        :func:`estimate_interpolation_error`.
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
    def load(cls, path) -> "CoefficientLookup":
        """A lookup of the database file ``path`` (:func:`adbsat_ros.database.build.load_database`)."""
        return cls(load_database(path))

    # ------------------------------------------------------------------------------ angles
    def _reduce(self, aoa_deg: float, aos_deg: float):
        """Query angles as grid coordinates; ValueError naming the angle and the range."""
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
                raise ValueError(
                    f"angle of attack {aoa_deg:g} deg is outside the database's range [{a0:g}, {a1:g}] deg"
                    + (
                        ""
                        if self.periodic
                        else " (the grid is not a full circle, so it does not wrap around)"
                    )
                )
        return min(max(aoa_deg, a0), a1), aos_deg

    @staticmethod
    def _cell(nodes: list, x: float):
        n = len(nodes)
        if n == 1:
            return 0, 0, 0.0
        i = min(max(bisect.bisect_right(nodes, x) - 1, 0), n - 2)
        return i, i + 1, (x - nodes[i]) / (nodes[i + 1] - nodes[i])

    # ------------------------------------------------------------------------------ public
    def body_coefficients(self, aoa_deg: float, aos_deg: float):
        """Interpolated Cf_G and Cm_G at one attitude (the fast path).

        Parameters
        ----------
        aoa_deg, aos_deg : float
            Angle of attack and sideslip [deg] (frames module conventions).

        Returns
        -------
        Cf_G, Cm_G : ndarray, shape (3,)
            Mesh-frame force and moment coefficients (moment about the database's moment point).

        Raises
        ------
        ValueError
            If an angle is outside the database's range (the message says which and the range).
        """
        row = self._interpolate(float(aoa_deg), float(aos_deg))
        return np.array(row[:3]), np.array(row[3:])

    def _interpolate(self, aoa_deg: float, aos_deg: float) -> list:
        """The six interpolated values (Cf_G, Cm_G) as Python floats (exact at the nodes)."""
        a, b = self._reduce(aoa_deg, aos_deg)
        i, i1, t = self._cell(self._aoa_list, a)
        j, j1, s = self._cell(self._aos_list, b)
        rows = self._rows
        v00, v01, v10, v11 = rows[i][j], rows[i][j1], rows[i1][j], rows[i1][j1]
        w00, w01, w10, w11 = (1.0 - t) * (1.0 - s), (1.0 - t) * s, t * (1.0 - s), t * s
        return [w00 * p + w01 * q + w10 * r + w11 * z for p, q, r, z in zip(v00, v01, v10, v11)]

    def body_coefficients_many(self, aoa_deg, aos_deg):
        """Vectorised :meth:`body_coefficients` for arrays of angles [deg] (broadcast together).

        Returns
        -------
        Cf_G, Cm_G : ndarray, shape (..., 3)
        """
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
        """Interpolated coefficients at an attitude given by angles [deg] or a flow direction.

        Parameters
        ----------
        aoa_deg, aos_deg : float, optional
            Angle of attack and sideslip [deg].
        flow_direction : array_like, shape (3,), optional
            Direction of the gas motion relative to the body in the mesh frame G (any length > 0),
            instead of the angles.

        Returns
        -------
        InterpolatedCoefficients
        """
        if flow_direction is not None:
            if aoa_deg is not None or aos_deg is not None:
                raise ValueError("give either aoa_deg/aos_deg or flow_direction, not both")
            u = np.asarray(flow_direction, dtype=float)
            if u.shape == (3,):
                x, y, z = u.tolist()
                norm = math.sqrt(x * x + y * y + z * z)
            else:
                norm = float("nan")
            if not math.isfinite(norm) or norm == 0.0:
                raise ValueError(
                    f"flow_direction must be a finite non-zero 3-vector, got {flow_direction!r}"
                )
            a_rad = math.atan2(z / norm, -x / norm)  # frames.angles_of_flow, on floats
            b_rad = math.asin(max(-1.0, min(1.0, y / norm)))
            aoa_deg, aos_deg = math.degrees(a_rad), math.degrees(b_rad)
        elif aoa_deg is None or aos_deg is None:
            raise ValueError("give aoa_deg and aos_deg, or flow_direction")
        aoa_deg, aos_deg = float(aoa_deg), float(aos_deg)
        row = self._interpolate(aoa_deg, aos_deg)
        fx, fy, fz = row[0], row[1], row[2]
        # Cf_w = L_WB L_GB Cf_G, written out (frames.body_to_wind; L_GB = diag(1, -1, -1))
        a, b = math.radians(aoa_deg), math.radians(aos_deg)
        ca, sa, cb, sb = math.cos(a), math.sin(a), math.cos(b), math.sin(b)
        return InterpolatedCoefficients(
            aoa_deg=aoa_deg,
            aos_deg=aos_deg,
            Cf_G=np.array(row[:3]),
            Cm_G=np.array(row[3:]),
            CD=-(ca * cb * fx - sb * fy - sa * cb * fz),
            CL=sa * fx + ca * fz,
            CY=-ca * sb * fx - cb * fy + sa * sb * fz,
            reference_area=self._area,
            reference_length=self._length,
        )

    __call__ = coefficients
