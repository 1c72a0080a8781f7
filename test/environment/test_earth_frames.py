"""Earth orientation (GCRF <-> ITRF) and WGS-84 geodetic conversions."""

import datetime as dt
import math
import warnings

import erfa
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from adbsat_ros.environment.earth_frames import (
    EARTH_ROTATION_RATE,
    earth_orientation,
    ecef_to_eci,
    eci_to_ecef,
)
from adbsat_ros.environment.geodetic import (
    ecef_to_geodetic,
    enu_to_ecef_matrix,
    geodetic_to_ecef,
)
from adbsat_ros.environment.time_scales import utc_day

ARCSEC = math.pi / 180 / 3600

# Vallado, Seago & Seidelmann (2006), "Implementation issues surrounding the new IAU reference
# systems for astrodynamics", AAS 06-134, example (also Vallado, Fundamentals of Astrodynamics,
# 3rd ed., Example 3-14/3-15): 2004-04-06 07:51:28.386009 UTC, UT1-UTC = -0.4399619 s,
# x_p = -0.140682", y_p = 0.333309", TAI-UTC = 32 s.
VALLADO_TIME = dt.datetime(2004, 4, 6, 7, 51, 28, 386009)
VALLADO_DUT1 = -0.4399619
VALLADO_POLAR = (-0.140682 * ARCSEC, 0.333309 * ARCSEC)
VALLADO_R_ITRF = np.array([-1033.4793830, 7901.2952754, 6380.3565958]) * 1e3
VALLADO_V_ITRF = np.array([-3.225636520, -2.872451450, 5.531924446]) * 1e3
# GCRF from the IAU 2006/2000A CIO-based reduction with dX = dY = 0 (the same paper)
VALLADO_R_GCRF = np.array([5102.5089592, 6123.0114033, 6378.1369247]) * 1e3
VALLADO_V_GCRF = np.array([-4.74322016, 0.79053650, 5.53375528]) * 1e3


def vallado_orientation():
    return earth_orientation(VALLADO_TIME, ut1_minus_utc=VALLADO_DUT1, polar_motion=VALLADO_POLAR)


def test_rotation_rate_is_the_iers_value():
    assert EARTH_ROTATION_RATE == pytest.approx(7.292115146706979e-5, rel=1e-15)
    assert EARTH_ROTATION_RATE == pytest.approx(7.292115e-5, rel=3e-8)


@pytest.mark.parametrize(
    "time",
    [
        VALLADO_TIME,
        dt.datetime(2015, 1, 19),
        dt.datetime(1972, 7, 1, 12),
        dt.datetime(2090, 3, 3, 3, 3, 3),
    ],
)
def test_matrix_equals_erfa_c2t06a_through_erfa_time_scales(time):
    # Reference chain entirely in ERFA: dtf2d (UTC) -> utctai -> taitt, utcut1, then c2t06a.
    sec = time.second + time.microsecond * 1e-6
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", erfa.ErfaWarning)  # "dubious year" past ERFA's table
        u1, u2 = erfa.dtf2d("UTC", time.year, time.month, time.day, time.hour, time.minute, sec)
        a1, a2 = erfa.utctai(u1, u2)
        t1, t2 = erfa.taitt(a1, a2)
        b1, b2 = erfa.utcut1(u1, u2, 0.3)
    expected = erfa.c2t06a(t1, t2, b1, b2, 1e-6, -2e-6)
    ours = earth_orientation(time, ut1_minus_utc=0.3, polar_motion=(1e-6, -2e-6))
    assert np.abs(ours.celestial_to_terrestrial - expected).max() < 1e-12


def test_vallado_itrf_to_gcrf():
    position, velocity = vallado_orientation().ecef_to_eci(VALLADO_R_ITRF, VALLADO_V_ITRF)
    assert np.linalg.norm(position - VALLADO_R_GCRF) < 0.02  # m
    assert np.abs(velocity - VALLADO_V_GCRF).max() < 1e-3  # m/s


def test_vallado_gcrf_to_itrf():
    position, velocity = vallado_orientation().eci_to_ecef(VALLADO_R_GCRF, VALLADO_V_GCRF)
    assert np.linalg.norm(position - VALLADO_R_ITRF) < 0.02
    assert np.abs(velocity - VALLADO_V_ITRF).max() < 1e-3


def test_default_orientation_error_is_the_stated_ut1_error():
    # Without EOP (UT1 = UTC, no polar motion) the error is dominated by the UT1 offset: an
    # along-track shift of |DUT1| * omega * rho (rho = distance from the spin axis), here ~256 m,
    # within the module's stated bound of 0.9 s * omega * rho.
    position, _ = earth_orientation(VALLADO_TIME).ecef_to_eci(VALLADO_R_ITRF)
    rho = math.hypot(VALLADO_R_ITRF[0], VALLADO_R_ITRF[1])
    error = np.linalg.norm(position - VALLADO_R_GCRF)
    assert error == pytest.approx(abs(VALLADO_DUT1) * EARTH_ROTATION_RATE * rho, rel=0.05)
    assert error < 0.9 * EARTH_ROTATION_RATE * rho


