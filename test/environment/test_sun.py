"""The Sun's position against the seasons, the solar pressure's scaling, and Earth's shadow against
a direct integration of the visible solar disc and along an orbit through eclipse."""

from __future__ import annotations

import datetime as dt
import math

import erfa
import numpy as np
import pytest

from adbsat_ros.environment.sun import (
    ASTRONOMICAL_UNIT,
    EARTH_SHADOW_RADIUS,
    SUN_RADIUS,
    SunTrack,
    lit_fraction,
    solar_pressure,
    sun_position_eci,
    sun_state,
)
from adbsat_ros.environment.time_scales import julian_dates

MU = 3.986004418e14


def true_of_date(time, vector):
    """``vector`` (GCRS) in the true equator and equinox of date (ERFA's IAU 2006/2000A
    bias-precession-nutation matrix): where the seasons are defined."""
    _, (tt1, tt2), _ = julian_dates(time)
    return erfa.pnm06a(tt1, tt2) @ vector


@pytest.mark.parametrize(
    "time, au",
    [(dt.datetime(2024, 1, 3, 0, 39), 0.98331), (dt.datetime(2024, 7, 5, 5, 6), 1.01673)],
)
def test_the_sun_is_nearest_at_perihelion_and_furthest_at_aphelion(time, au):
    """Earth-Sun distances at perihelion and aphelion 2024 (USNO: 0.983 and 1.017 au)."""
    assert np.linalg.norm(sun_position_eci(time)) / ASTRONOMICAL_UNIT == pytest.approx(au, abs=2e-4)


def test_the_seasons_are_where_the_calendar_puts_them():
    """In the frame of date the Sun crosses the equator at the March equinox (2024-03-20 03:06
    UTC) and stands 23.44 deg north at the June solstice (2024-06-20 20:51 UTC), within the
    minute of the published times (0.01 deg) and the 20 arcsec of aberration."""
    equinox = dt.datetime(2024, 3, 20, 3, 6)
    s = true_of_date(equinox, sun_position_eci(equinox))
    assert math.degrees(math.asin(s[2] / np.linalg.norm(s))) == pytest.approx(0.0, abs=0.015)
    assert math.degrees(math.atan2(s[1], s[0])) == pytest.approx(0.0, abs=0.03)
    solstice = dt.datetime(2024, 6, 20, 20, 51)
    s = true_of_date(solstice, sun_position_eci(solstice))
    assert math.degrees(math.asin(s[2] / np.linalg.norm(s))) == pytest.approx(23.438, abs=0.01)
    # the GCRS (J2000 axes) differs from the frame of date by 24 years of precession
    raw = sun_position_eci(equinox)
    assert math.degrees(math.atan2(raw[1], raw[0])) % 360.0 == pytest.approx(359.69, abs=0.02)


def test_the_solar_pressure_is_the_irradiance_over_c_and_falls_as_the_square_of_distance():
    assert solar_pressure(ASTRONOMICAL_UNIT) == pytest.approx(1361.0 / 299792458.0, rel=1e-15)
    assert solar_pressure(2.0 * ASTRONOMICAL_UNIT) == pytest.approx(
        solar_pressure(ASTRONOMICAL_UNIT) / 4.0, rel=1e-15
    )
    for bad in (0.0, -1.0, math.nan, math.inf):
        with pytest.raises(ValueError, match="sun_distance"):
            solar_pressure(bad)


