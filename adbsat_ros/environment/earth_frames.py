"""Earth orientation: GCRF (ECI) <-> ITRF (ECEF) with pyerfa; units m, m/s, rad. The CIO-based
rotation ``W(xp, yp) R3(ERA(UT1)) Q(TT)`` (``erfa.c2i06a`` or ``erfa.c2i00b``, ``erfa.era00``,
``erfa.pom00``); velocities: ``v_ecef = R v_eci - omega x r_ecef``. Defaults UT1 = UTC, no polar
motion; accuracy, Vallado et al. (2006) check: docs/physics.md, section 5.4."""

from __future__ import annotations

import datetime as _dt
import functools
import math
from dataclasses import dataclass

import erfa
import numpy as np

from adbsat_ros.environment.time_scales import (
    SECONDS_PER_DAY,
    seconds_of_day,
    utc_datetime,
    utc_day,
)
from adbsat_ros.geometry.frames import cross
from adbsat_ros.validation import vectors3

#: Rate of the Earth rotation angle [rad/s] (IERS Conventions 2010, eq. 5.15:
#: 2 pi * 1.00273781191135448 per UT1 day of 86400 s).
EARTH_ROTATION_RATE = 2.0 * math.pi * 1.00273781191135448 / 86400.0


#: Precession-nutation models accepted by :func:`earth_orientation`.
PRECESSION_NUTATION_MODELS = ("iau2006a", "iau2000b")

_ARCSEC = math.pi / (180.0 * 3600.0)


# --------------------------------------------------------------------------- Earth orientation
@dataclass(frozen=True, eq=False)
class EarthOrientation:
    """Orientation of the ITRF (ECEF) relative to the GCRF (ECI) at one (naive UTC) ``time``.
    ``celestial_to_terrestrial``: R, ``r_ecef = R @ r_eci``; ``earth_rotation_angle``: ERA(UT1)
    [rad]; ``rotation_vector_ecef``: angular velocity of ECEF relative to ECI, ECEF axes [rad/s]."""

    time: _dt.datetime
    celestial_to_terrestrial: np.ndarray
    earth_rotation_angle: float
    rotation_vector_ecef: np.ndarray

    # Positions are row vectors, (3,) or (N, 3): r_ecef = r_eci @ R.T.
    def eci_to_ecef(self, position_eci, velocity_eci=None):
        """``(position_ecef [m], velocity_ecef [m/s] or None)`` of ECI ones, (3,) or (N, 3)."""
        matrix = self.celestial_to_terrestrial
        position_ecef = vectors3(position_eci, "position_eci") @ matrix.T
        if velocity_eci is None:
            return position_ecef, None
        velocity = vectors3(velocity_eci, "velocity_eci") @ matrix.T
        return position_ecef, velocity - cross(self.rotation_vector_ecef, position_ecef)

    def ecef_to_eci(self, position_ecef, velocity_ecef=None):
        """``(position_eci [m], velocity_eci [m/s] or None)`` of ECEF ones, (3,) or (N, 3)."""
        matrix = self.celestial_to_terrestrial
        position = vectors3(position_ecef, "position_ecef")
        position_eci = position @ matrix
        if velocity_ecef is None:
            return position_eci, None
        velocity = vectors3(velocity_ecef, "velocity_ecef")
        return position_eci, (velocity + cross(self.rotation_vector_ecef, position)) @ matrix


_CELESTIAL_TO_INTERMEDIATE = {"iau2006a": erfa.c2i06a, "iau2000b": erfa.c2i00b}
#: Angular velocity of the ECEF frame in ECEF axes with zero polar motion [rad/s].
_ROTATION_VECTOR_ECEF = np.array((0.0, 0.0, EARTH_ROTATION_RATE))
_ROTATION_VECTOR_ECEF.setflags(write=False)
_IDENTITY = np.eye(3)


@functools.lru_cache(maxsize=256)
def _celestial_to_intermediate_at(model: str, bucket: int, step_days: float) -> np.ndarray:
    """Celestial-to-intermediate matrix at the centre of TT interval ``bucket``; memoised, the
    package's one memo (docs/benchmarks.md, the estimator's options)."""
    return _CELESTIAL_TO_INTERMEDIATE[model](2451545.0, (bucket + 0.5) * step_days)