def test_iau2000b_within_one_milliarcsecond_of_2006a():
    a = earth_orientation(dt.datetime(2015, 1, 19)).celestial_to_terrestrial
    b = earth_orientation(
        dt.datetime(2015, 1, 19), precession_nutation="iau2000b"
    ).celestial_to_terrestrial
    skew = a @ b.T - b @ a.T  # 2 sin(angle) [axis]_x for the small rotation between them
    angle = math.hypot(skew[2, 1], skew[0, 2], skew[1, 0]) / 2
    assert 0.0 < angle < 1e-3 * ARCSEC * 1.5


def test_matrix_is_a_rotation_and_read_only():
    matrix = earth_orientation(dt.datetime(2020, 2, 29, 12)).celestial_to_terrestrial
    assert np.allclose(matrix @ matrix.T, np.eye(3), atol=1e-15)
    assert np.linalg.det(matrix) == pytest.approx(1.0, abs=1e-15)
    with pytest.raises(ValueError):
        matrix[0, 0] = 1.0


def test_point_fixed_on_earth_moves_at_omega_rho_in_eci():
    time = dt.datetime(2015, 1, 19, 6)
    r_ecef = geodetic_to_ecef(math.radians(30), math.radians(45), 400e3)
    _, v_eci = ecef_to_eci(time, r_ecef, np.zeros(3))
    rho = math.hypot(r_ecef[0], r_ecef[1])
    assert np.linalg.norm(v_eci) == pytest.approx(EARTH_ROTATION_RATE * rho, rel=1e-9)
    # eastward: the ECEF velocity of an ECI-fixed point is westward, -omega x r
    _, v_ecef = eci_to_ecef(time, ecef_to_eci(time, r_ecef)[0], np.zeros(3))
    east = enu_to_ecef_matrix(math.radians(30), math.radians(45))[:, 0]
    assert v_ecef @ east == pytest.approx(-EARTH_ROTATION_RATE * rho, rel=1e-9)


def test_earth_rotates_once_per_sidereal_day():
    # After one sidereal day of UT1 (86164.0905 s) the ECEF frame is back to the same
    # orientation relative to ECI (up to precession-nutation: < 1e-6 rad a day).
    t0 = dt.datetime(2015, 1, 19)
    t1 = t0 + dt.timedelta(seconds=2 * math.pi / EARTH_ROTATION_RATE)
    a = earth_orientation(t0).celestial_to_terrestrial
    b = earth_orientation(t1).celestial_to_terrestrial
    assert np.abs(a - b).max() < 2e-6
    half = earth_orientation(t0 + dt.timedelta(seconds=math.pi / EARTH_ROTATION_RATE))
    # half a turn later: rotated by pi about the pole
    assert np.abs(np.diag([-1.0, -1.0, 1.0]) @ a - half.celestial_to_terrestrial).max() < 2e-6


@settings(max_examples=50, deadline=None)
@given(
    st.lists(st.floats(-8e6, 8e6), min_size=3, max_size=3),
    st.lists(st.floats(-8e3, 8e3), min_size=3, max_size=3),
    st.integers(0, 10**9),
)
def test_eci_ecef_round_trip(position, velocity, seconds):
    time = dt.datetime(2000, 1, 1) + dt.timedelta(seconds=seconds)
    orientation = earth_orientation(time)
    r_ecef, v_ecef = orientation.eci_to_ecef(position, velocity)
    r_eci, v_eci = orientation.ecef_to_eci(r_ecef, v_ecef)
    assert np.allclose(r_eci, position, rtol=0, atol=1e-6)
    assert np.allclose(v_eci, velocity, rtol=0, atol=1e-9)


def test_vectorised_states_match_single_ones():
    orientation = earth_orientation(dt.datetime(2015, 1, 19))
    positions = np.array([[7e6, 0, 0], [0, 7e6, 1e5], [1e6, 2e6, 6e6]])
    velocities = np.array([[0, 7.5e3, 0], [-7.5e3, 0, 10.0], [1.0, 2.0, 3.0]])
    r_all, v_all = orientation.eci_to_ecef(positions, velocities)
    for i in range(3):
        r, v = orientation.eci_to_ecef(positions[i], velocities[i])
        assert np.allclose(r_all[i], r, atol=1e-9) and np.allclose(v_all[i], v, atol=1e-12)


