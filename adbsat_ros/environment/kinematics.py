"""An orbital state's frames, geodetic coordinates, relative velocity at one instant; m, m/s, rad.
:func:`state_kinematics` (a knot's fast path) does it in plain floats, ERFA's operations in their
order; :func:`state_kinematics_reference` with erfa (``era00``, ``c2tcio``, ``gc2gd``) and numpy;
``test/environment/test_kinematics.py`` asserts they agree (docs/architecture.md, fast paths)."""

from __future__ import annotations

import math

import numpy as np

from adbsat_ros.environment.earth_frames import (
    SECONDS_PER_DAY,
    celestial_to_intermediate,
    rotation_terms,
)
from adbsat_ros.environment.geodetic import enu_to_ecef_matrix, geodetic_of
from adbsat_ros.geometry.frames import cross

_TWO_PI = 2.0 * math.pi
#: Angular velocity of the ECEF frame, ECEF axes, zero polar motion [rad/s] (as earth_frames).
_ROTATION_AXIS = (0.0, 0.0, 2.0 * math.pi * 1.00273781191135448 / 86400.0)

# WGS-84 (as erfa.eform(1)) and the constants of Fukushima's geodetic solution (ERFA's gc2gde).
_WGS84_A = 6378137.0
_WGS84_F = 1.0 / 298.257223563
_E2 = (2.0 - _WGS84_F) * _WGS84_F
_E4T = _E2 * _E2 * 1.5
_EC2 = 1.0 - _E2
_EC = math.sqrt(_EC2)
_POLAR_RADIUS = _WGS84_A * _EC
_POLAR_AXIS_EPS2 = _WGS84_A * _WGS84_A * 1e-32


def earth_rotation_angle(ut1_day: float, ut1_fraction: float) -> float:
    """ERA(UT1) [rad] in [0, 2 pi) of a two-part UT1 Julian date: ``erfa.era00``'s operations."""
    small, large = (ut1_day, ut1_fraction) if ut1_day < ut1_fraction else (ut1_fraction, ut1_day)
    days = small + (large - 2451545.0)
    fraction = math.fmod(small, 1.0) + math.fmod(large, 1.0)
    angle = math.fmod(_TWO_PI * (fraction + 0.7790572732640 + 0.00273781191135448 * days), _TWO_PI)
    return angle + _TWO_PI if angle < 0.0 else angle


def rotation_floats(
    jd1, day_fraction, tt_minus_utc, ut1_minus_utc, xp, yp, precession_nutation, step
) -> tuple:
    """:func:`~.earth_frames.rotation_terms` as ``(R, ERA, omega)``: R 9 floats, row-major."""
    if xp != 0.0 or yp != 0.0:  # (polar motion: erfa's)
        matrix, era, axis = rotation_terms(
            jd1, day_fraction, tt_minus_utc, ut1_minus_utc, xp, yp, precession_nutation, step
        )
        return tuple(matrix.ravel().tolist()), era, tuple(axis.tolist())
    q = celestial_to_intermediate(jd1, day_fraction + tt_minus_utc, precession_nutation, step)
    era = earth_rotation_angle(jd1, day_fraction + ut1_minus_utc / SECONDS_PER_DAY)
    c, s = math.cos(era), math.sin(era)
    (q00, q01, q02), (q10, q11, q12), (q20, q21, q22) = q.tolist()
    # R3(ERA) @ Q with R3 = [[c, s, 0], [-s, c, 0], [0, 0, 1]], as erfa.rz
    matrix = (
        c * q00 + s * q10,
        c * q01 + s * q11,
        c * q02 + s * q12,
        c * q10 - s * q00,
        c * q11 - s * q01,
        c * q12 - s * q02,
        q20,
        q21,
        q22,
    )
    return matrix, era, _ROTATION_AXIS


def geodetic_of_floats(x: float, y: float, z: float) -> tuple:
    """``(latitude [rad], longitude [rad], altitude [m])`` of ECEF (x, y, z) [m]: Fukushima (2006)
    with one Halley step, ``erfa.gc2gd``'s operations in their order."""
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


