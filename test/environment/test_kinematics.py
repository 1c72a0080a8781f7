"""The float kinematics of a knot (fast path) against erfa and numpy (reference)."""

from __future__ import annotations

import math

import erfa
import numpy as np
import pytest

from adbsat_ros.environment.earth_frames import rotation_terms
from adbsat_ros.environment.geodetic import WGS84
from adbsat_ros.environment.kinematics import (
    earth_rotation_angle,
    geodetic_of_floats,
    rotation_floats,
    state_kinematics,
    state_kinematics_reference,
)
from adbsat_ros.environment.time_scales import utc_day

ARCSEC = math.pi / (180.0 * 3600.0)


def test_float_geodetic_equals_erfa_gc2gd_bit_for_bit():
    """Random LEO and ground positions, both hemispheres, the poles, the polar axis, the
    equator, the centre and far-out points."""
    rng = np.random.default_rng(7)
    direction = rng.normal(size=(5000, 3))
    radius = rng.uniform(6.2e6, 7.6e6, size=(5000, 1))
    positions = direction / np.linalg.norm(direction, axis=1, keepdims=True) * radius
    special = np.array(
        [
            [6378137.0, 0.0, 0.0],
            [0.0, 0.0, 6356752.314245],
            [0.0, 0.0, -6.8e6],
            [1e-3, 0.0, 6.8e6],
            [0.0, 0.0, 0.0],
            [-6.8e6, 0.0, 0.0],
            [0.0, -6.8e6, 1.0],
            [4.2e7, 1e3, -2e3],
            [1e-9, 1e-9, 1e-9],
            [6.8e6, 0.0, -0.0],
        ]
    )
    for position in np.vstack([positions, special]):
        longitude, latitude, altitude, status = erfa.ufunc.gc2gd(WGS84, position)
        assert status == 0
        expected = (float(latitude), float(longitude), float(altitude))
        assert geodetic_of_floats(*position.tolist()) == expected, position


def test_float_earth_rotation_angle_equals_erfa_era00_bit_for_bit():
    rng = np.random.default_rng(11)
    days = 2436204.5 + rng.integers(0, 52000, size=5000)
    fractions = rng.uniform(-2e-5, 1.0 + 2e-5, size=5000)
    for day, fraction in zip(days.tolist(), fractions.tolist()):
        assert earth_rotation_angle(day, fraction) == float(erfa.ufunc.era00(day, fraction))
        assert earth_rotation_angle(fraction, day) == float(erfa.ufunc.era00(fraction, day))
        assert 0.0 <= earth_rotation_angle(day, fraction) < 2.0 * math.pi


@pytest.mark.parametrize("model", ["iau2006a", "iau2000b"])
@pytest.mark.parametrize("step", [0.0, 60.0])
def test_float_rotation_equals_erfa_rotation_terms_bit_for_bit(model, step):
    """Without polar motion composed by hand (erfa.rz's operations), with it erfa's own."""
    rng = np.random.default_rng(5)
    for year, month, day in zip(
        rng.integers(1960, 2100, 40).tolist(),
        rng.integers(1, 13, 40).tolist(),
        rng.integers(1, 29, 40).tolist(),
    ):
        jd1, tt_minus_utc, _ = utc_day(year, month, day)
        fraction = float(rng.uniform(0.0, 1.0))
        ut1 = float(rng.uniform(-0.9, 0.9))
        for xp, yp in ((0.0, 0.0), (3.0 * ARCSEC, -2.0 * ARCSEC)):
            options = (ut1, xp, yp, model, step)
            matrix, era, axis = rotation_terms(jd1, fraction, tt_minus_utc, *options)
            floats = rotation_floats(jd1, fraction, tt_minus_utc, *options)
            assert floats == (tuple(matrix.ravel().tolist()), era, tuple(axis.tolist()))


@pytest.mark.parametrize("frame", ["eci", "ecef"])
@pytest.mark.parametrize("earth_rotation", [True, False])
@pytest.mark.parametrize("wind_frame", [None, "enu", "ecef"])
def test_float_kinematics_agree_with_the_numpy_reference(frame, earth_rotation, wind_frame):
    """Vectors within 1e-12 of their norm, latitude and longitude within 1e-12 rad, altitude
    within 1e-12 of the radius, speed within 1e-12 relative, over random states and instants."""
    rng = np.random.default_rng(13)
    for _ in range(300):
        jd1, tt_minus_utc, _ = utc_day(int(rng.integers(1970, 2090)), 6, 15)
        options = (0.0, 0.0, 0.0, "iau2006a", 60.0)
        matrix, _, omega = rotation_floats(jd1, float(rng.uniform()), tt_minus_utc, *options)
        rotation = np.reshape(matrix, (3, 3))
        direction = rng.normal(size=3)
        position = direction / np.linalg.norm(direction) * rng.uniform(6.5e6, 7.3e6)
        velocity = rng.normal(size=3) * 5000.0
        wind = None if wind_frame is None else tuple(rng.normal(size=3) * 100.0)
        args = (frame, tuple(position), tuple(velocity), wind, wind_frame, earth_rotation)
        vectors, *geodetic, speed = state_kinematics(matrix, omega, *args)
        ref_vectors, *ref_geodetic, ref_speed = state_kinematics_reference(
            rotation, np.array(omega), *args
        )
        vectors = np.array(vectors)
        scale = np.linalg.norm(ref_vectors, axis=1, keepdims=True)
        assert np.all(np.abs(vectors - ref_vectors) <= 1e-12 * scale)
        assert np.allclose(geodetic[:2], ref_geodetic[:2], rtol=0.0, atol=1e-12)
        assert geodetic[2] == pytest.approx(ref_geodetic[2], rel=0.0, abs=1e-12 * scale[0, 0])
        assert speed == pytest.approx(ref_speed, rel=1e-12)
