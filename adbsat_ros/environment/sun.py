"""The Sun for solar radiation pressure: position (ERFA ``epv00``, GCRS = ECI, 1900-2100),
pressure P = S / c (1 au / d)^2 [Pa], and Earth's conical shadow (Montenbruck & Gill 2000,
3.4.2). docs/physics.md, section 7.1.
"""

from __future__ import annotations

import datetime as dt
import math
from dataclasses import dataclass

import erfa
import numpy as np

from adbsat_ros.environment.time_scales import julian_dates, utc_datetime

#: Total solar irradiance at 1 au [W/m^2]: 1360.8 +- 0.5 at solar minimum (Kopp & Lean 2011,
#: Geophys. Res. Lett. 38, L01706); it varies by about 0.1 % over a solar cycle.
SOLAR_IRRADIANCE_1AU = 1361.0
#: Speed of light [m/s] (exact).
SPEED_OF_LIGHT = 299_792_458.0
#: Solar radiation pressure at 1 au [Pa] (S / c, about 4.54e-6).
SOLAR_PRESSURE_1AU = SOLAR_IRRADIANCE_1AU / SPEED_OF_LIGHT
#: Astronomical unit [m] (IAU 2012, exact; ERFA's DAU).
ASTRONOMICAL_UNIT = float(erfa.DAU)
#: Nominal solar radius [m] (IAU 2015 Resolution B3).
SUN_RADIUS = 6.957e8
#: Radius of the Earth's shadow-casting sphere [m]: the WGS-84 equatorial radius (a spherical
#: Earth; the flattening moves the shadow's edge by at most about 20 km, a few seconds of orbit).
EARTH_SHADOW_RADIUS = 6_378_137.0


@dataclass(frozen=True)
class SunState:
    """The Sun from a satellite: unit vector (GCRS), distance [m], disc visible, pressure [Pa]."""

    direction_eci: np.ndarray
    distance: float
    lit_fraction: float
    pressure: float


def sun_position_eci(time) -> np.ndarray:
    """Geocentric position of the Sun [m], GCRS, at a UTC datetime ``time``."""
    _, (tt1, tt2), _ = julian_dates(time)
    heliocentric, _ = erfa.epv00(tt1, tt2)
    return -np.asarray(heliocentric["p"], dtype=float) * ASTRONOMICAL_UNIT


def solar_pressure(sun_distance) -> float:
    """P_1au (1 au / d)^2 [Pa] at ``sun_distance`` d [m]; ValueError unless finite and > 0."""
    d = float(sun_distance)
    if not (math.isfinite(d) and d > 0.0):
        raise ValueError(f"sun_distance must be a finite positive number of metres, got {d!r}")
    return SOLAR_PRESSURE_1AU * (ASTRONOMICAL_UNIT / d) ** 2


def lit_fraction(position_eci, sun_position_eci):
    """Fraction in [0, 1] of the solar disc visible from ``position_eci`` past a spherical Earth.

    Montenbruck & Gill (2000), eqs. 3.85-3.87. Positions [m], GCRS, (3,) or (N, 3).
    ValueError: non-finite, or a position inside the Earth.
    """
    r = np.asarray(position_eci, dtype=float)
    s = np.asarray(sun_position_eci, dtype=float)
    if r.shape[-1:] != (3,) or r.ndim > 2 or not np.all(np.isfinite(r)):
        raise ValueError("position_eci must be finite, shape (3,) or (N, 3), in metres")
    if s.shape != (3,) or not np.all(np.isfinite(s)) or not np.any(s):
        raise ValueError("sun_position_eci must be a finite non-zero 3-vector in metres")
    single = r.ndim == 1
    r = np.atleast_2d(r)
    radius = np.linalg.norm(r, axis=1)
    if np.any(radius < EARTH_SHADOW_RADIUS):
        raise ValueError(
            f"position_eci must be outside the Earth (|r| >= {EARTH_SHADOW_RADIUS:.0f} m), got "
            f"|r| = {radius.min():.0f} m"
        )
    to_sun = s - r
    distance = np.linalg.norm(to_sun, axis=1)
    a = np.arcsin(np.minimum(SUN_RADIUS / distance, 1.0))
    b = np.arcsin(np.minimum(EARTH_SHADOW_RADIUS / radius, 1.0))
    cos_c = -np.einsum("ij,ij->i", r, to_sun) / (radius * distance)
    c = np.arccos(np.clip(cos_c, -1.0, 1.0))
    fraction = np.ones_like(c)
    fraction[c <= b - a] = 0.0
    annular = (c < a - b) & (c > b - a)
    fraction[annular] = 1.0 - (b[annular] / a[annular]) ** 2
    partial = (c < a + b) & (c > np.abs(a - b))
    if np.any(partial):
        ap, bp, cp = a[partial], b[partial], c[partial]
        x = (cp * cp + ap * ap - bp * bp) / (2.0 * cp)
        y = np.sqrt(np.maximum(ap * ap - x * x, 0.0))
        overlap = (
            ap * ap * np.arccos(np.clip(x / ap, -1.0, 1.0))
            + bp * bp * np.arccos(np.clip((cp - x) / bp, -1.0, 1.0))
            - cp * y
        )
        fraction[partial] = 1.0 - overlap / (math.pi * ap * ap)
    fraction = np.clip(fraction, 0.0, 1.0)
    return float(fraction[0]) if single else fraction