def check_orientation_options(
    ut1_minus_utc, polar_motion, precession_nutation, precession_nutation_step
):
    """``(ut1_minus_utc [s], x_p, y_p [rad], model, step [s])``; ValueError naming a bad one."""
    ut1_minus_utc = float(ut1_minus_utc)
    if not math.isfinite(ut1_minus_utc) or abs(ut1_minus_utc) > 1.0:
        raise ValueError(
            f"ut1_minus_utc must be a finite number of seconds in [-1, 1], got {ut1_minus_utc!r}"
        )
    try:
        xp, yp = float(polar_motion[0]), float(polar_motion[1])
        if len(polar_motion) != 2:
            raise ValueError
    except (TypeError, ValueError, IndexError):
        raise ValueError(
            f"polar_motion must be a pair (x_p, y_p) in rad, got {polar_motion!r}"
        ) from None
    if not (math.isfinite(xp) and math.isfinite(yp)) or max(abs(xp), abs(yp)) > 10 * _ARCSEC:
        raise ValueError(
            f"polar_motion must be finite and within 10 arcsec (given in rad), got {polar_motion!r}"
        )
    if precession_nutation not in PRECESSION_NUTATION_MODELS:
        raise ValueError(
            f"unknown precession_nutation {precession_nutation!r}; "
            f"allowed: {', '.join(PRECESSION_NUTATION_MODELS)}"
        )
    step = float(precession_nutation_step)
    if not (math.isfinite(step) and 0.0 <= step <= 3600.0):
        raise ValueError(
            f"precession_nutation_step must be in [0, 3600] s, got {precession_nutation_step!r}"
        )
    return ut1_minus_utc, xp, yp, precession_nutation, step


def celestial_to_intermediate(jd1, tt2, precession_nutation, step):
    """The GCRS-to-CIRS matrix (3, 3) at TT ``jd1`` + ``tt2`` [day], kept per ``step`` [s] of TT
    (0: exactly at the time)."""
    if step > 0.0:
        step_days = step / SECONDS_PER_DAY
        bucket = math.floor(((jd1 - 2451545.0) + tt2) / step_days)
        return _celestial_to_intermediate_at(precession_nutation, bucket, step_days)
    return _CELESTIAL_TO_INTERMEDIATE[precession_nutation](jd1, tt2)


def rotation_terms(
    jd1, day_fraction, tt_minus_utc, ut1_minus_utc, xp, yp, precession_nutation, step
):
    """R (3, 3), ERA [rad], omega (ECEF, [rad/s]) at UTC two-part JD ``jd1`` + ``day_fraction``;
    ``tt_minus_utc`` [day]; the rest as :func:`check_orientation_options` returns them."""
    tt2 = day_fraction + tt_minus_utc
    q = celestial_to_intermediate(jd1, tt2, precession_nutation, step)
    era = float(erfa.era00(jd1, day_fraction + ut1_minus_utc / SECONDS_PER_DAY))
    if xp == 0.0 and yp == 0.0:
        return erfa.c2tcio(q, era, _IDENTITY), era, _ROTATION_VECTOR_ECEF
    polar = erfa.pom00(xp, yp, erfa.sp00(jd1, tt2))
    return erfa.c2tcio(q, era, polar), era, polar @ _ROTATION_VECTOR_ECEF


def earth_orientation(
    time,
    *,
    ut1_minus_utc: float = 0.0,
    polar_motion=(0.0, 0.0),
    precession_nutation: str = "iau2006a",
    precession_nutation_step: float = 0.0,
) -> EarthOrientation:
    """Earth orientation (GCRF -> ITRF rotation) at a UTC instant, an :class:`EarthOrientation`.
    time: UTC datetime, timezone-aware or naive meaning UTC.
    ut1_minus_utc: UT1 - UTC [s], |.| <= 1 (default 0, docs/physics.md, section 5.4).
    polar_motion: pole coordinates (x_p, y_p) [rad], within 10 arcsec.
    precession_nutation: ``"iau2006a"`` (``erfa.c2i06a``) or ``"iau2000b"`` (within 1 mas of 2000A).
    precession_nutation_step: 0, or [s] in (0, 3600]: Q at its TT interval's centre, memoised.
    ValueError: a ``time`` that is no datetime, an option out of range, an unknown model (named)."""
    time = utc_datetime(time)
    options = check_orientation_options(
        ut1_minus_utc, polar_motion, precession_nutation, precession_nutation_step
    )
    jd1, tt_minus_utc, _ = utc_day(time.year, time.month, time.day)
    day_fraction = seconds_of_day(time) / SECONDS_PER_DAY
    matrix, era, axis = rotation_terms(jd1, day_fraction, tt_minus_utc, *options)
    matrix.setflags(write=False)
    axis.setflags(write=False)
    return EarthOrientation(time, matrix, era, axis)


def eci_to_ecef(time, position_eci, velocity_eci=None, **orientation_options):
    """``earth_orientation(time, **orientation_options).eci_to_ecef(...)``."""
    return earth_orientation(time, **orientation_options).eci_to_ecef(position_eci, velocity_eci)


def ecef_to_eci(time, position_ecef, velocity_ecef=None, **orientation_options):
    """``earth_orientation(time, **orientation_options).ecef_to_eci(...)``."""
    return earth_orientation(time, **orientation_options).ecef_to_eci(position_ecef, velocity_ecef)