def test_aware_and_naive_utc_give_the_same_orientation():
    naive = dt.datetime(2015, 1, 19, 3)
    aware = dt.datetime(2015, 1, 19, 5, tzinfo=dt.timezone(dt.timedelta(hours=2)))
    assert np.array_equal(
        earth_orientation(naive).celestial_to_terrestrial,
        earth_orientation(aware).celestial_to_terrestrial,
    )


# --------------------------------------------------------------------------------- geodetic
def test_wgs84_reference_points():
    # WGS-84: a = 6378137 m, b = a (1 - f) = 6356752.314245 m (f = 1/298.257223563; GRS80's b
    # differs by 0.1 mm, which this tolerance would catch).
    assert np.allclose(geodetic_to_ecef(0.0, 0.0, 0.0), [6378137.0, 0.0, 0.0], atol=1e-9)
    assert geodetic_to_ecef(math.pi / 2, 0.0, 0.0)[2] == pytest.approx(6356752.314245, abs=1e-5)
    lat, lon, alt = ecef_to_geodetic([0.0, 6378137.0 + 400e3, 0.0])
    assert (lat, lon, alt) == pytest.approx((0.0, math.pi / 2, 400e3), abs=1e-9)


@settings(max_examples=300, deadline=None)
@given(
    st.floats(-90.0, 90.0),
    st.floats(-180.0, 180.0),
    st.floats(-10e3, 2000e3),
)
def test_geodetic_round_trip_to_a_millimetre(lat_deg, lon_deg, altitude):
    lat, lon = math.radians(lat_deg), math.radians(lon_deg)
    position = geodetic_to_ecef(lat, lon, altitude)
    lat2, lon2, alt2 = ecef_to_geodetic(position)
    assert abs(alt2 - altitude) < 1e-3
    # compare points (longitude is undefined at the poles)
    assert np.linalg.norm(geodetic_to_ecef(lat2, lon2, alt2) - position) < 1e-3
    assert abs(lat2 - lat) * 6.4e6 < 1e-3


@settings(max_examples=200, deadline=None)
@given(
    st.lists(st.floats(-8e6, 8e6), min_size=3, max_size=3).filter(
        lambda v: np.linalg.norm(v) > 6.2e6
    )
)
def test_ecef_round_trip_to_a_millimetre(position):
    lat, lon, alt = ecef_to_geodetic(position)
    assert np.linalg.norm(geodetic_to_ecef(lat, lon, alt) - np.array(position)) < 1e-3


def test_enu_matrix_is_local_east_north_up():
    lat, lon, h = math.radians(52.0), math.radians(-1.5), 300e3
    matrix = enu_to_ecef_matrix(lat, lon)
    assert np.allclose(matrix.T @ matrix, np.eye(3), atol=1e-15)
    step = 1e-7
    up = geodetic_to_ecef(lat, lon, h + 1.0) - geodetic_to_ecef(lat, lon, h)
    north = geodetic_to_ecef(lat + step, lon, h) - geodetic_to_ecef(lat, lon, h)
    east = geodetic_to_ecef(lat, lon + step, h) - geodetic_to_ecef(lat, lon, h)
    for column, direction in zip(matrix.T, (east, north, up)):
        assert np.allclose(column, direction / np.linalg.norm(direction), atol=1e-6)


# ------------------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: earth_orientation("2015-01-19"), "time"),
        (lambda: earth_orientation(dt.date(2015, 1, 19)), "time"),
        (
            lambda: earth_orientation(dt.datetime(2015, 1, 1), ut1_minus_utc=float("nan")),
            "ut1_minus_utc",
        ),
        (lambda: earth_orientation(dt.datetime(2015, 1, 1), polar_motion=(0.0,)), "polar_motion"),
        (
            lambda: earth_orientation(dt.datetime(2015, 1, 1), precession_nutation="iau1976"),
            "iau2006a, iau2000b",
        ),
        (lambda: eci_to_ecef(dt.datetime(2015, 1, 1), [1.0, 2.0]), "position_eci"),
        (
            lambda: eci_to_ecef(dt.datetime(2015, 1, 1), [7e6, 0, 0], [0, float("nan"), 0]),
            "velocity_eci",
        ),
        (lambda: ecef_to_eci(dt.datetime(2015, 1, 1), [7e6, 0, float("inf")]), "position_ecef"),
        (lambda: ecef_to_geodetic([7e6, "x", 0]), "position_ecef"),
        (lambda: geodetic_to_ecef(2.0, 0.0, 0.0), "latitude"),
        (lambda: geodetic_to_ecef(0.0, float("nan"), 0.0), "longitude"),
        (lambda: geodetic_to_ecef(0.0, 0.0, float("inf")), "altitude"),
    ],
)
def test_bad_inputs_name_the_input(call, name):
    with pytest.raises(ValueError, match=name):
        call()