def _visible_fraction(rx, ry, rz, sx, sy, sz) -> float:
    """:func:`lit_fraction` of one checked position, in floats."""
    radius = math.hypot(rx, ry, rz)
    dx, dy, dz = sx - rx, sy - ry, sz - rz
    distance = math.hypot(dx, dy, dz)
    a = math.asin(min(SUN_RADIUS / distance, 1.0))
    b = math.asin(min(EARTH_SHADOW_RADIUS / radius, 1.0))
    cos_c = -(rx * dx + ry * dy + rz * dz) / (radius * distance)
    c = math.acos(min(max(cos_c, -1.0), 1.0))
    if c >= a + b:
        return 1.0
    if c <= b - a:
        return 0.0
    if c <= a - b:
        return 1.0 - (b / a) ** 2
    x = (c * c + a * a - b * b) / (2.0 * c)
    y = math.sqrt(max(a * a - x * x, 0.0))
    overlap = (
        a * a * math.acos(min(max(x / a, -1.0), 1.0))
        + b * b * math.acos(min(max((c - x) / b, -1.0), 1.0))
        - c * y
    )
    return min(max(1.0 - overlap / (math.pi * a * a), 0.0), 1.0)


def sun_state(time, position_eci, sun_position=None) -> SunState:
    """The Sun from ``position_eci`` [m] (GCRS) at UTC ``time``; ValueError as lit_fraction."""
    sun = sun_position_eci(time) if sun_position is None else np.asarray(sun_position, float)
    r = np.asarray(position_eci, dtype=float)
    rx, ry, rz = r.tolist()
    radius = math.hypot(rx, ry, rz)
    if r.shape != (3,) or not math.isfinite(radius):
        raise ValueError("position_eci must be finite, shape (3,), in metres")
    if radius < EARTH_SHADOW_RADIUS:
        raise ValueError(
            f"position_eci must be outside the Earth (|r| >= {EARTH_SHADOW_RADIUS:.0f} m), got "
            f"|r| = {radius:.0f} m"
        )
    to_sun = sun - r
    distance = math.sqrt(float(to_sun @ to_sun))
    fraction = _visible_fraction(rx, ry, rz, *sun.tolist())
    return SunState(to_sun / distance, distance, fraction, solar_pressure(distance))


class SunTrack:
    """The cache of the Sun's position: exact on knots every ``step`` s in (0, 3600], linear between
    (error |p''| h^2 / 8); keyed by the knot index, counting ``hits`` and ``misses``.
    """

    _ORIGIN = dt.datetime(2000, 1, 1)

    def __init__(self, step: float = 60.0):
        step = float(step)
        if not (0.0 < step <= 3600.0):
            raise ValueError(f"step must be in (0, 3600] s, got {step!r}")
        self.step = step
        self._knots: dict = {}  # index -> position, the latest two
        self.hits = self.misses = 0

    def position(self, time) -> np.ndarray:
        """The Sun's geocentric position [m], GCRS, at UTC ``time`` (datetime)."""
        utc = utc_datetime(time)
        t = (utc - self._ORIGIN).total_seconds() / self.step
        index = math.floor(t)
        ends = []
        for k in (index, index + 1):
            p = self._knots.get(k)
            if p is None:
                self.misses += 1
                p = sun_position_eci(self._ORIGIN + dt.timedelta(seconds=k * self.step))
            ends.append(p)
        if len(self._knots) != 2 or index not in self._knots or index + 1 not in self._knots:
            self._knots = {index: ends[0], index + 1: ends[1]}
        else:
            self.hits += 1
        w = t - index
        return (1.0 - w) * ends[0] + w * ends[1]
