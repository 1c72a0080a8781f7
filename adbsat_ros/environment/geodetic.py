"""WGS-84 geodetic coordinates [rad, m] from and to ECEF (ITRF), and local East-North-Up axes."""

from __future__ import annotations

import math

import erfa
import numpy as np

from adbsat_ros.validation import all_finite, vectors3

#: ERFA's identifier of the WGS-84 reference ellipsoid (for ``erfa.gc2gd``/``erfa.gd2gc``).
WGS84 = 1


# ------------------------------------------------------------------------------------ geodetic
def geodetic_to_ecef(latitude, longitude, altitude) -> np.ndarray:
    """ECEF (ITRF) position [m] (..., 3) of WGS-84 latitude, east longitude [rad] and height [m].

    ValueError: a non-finite or out-of-range input (named).
    """
    latitude = np.asarray(latitude, dtype=float)
    longitude = np.asarray(longitude, dtype=float)
    altitude = np.asarray(altitude, dtype=float)
    for name, value in (("latitude", latitude), ("longitude", longitude), ("altitude", altitude)):
        if not all_finite(value):
            raise ValueError(f"{name} must be finite, got {value!r}")
    if np.any(np.abs(latitude) > math.pi / 2):
        raise ValueError(f"latitude must be in [-pi/2, pi/2] rad, got {latitude!r}")
    # (the raw ufunc: its status is non-zero only for inputs excluded above)
    position, _status = erfa.ufunc.gd2gc(WGS84, longitude, latitude, altitude)
    return position


def ecef_to_geodetic(position_ecef):
    """WGS-84 latitude, east longitude in (-pi, pi] [rad], height [m] of ECEF positions [m]."""
    position = vectors3(position_ecef, "position_ecef")
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
    """:func:`ecef_to_geodetic` of one finite position, shape (3,), as floats; beyond about
    1e150 m, where ERFA's squares overflow, the height is |r| (far above any range)."""
    with np.errstate(over="ignore", invalid="ignore"):
        longitude, latitude, altitude, status = erfa.ufunc.gc2gd(WGS84, position_ecef)
    if status != 0:  # pragma: no cover - defensive (only a bad ellipsoid identifier)
        raise ValueError(f"erfa.gc2gd failed (status {status}) for position {position_ecef!r}")
    if not math.isfinite(altitude):
        return float(latitude), float(longitude), math.hypot(*position_ecef.tolist())
    return float(latitude), float(longitude), float(altitude)