def state_kinematics(matrix, omega, frame, position, velocity, wind, wind_frame, earth_rotation):
    """``(vectors, latitude, longitude, altitude, |v_rel|)`` of one state, in floats.
    matrix: R (``r_ecef = R r_eci``), 9 floats row-major; omega: ECEF's angular velocity [rad/s];
    frame ``"eci"``/``"ecef"`` of ``position``, ``velocity``; wind: None or in ``wind_frame``
    (``"enu"``/``"ecef"``); earth_rotation: the air co-rotating. ``vectors``: 3-tuples position,
    velocity, relative velocity, each ECI then ECEF."""
    m0, m1, m2, m3, m4, m5, m6, m7, m8 = matrix
    w0, w1, w2 = omega
    if frame == "eci":
        # r_ecef = R r_eci; v_ecef = R v_eci - omega x r_ecef
        position_eci = x, y, z = position
        velocity_eci = vx, vy, vz = velocity
        position_ecef = px, py, pz = _rotate(matrix, x, y, z)
        velocity_ecef = (
            (m0 * vx + m1 * vy + m2 * vz) - (w1 * pz - w2 * py),
            (m3 * vx + m4 * vy + m5 * vz) - (w2 * px - w0 * pz),
            (m6 * vx + m7 * vy + m8 * vz) - (w0 * py - w1 * px),
        )
    else:
        # r_eci = R^T r_ecef; v_eci = R^T (v_ecef + omega x r_ecef)
        position_ecef = px, py, pz = position
        velocity_ecef = vx, vy, vz = velocity
        position_eci = _rotate_back(matrix, px, py, pz)
        velocity_eci = _rotate_back(
            matrix, vx + (w1 * pz - w2 * py), vy + (w2 * px - w0 * pz), vz + (w0 * py - w1 * px)
        )
    latitude, longitude, altitude = geodetic_of_floats(px, py, pz)
    if wind is not None and wind_frame == "enu":
        east, north, up = wind
        sin_lat, cos_lat = math.sin(latitude), math.cos(latitude)
        sin_lon, cos_lon = math.sin(longitude), math.cos(longitude)
        wind = (
            -sin_lon * east + -sin_lat * cos_lon * north + cos_lat * cos_lon * up,
            cos_lon * east + -sin_lat * sin_lon * north + cos_lat * sin_lon * up,
            cos_lat * north + sin_lat * up,
        )
    if earth_rotation:
        # v_rel,ecef = v_ecef - wind; v_rel,eci = R^T v_rel,ecef
        relative_ecef = velocity_ecef if wind is None else _minus(velocity_ecef, wind)
        relative_eci = _rotate_back(matrix, *relative_ecef)
    else:
        relative_eci = (
            velocity_eci if wind is None else _minus(velocity_eci, _rotate_back(matrix, *wind))
        )
        relative_ecef = _rotate(matrix, *relative_eci)
    vectors = (position_eci, position_ecef, velocity_eci, velocity_ecef)
    vectors += (relative_eci, relative_ecef)
    x, y, z = relative_ecef
    return vectors, latitude, longitude, altitude, math.sqrt(x * x + y * y + z * z)


def state_kinematics_reference(
    rotation, omega, frame, position, velocity, wind, wind_frame, earth_rotation
):
    """:func:`state_kinematics` with erfa and numpy: R (3, 3), omega (3,), ``vectors`` (6, 3)."""
    position, velocity = np.array(position, dtype=float), np.array(velocity, dtype=float)
    if frame == "eci":
        position_eci, velocity_eci = position, velocity
        position_ecef = rotation @ position_eci
        velocity_ecef = rotation @ velocity_eci - cross(omega, position_ecef)
    else:
        position_ecef, velocity_ecef = position, velocity
        position_eci = position_ecef @ rotation
        velocity_eci = (velocity_ecef + cross(omega, position_ecef)) @ rotation
    latitude, longitude, altitude = geodetic_of(position_ecef)
    if wind is not None:
        wind = np.asarray(wind, dtype=float)
        if wind_frame == "enu":
            wind = enu_to_ecef_matrix(latitude, longitude) @ wind
    if earth_rotation:
        relative_ecef = velocity_ecef if wind is None else velocity_ecef - wind
        relative_eci = relative_ecef @ rotation
    else:
        relative_eci = velocity_eci if wind is None else velocity_eci - wind @ rotation
        relative_ecef = rotation @ relative_eci
    vectors = np.array(
        (position_eci, position_ecef, velocity_eci, velocity_ecef, relative_eci, relative_ecef)
    )
    return vectors, latitude, longitude, altitude, float(np.linalg.norm(relative_ecef))


def _rotate(m, x, y, z) -> tuple:
    """``M @ (x, y, z)`` of M given as 9 floats, row-major."""
    return (
        m[0] * x + m[1] * y + m[2] * z,
        m[3] * x + m[4] * y + m[5] * z,
        m[6] * x + m[7] * y + m[8] * z,
    )


def _rotate_back(m, x, y, z) -> tuple:
    """``M.T @ (x, y, z)`` (the inverse rotation) of M given as 9 floats, row-major."""
    return (
        m[0] * x + m[3] * y + m[6] * z,
        m[1] * x + m[4] * y + m[7] * z,
        m[2] * x + m[5] * y + m[8] * z,
    )


def _minus(a, b) -> tuple:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])
