"""WGS-84 geodetic coordinates (latitude, east longitude [rad], height [m]) from and to ECEF
(ITRF) positions, and the local East-North-Up axes."""

from __future__ import annotations

import math

import erfa
import numpy as np

from adbsat_ros.validation import all_finite, vectors3

#: ERFA's identifier of the WGS-84 reference ellipsoid (for ``erfa.gc2gd``/``erfa.gd2gc``).
WGS84 = 1


# WGS-84 ellipsoid (as erfa.eform(WGS84)) and the constants of Fukushima's geodetic solution.
_WGS84_A = 6378137.0
_WGS84_F = 1.0 / 298.257223563
_E2 = (2.0 - _WGS84_F) * _WGS84_F
_E4T = _E2 * _E2 * 1.5
_EC2 = 1.0 - _E2
_EC = math.sqrt(_EC2)
_POLAR_RADIUS = _WGS84_A * _EC
_POLAR_AXIS_EPS2 = _WGS84_A * _WGS84_A * 1e-32


# ------------------------------------------------------------------------------------ geodetic
def geodetic_to_ecef(latitude, longitude, altitude) -> np.ndarray:
    """ECEF (ITRF) position [m], shape (..., 3), of WGS-84 latitude [rad] in [-pi/2, pi/2],
    east longitude [rad] and height [m]; ValueError naming a non-finite or out-of-range input."""
    latitude = np.asarray(latitude, dtype=float)
    longitude = np.asarray(longitude, dtype=float)
    altitude = np.asarray(altitude, dtype=float)
    for name, value in (("latitude", latitude), ("longitude", longitude), ("altitude", altitude)):
        if not all_finite(value):
            raise ValueError(f"{name} must be finite, got {value!r}")
    if latitude.ndim == 0:
        if abs(float(latitude)) > math.pi / 2:
            raise ValueError(f"latitude must be in [-pi/2, pi/2] rad, got {latitude!r}")
    elif np.any(np.abs(latitude) > math.pi / 2):
        raise ValueError(f"latitude must be in [-pi/2, pi/2] rad, got {latitude!r}")
    # Raw ufunc (skips pyerfa's status-to-warning wrapper); status is non-zero only for a bad
    # ellipsoid identifier or |latitude| > pi/2, both excluded above.
    position, _status = erfa.ufunc.gd2gc(WGS84, longitude, latitude, altitude)
    return position


def ecef_to_geodetic(position_ecef):
    """WGS-84 latitude, east longitude in (-pi, pi] [rad] and height [m] of ECEF positions [m],
    (3,) or (N, 3); ValueError for a non-finite or mis-shaped position."""
    position = vectors3(position_ecef, "position_ecef")
    # The raw ufunc skips pyerfa's status-to-warning wrapper; status < 0 is only possible
    # for a bad ellipsoid identifier, which WGS84 is not.
    longitude, latitude, altitude, status = erfa.ufunc.gc2gd(WGS84, position)
    if position.ndim == 1:
        if status != 0:  # pragma: no cover - defensive
            raise ValueError(f"erfa.gc2gd failed (status {status}) for position {position_ecef!r}")
        return float(latitude), float(longitude), float(altitude)
    if np.any(status != 0):  # pragma: no cover - defensive
        raise ValueError(f"erfa.gc2gd failed for some of the positions {position_ecef!r}")
    return latitude, longitude, altitude


def enu_to_ecef_matrix(latitude: float, longitude: float) -> np.ndarray:
    """M with ``v_ecef = M @ v_enu`` at geodetic ``latitude``, ``longitude`` [rad]."""
    sin_lat, cos_lat = math.sin(latitude), math.cos(latitude)
    sin_lon, cos_lon = math.sin(longitude), math.cos(longitude)
    return np.array(
        [
            [-sin_lon, -sin_lat * cos_lon, cos_lat * cos_lon],
            [cos_lon, -sin_lat * sin_lon, cos_lat * sin_lon],
            [0.0, cos_lat, sin_lat],
        ]
    )


def geodetic_of(position_ecef: np.ndarray):
    """:func:`ecef_to_geodetic` of one position already checked, shape (3,), as floats."""
    longitude, latitude, altitude, status = erfa.ufunc.gc2gd(WGS84, position_ecef)
    if status != 0:  # pragma: no cover - defensive (only a bad ellipsoid identifier)
        raise ValueError(f"erfa.gc2gd failed (status {status}) for position {position_ecef!r}")
    return float(latitude), float(longitude), float(altitude)


def geodetic_of_floats(x: float, y: float, z: float) -> tuple:
    """``(latitude [rad], longitude [rad], altitude [m])`` of ECEF (x, y, z) [m].

    Fukushima (2006) with one Halley step, ERFA's ``gc2gde`` operations in its order, so equal
    to ``erfa.gc2gd`` bit for bit.
    """
    p2 = x * x + y * y
    longitude = math.atan2(y, x) if p2 > 0.0 else 0.0
    absz = abs(z)
    if p2 > _POLAR_AXIS_EPS2:
        p = math.sqrt(p2)
        s0 = absz / _WGS84_A
        pn = p / _WGS84_A
        zc = _EC * s0
        c0 = _EC * pn
        c02 = c0 * c0
        c03 = c02 * c0
        s02 = s0 * s0
        s03 = s02 * s0
        a02 = c02 + s02
        a0 = math.sqrt(a02)
        a03 = a02 * a0
        d0 = zc * a03 + _E2 * s03
        f0 = pn * a03 - _E2 * c03
        b0 = _E4T * s02 * c02 * pn * (a0 - _EC)  # Halley correction
        s1 = d0 * f0 - b0 * s0
        cc = _EC * (f0 * f0 - b0 * c0)
        latitude = math.atan(s1 / cc)
        s12 = s1 * s1
        cc2 = cc * cc
        altitude = (p * cc + absz * s1 - _WGS84_A * math.sqrt(_EC2 * s12 + cc2)) / math.sqrt(
            s12 + cc2
        )
    else:  # on the polar axis
        latitude = math.pi / 2.0
        altitude = absz - _POLAR_RADIUS
    if z < 0:
        latitude = -latitude
    return latitude, longitude, altitude


def enu_to_ecef(latitude: float, longitude: float, east: float, north: float, up: float) -> tuple:
    """``enu_to_ecef_matrix(latitude, longitude) @ (east, north, up)`` as three floats."""
    sin_lat, cos_lat = math.sin(latitude), math.cos(latitude)
    sin_lon, cos_lon = math.sin(longitude), math.cos(longitude)
    return (
        -sin_lon * east + -sin_lat * cos_lon * north + cos_lat * cos_lon * up,
        cos_lon * east + -sin_lat * sin_lon * north + cos_lat * sin_lon * up,
        cos_lat * north + sin_lat * up,
    )