def test_precession_nutation_step_is_accurate_and_order_independent():
    """A 60 s precession-nutation step moves the GCRF->ITRF matrix by < 1e-9 rad (the docstring's
    bound)."""
    base = dt.datetime(2026, 3, 20, 12, 0, 0)
    worst = 0.0
    for seconds in (0.0, 17.3, 29.9, 30.1, 59.99, 3600.5, 86400.0 * 200):
        t = base + dt.timedelta(seconds=seconds)
        exact = earth_orientation(t).celestial_to_terrestrial
        stepped = earth_orientation(t, precession_nutation_step=60.0).celestial_to_terrestrial
        worst = max(worst, float(np.abs(stepped - exact).max()))
    assert 0.0 < worst < 1e-9
    # the same instant gives the same matrix whatever was evaluated before
    t = base + dt.timedelta(seconds=45.0)
    first = earth_orientation(t, precession_nutation_step=60.0).celestial_to_terrestrial.copy()
    earth_orientation(base + dt.timedelta(days=3), precession_nutation_step=60.0)
    assert np.array_equal(
        first, earth_orientation(t, precession_nutation_step=60.0).celestial_to_terrestrial
    )
    with pytest.raises(ValueError, match="precession_nutation_step"):
        earth_orientation(t, precession_nutation_step=-1.0)


# --------------------------------------------------------------- the per-message float path
def test_day_constants_are_erfa_julian_date_leap_seconds_and_day_of_year():
    for day in (
        dt.date(1972, 1, 1),
        dt.date(2016, 12, 31),
        dt.date(2017, 1, 1),
        dt.date(2024, 12, 31),
    ):
        jd1, tt_minus_utc, day_of_year = utc_day(day.year, day.month, day.day)
        assert (jd1, 0.0) == erfa.dtf2d("UTC", day.year, day.month, day.day, 0, 0, 0.0)
        assert tt_minus_utc * 86400.0 == pytest.approx(
            erfa.dat(day.year, day.month, day.day, 0.5) + 32.184, abs=1e-9
        )
        assert day_of_year == day.timetuple().tm_yday
    # 2016-12-31 ended with a leap second: TT - UTC grows by 1 s from the next day
    assert (utc_day(2017, 1, 1)[1] - utc_day(2016, 12, 31)[1]) * 86400.0 == pytest.approx(
        1.0, abs=1e-9
    )


@pytest.mark.parametrize("model", ["iau2006a", "iau2000b"])
def test_orientation_over_random_instants_equals_erfa_built_matrix(model):
    """earth_orientation (float path, memoised precession-nutation) against the same rotation built
    from pyerfa pieces: W(xp, yp, s') R3(ERA(UT1)) Q(TT at the step's centre), to 1e-12."""
    c2i = {"iau2006a": erfa.c2i06a, "iau2000b": erfa.c2i00b}[model]
    rng = np.random.default_rng(11)
    for _ in range(60):
        time = dt.datetime(1972, 1, 1) + dt.timedelta(
            days=int(rng.integers(0, 128 * 365)), seconds=float(rng.uniform(0, 86400))
        )
        dut1 = float(rng.uniform(-0.9, 0.9))
        polar = tuple(rng.uniform(-0.5, 0.5, 2) * ARCSEC) if rng.random() < 0.5 else (0.0, 0.0)
        step = float(rng.choice([0.0, 1.0, 60.0, 3600.0]))
        sec = time.second + time.microsecond * 1e-6
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", erfa.ErfaWarning)
            u1, u2 = erfa.dtf2d("UTC", time.year, time.month, time.day, time.hour, time.minute, sec)
            t1, t2 = erfa.taitt(*erfa.utctai(u1, u2))
            b1, b2 = erfa.utcut1(u1, u2, dut1)
        if step > 0.0:
            step_days = step / 86400.0
            q = c2i(2451545.0, (math.floor(((t1 - 2451545.0) + t2) / step_days) + 0.5) * step_days)
        else:
            q = c2i(t1, t2)
        w = np.eye(3) if polar == (0.0, 0.0) else erfa.pom00(polar[0], polar[1], erfa.sp00(t1, t2))
        ours = earth_orientation(
            time,
            ut1_minus_utc=dut1,
            polar_motion=polar,
            precession_nutation=model,
            precession_nutation_step=step,
        )
        assert (
            np.abs(ours.celestial_to_terrestrial - erfa.c2tcio(q, erfa.era00(b1, b2), w)).max()
            < 1e-12
        )
        assert ours.earth_rotation_angle == pytest.approx(erfa.era00(b1, b2), abs=1e-12)
        assert np.allclose(
            ours.rotation_vector_ecef, w @ [0.0, 0.0, EARTH_ROTATION_RATE], rtol=1e-12, atol=0
        )
        assert (
            not ours.celestial_to_terrestrial.flags.writeable
            and not ours.rotation_vector_ecef.flags.writeable
        )