def visible_disc_fraction(position, sun, samples: int = 1201) -> float:
    """The fraction of the solar disc not behind the Earth, by counting points of a grid over
    the disc as seen from ``position`` (angles in the plane normal to the Sun's direction)."""
    to_sun = sun - position
    distance = np.linalg.norm(to_sun)
    w = to_sun / distance
    e1 = np.cross(w, [0.0, 0.0, 1.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(w, e1)
    a = math.asin(SUN_RADIUS / distance)
    t = np.linspace(-a, a, samples)
    x, y = np.meshgrid(t, t)
    inside = x * x + y * y <= a * a
    directions = (
        w[None, None, :]
        + np.tan(x)[..., None] * e1[None, None, :]
        + np.tan(y)[..., None] * e2[None, None, :]
    )
    directions /= np.linalg.norm(directions, axis=-1, keepdims=True)
    # a line of sight from the satellite meets the Earth's sphere?
    along = -(directions @ position)
    closest = np.linalg.norm(position[None, None, :] + along[..., None] * directions, axis=-1)
    blocked = (along > 0.0) & (closest < EARTH_SHADOW_RADIUS)
    return float((inside & ~blocked).sum() / inside.sum())


def test_the_penumbra_equals_a_count_over_the_visible_solar_disc():
    sun = np.array([ASTRONOMICAL_UNIT, 0.0, 0.0])
    r = EARTH_SHADOW_RADIUS + 400e3
    # the penumbra at 400 km: the Earth's limb crosses the Sun where the satellite is about
    # asin(R_E / r) from the anti-Sun direction, within a Sun radius (0.27 deg)
    edge = math.pi - math.asin(EARTH_SHADOW_RADIUS / r)
    fractions = []
    for offset in (-0.26, -0.13, 0.0, 0.13, 0.26):
        theta = edge + math.radians(offset)
        position = r * np.array([math.cos(theta), math.sin(theta), 0.0])
        expected = visible_disc_fraction(position, sun)
        fractions.append(expected)
        assert lit_fraction(position, sun) == pytest.approx(expected, abs=2e-3)
    assert fractions[0] > 0.95 and fractions[-1] < 0.05  # the offsets span the penumbra


def test_along_an_orbit_the_shadow_is_continuous_with_a_short_penumbra():
    """A 400 km circular orbit whose plane holds the Sun: about a third of it in umbra, the
    light fading over about 8 s on each side (2 x the Sun's angular diameter of 0.53 deg over
    the orbit's 0.063 deg/s, stretched by the limb's slant), in steps no larger than a 0.1 s
    sample of that fade can make."""
    time = dt.datetime(2026, 3, 20, 12)
    sun = sun_position_eci(time)
    u = sun / np.linalg.norm(sun)
    e2 = np.cross(u, [0.0, 0.0, 1.0])
    e2 /= np.linalg.norm(e2)
    r = EARTH_SHADOW_RADIUS + 400e3
    period = 2.0 * math.pi * math.sqrt(r**3 / MU)
    t = np.arange(0.0, period, 0.1)
    theta = 2.0 * math.pi * t / period
    positions = r * (np.cos(theta)[:, None] * u + np.sin(theta)[:, None] * e2)
    f = lit_fraction(positions, sun)
    assert 0.35 < np.mean(f == 0.0) < 0.42
    assert f[0] == 1.0 and f.min() == 0.0
    penumbra_seconds = 0.1 * np.count_nonzero((f > 0.0) & (f < 1.0)) / 2.0
    assert 6.0 < penumbra_seconds < 12.0
    steps = np.abs(np.diff(f))
    assert steps.max() < 0.1 * 3.0 / 6.0  # the steepest part of a >= 6 s fade, sampled at 0.1 s
    assert np.all(np.diff(f[(theta > 0.5 * math.pi) & (theta < math.pi)]) <= 0.0)  # into shadow


def test_the_state_of_the_sun_for_a_satellite():
    time = dt.datetime(2026, 6, 1)
    position = np.array([7e6, 0.0, 0.0])
    state = sun_state(time, position)
    to_sun = sun_position_eci(time) - position
    np.testing.assert_allclose(state.direction_eci, to_sun / np.linalg.norm(to_sun), atol=1e-15)
    assert state.pressure == pytest.approx(solar_pressure(np.linalg.norm(to_sun)))
    assert 0.0 <= state.lit_fraction <= 1.0


@pytest.mark.parametrize(
    "position, match",
    [
        ([math.nan, 0.0, 0.0], "position_eci"),
        ([6.0e6, 0.0, 0.0], "outside the Earth"),
        ([[7e6, 0.0]], "position_eci"),
    ],
)
def test_bad_positions_are_refused_by_name(position, match):
    with pytest.raises(ValueError, match=match):
        lit_fraction(position, [ASTRONOMICAL_UNIT, 0.0, 0.0])


def test_one_position_and_many_give_the_same_shadow():
    """sun_state's shadow of one position (floats) equals lit_fraction's of many (arrays),
    through umbra, penumbra and sunlight."""
    sun = sun_position_eci(dt.datetime(2026, 8, 1))
    u = sun / np.linalg.norm(sun)
    e2 = np.cross(u, [0.0, 0.0, 1.0])
    e2 /= np.linalg.norm(e2)
    rng = np.random.default_rng(5)
    r = EARTH_SHADOW_RADIUS + rng.uniform(150e3, 40000e3, 3000)
    edge = math.pi - np.arcsin(EARTH_SHADOW_RADIUS / r)
    theta = edge + rng.normal(0.0, 0.01, r.size)  # most within a few penumbra widths
    positions = r[:, None] * (np.cos(theta)[:, None] * u + np.sin(theta)[:, None] * e2)
    many = lit_fraction(positions, sun)
    one = [sun_state(dt.datetime(2026, 8, 1), p, sun).lit_fraction for p in positions]
    assert 0.2 < np.mean((many > 0) & (many < 1)) < 0.9
    # (rounding, which the overlap amplifies where the discs are about to touch)
    np.testing.assert_allclose(one, many, rtol=0, atol=1e-8)


def test_the_sun_track_follows_the_ephemeris_within_its_bound():
    """Linear between knots a minute apart: within 3 m of ERFA's position (the bound 2.7 m),
    and a stream of stamps evaluates each knot once."""
    track = SunTrack(60.0)
    start = dt.datetime(2026, 5, 17, 3, 0, 7)
    worst = 0.0
    for k in range(600):
        time = start + dt.timedelta(seconds=0.5 * k)
        worst = max(worst, np.linalg.norm(track.position(time) - sun_position_eci(time)))
    assert worst < 3.0
    assert track.misses == 7 and track.hits == 600 - 6  # knots 03:00 ... 03:06; 6 calls made them
    with pytest.raises(ValueError, match="step"):
        SunTrack(0.0)
