"""Flight conditions: frames, relative wind, free stream, ADBSat parity, validation."""

import copy
import dataclasses
import datetime as dt
import json
import math

import numpy as np
import pytest

from adbsat_ros.environment.atmosphere import SpaceWeather, evaluate_atmosphere
from adbsat_ros.environment.circular_orbit import (
    circular_orbit_speed,
    flight_conditions_circular_orbit,
)
from adbsat_ros.environment.earth_frames import EARTH_ROTATION_RATE, earth_orientation, ecef_to_eci
from adbsat_ros.environment.flight_conditions import (
    FlightConditions,
    conditions_options,
    evaluate_flight_conditions,
    flight_conditions,
)
from adbsat_ros.environment.geodetic import enu_to_ecef_matrix, geodetic_to_ecef
from adbsat_ros.physics.constants import AVOGADRO, BOLTZMANN, MOLAR_MASS_G
from adbsat_ros.physics.freestream import FreeStream

TIME = dt.datetime(2015, 1, 19, 6, 30)
# ADBSat validation paper conditions (Sinpetru et al. 2022, Comput. Phys. Commun. 275; physics.md)
PAPER_TIME = dt.datetime(2015, 1, 19)
WEATHER = SpaceWeather(f107=121.7, f107a=138.1, ap=4.0)
LAT, LON, ALT = math.radians(45.0), math.radians(10.0), 400e3


def assert_same_atmosphere(a, b, rel=1e-9):
    assert a.mass_density == pytest.approx(b.mass_density, rel=rel)
    assert a.temperature == pytest.approx(b.temperature, rel=rel)
    for name, value in a.number_densities.items():
        assert value == pytest.approx(b.number_densities[name], rel=rel), name


def at_rest_in_ecef(**kwargs):
    position = geodetic_to_ecef(LAT, LON, ALT)
    return flight_conditions(TIME, position, np.zeros(3), WEATHER, frame="ecef", **kwargs)


def test_satellite_at_rest_in_ecef_has_no_relative_wind():
    conditions = at_rest_in_ecef()
    assert np.array_equal(conditions.relative_velocity_ecef, np.zeros(3))
    assert np.abs(conditions.relative_velocity_eci).max() == 0.0
    assert conditions.speed == 0.0 and conditions.speed_ratio == 0.0
    assert (conditions.latitude, conditions.longitude) == pytest.approx((LAT, LON), abs=1e-12)
    assert conditions.altitude == pytest.approx(ALT, abs=1e-6)
    # the same state given in ECI (its inertial velocity is omega x r): still no wind
    r_eci, v_eci = ecef_to_eci(TIME, conditions.position_ecef, np.zeros(3))
    assert np.linalg.norm(v_eci) > 300.0
    again = flight_conditions(TIME, r_eci, v_eci, WEATHER, frame="eci")
    assert np.abs(again.relative_velocity_eci).max() < 1e-9
    assert np.abs(again.relative_velocity_ecef).max() < 1e-9
    assert np.linalg.norm(again.position_ecef - conditions.position_ecef) < 1e-6
    assert_same_atmosphere(again.atmosphere, conditions.atmosphere)


def test_zero_relative_speed_does_not_crash_but_has_no_free_stream():
    for model, options in (
        ("langmuir", None),
        ("goodman", None),
        ("sesam", None),
        ("fixed", {"alpha": 0.9}),
    ):
        conditions = at_rest_in_ecef(accommodation_model=model, accommodation_options=options)
        assert 0.0 < conditions.alpha <= 1.0
        assert conditions.flow_direction_ecef is None
        with pytest.raises(ValueError, match="speed"):
            conditions.free_stream()


def test_air_at_rest_in_eci_without_earth_rotation():
    # A point fixed on the Earth moves through inertially fixed air at omega * rho.
    conditions = at_rest_in_ecef(earth_rotation=False)
    rho = math.hypot(conditions.position_ecef[0], conditions.position_ecef[1])
    assert conditions.speed == pytest.approx(EARTH_ROTATION_RATE * rho, rel=1e-9)
    east = enu_to_ecef_matrix(LAT, LON)[:, 0]
    assert conditions.relative_velocity_ecef @ east == pytest.approx(conditions.speed, rel=1e-9)


def test_prograde_equatorial_orbit_loses_the_earth_rotation_speed():
    # Eastward circular orbit at 400 km: v_rel ~ v - omega r (co-rotating air); the GCRS equator
    # is within ~2e-3 rad of the true equator, which changes this by < 1 mm/s.
    radius = 6378137.0 + 400e3
    speed = math.sqrt(3.986004418e14 / radius)
    position = earth_orientation(TIME).ecef_to_eci([radius, 0.0, 0.0])[0]
    velocity = np.cross([0.0, 0.0, 1.0], position) / radius * speed
    conditions = flight_conditions(TIME, position, velocity, WEATHER)
    assert conditions.speed == pytest.approx(speed - EARTH_ROTATION_RATE * radius, abs=0.5)
    retrograde = flight_conditions(TIME, position, -velocity, WEATHER)
    assert retrograde.speed == pytest.approx(speed + EARTH_ROTATION_RATE * radius, abs=0.5)


def test_wind_enu_and_ecef_agree_and_subtract():
    wind_enu = np.array([30.0, -100.0, 2.0])
    enu = at_rest_in_ecef(wind=wind_enu)
    wind_ecef = enu_to_ecef_matrix(LAT, LON) @ wind_enu
    ecef = at_rest_in_ecef(wind=wind_ecef, wind_frame="ecef")
    assert np.allclose(enu.relative_velocity_ecef, -wind_ecef, atol=1e-9)
    assert np.allclose(ecef.relative_velocity_ecef, enu.relative_velocity_ecef, atol=1e-9)
    assert enu.speed == pytest.approx(np.linalg.norm(wind_enu), rel=1e-12)
    # the flow direction is the wind direction
    assert np.allclose(enu.flow_direction_ecef, wind_ecef / np.linalg.norm(wind_ecef), atol=1e-12)


def test_eci_and_ecef_relative_velocity_are_the_same_vector():
    position = np.array([4.0e6, -3.0e6, 4.2e6])
    velocity = np.array([5.0e3, 5.5e3, 0.5e3])
    conditions = flight_conditions(TIME, position, velocity, WEATHER, wind=[10.0, 20.0, 0.0])
    matrix = earth_orientation(TIME).celestial_to_terrestrial
    assert np.allclose(
        matrix @ conditions.relative_velocity_eci, conditions.relative_velocity_ecef, atol=1e-9
    )
    assert np.linalg.norm(conditions.relative_velocity_eci) == pytest.approx(
        conditions.speed, rel=1e-12
    )


def test_free_stream_carries_the_conditions():
    position = np.array([6778e3, 0.0, 0.0])
    velocity = np.array([0.0, 7668.0, 0.0])
    conditions = flight_conditions(TIME, position, velocity, WEATHER)
    stream = conditions.free_stream()
    assert isinstance(stream, FreeStream)
    assert stream.speed == conditions.speed
    assert stream.temperature == conditions.atmosphere.temperature
    assert stream.density == conditions.atmosphere.mass_density
    assert set(stream.species) == {"He", "O", "N2", "O2", "Ar", "H", "N", "AnO"}
    assert stream.speed_ratio == pytest.approx(conditions.speed_ratio, rel=1e-12)
    assert stream.mean_mass == pytest.approx(conditions.mean_molecular_mass, rel=1e-12)
    without = flight_conditions(TIME, position, velocity, WEATHER, anomalous_oxygen=False)
    assert "AnO" not in without.free_stream().species
    assert without.mass_density < conditions.mass_density


def test_mean_mass_and_speed_ratio_by_hand():
    conditions = flight_conditions_circular_orbit(PAPER_TIME, 400e3, 0.0, 0.0, WEATHER)
    n = conditions.atmosphere.number_densities
    mass = sum(n[k] * MOLAR_MASS_G[k] for k in n) / sum(n.values()) / (1000 * AVOGADRO)
    assert conditions.mean_molecular_mass == pytest.approx(mass, rel=1e-12)
    thermal = math.sqrt(2 * BOLTZMANN * conditions.atmosphere.temperature / mass)
    assert conditions.speed_ratio == pytest.approx(conditions.speed / thermal, rel=1e-12)


def test_circular_orbit_speed_as_adbsat():
    # sqrt(3.986004418e14 / (6378136.49 + 400e3)) = 7668.558 m/s
    assert circular_orbit_speed(400e3) == pytest.approx(7668.558, abs=1e-3)
    conditions = flight_conditions_circular_orbit(PAPER_TIME, 400e3, 0.0, 0.0, WEATHER)
    assert conditions.speed == circular_orbit_speed(400e3)
    assert conditions.relative_velocity_eci is None and conditions.velocity_ecef is None
    assert np.allclose(conditions.position_ecef, [6378137.0 + 400e3, 0.0, 0.0], atol=1e-6)
    # the atmosphere is NRLMSISE-00 at that point
    assert conditions.atmosphere == evaluate_atmosphere(PAPER_TIME, 400e3, 0.0, 0.0, WEATHER)


@pytest.mark.parametrize(
    "altitude, expected", [(100e3, 1.0), (200e3, 1.0), (300e3, 0.97), (400e3, 0.81)]
)
def test_validation_paper_langmuir_alphas(altitude, expected):
    conditions = flight_conditions_circular_orbit(PAPER_TIME, altitude, 0.0, 0.0, WEATHER)
    assert conditions.accommodation_model == "langmuir"
    assert conditions.alpha == pytest.approx(expected, abs=0.02 if expected < 1 else 0.005)


def test_atmosphere_is_evaluated_at_the_geodetic_point_of_the_state():
    position = geodetic_to_ecef(LAT, LON, ALT)
    conditions = flight_conditions(TIME, position, [0.0, 0.0, 7.6e3], WEATHER, frame="ecef")
    assert_same_atmosphere(conditions.atmosphere, evaluate_atmosphere(TIME, ALT, LAT, LON, WEATHER))


def test_timezone_aware_time_and_precomputed_orientation():
    position = np.array([6778e3, 0.0, 0.0])
    velocity = np.array([0.0, 7668.0, 0.0])
    aware = TIME.replace(tzinfo=dt.timezone.utc).astimezone(dt.timezone(dt.timedelta(hours=-5)))
    a = flight_conditions(TIME, position, velocity, WEATHER)
    b = flight_conditions(aware, position, velocity, WEATHER)
    c = flight_conditions(TIME, position, velocity, WEATHER, orientation=earth_orientation(TIME))
    for other in (b, c):
        assert np.array_equal(a.relative_velocity_ecef, other.relative_velocity_ecef)
        assert a.atmosphere == other.atmosphere
    assert a.time == b.time and a.time.tzinfo is dt.timezone.utc
    with pytest.raises(ValueError, match="orientation"):
        flight_conditions(
            TIME, position, velocity, WEATHER, orientation=earth_orientation(PAPER_TIME)
        )


def test_results_are_read_only_and_do_not_alias_inputs():
    position = np.array([6778e3, 0.0, 0.0])
    velocity = np.array([0.0, 7668.0, 0.0])
    conditions = flight_conditions(TIME, position, velocity, WEATHER)
    position[0] = 0.0
    assert conditions.position_eci[0] == 6778e3
    with pytest.raises(ValueError):
        conditions.relative_velocity_ecef[0] = 1.0


def test_as_dict_is_strict_json_in_si_units():
    conditions = flight_conditions(TIME, [6778e3, 0.0, 0.0], [0.0, 7668.0, 0.0], WEATHER)
    data = json.loads(json.dumps(conditions.as_dict(), allow_nan=False))
    assert data["altitude"] == pytest.approx(conditions.altitude)
    assert data["number_densities"]["O"] == conditions.atmosphere.number_densities["O"]
    assert data["units"]["mass_density"] == "kg/m^3"
    assert len(data["relative_velocity_ecef"]) == 3
    assert isinstance(conditions, FlightConditions)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(frame="j2000"), "frame"),
        (dict(position=[7e6, 0.0, float("nan")]), "position"),
        (dict(position=[7e6, 0.0]), "position"),
        (dict(position=[3e7, 0.0, 0.0]), "altitude"),
        (dict(velocity=[0.0, 7.6e3]), "velocity"),
        (dict(velocity=[0.0, float("inf"), 0.0]), "velocity"),
        (dict(wind=[1.0, 2.0]), "wind"),
        (dict(wind_frame="ned"), "wind_frame"),
        (dict(accommodation_model="cll"), "fixed, langmuir, goodman, sesam"),
        (dict(accommodation_model="fixed"), "alpha"),
        (dict(accommodation_options={"alpha": 0.5}), "alpha"),
        (dict(time="2015-01-19"), "time"),
        (dict(time=dt.datetime(1950, 1, 1)), "time"),
        (dict(space_weather=None), "space_weather"),
    ],
)
def test_bad_inputs_name_the_input(kwargs, name):
    args = dict(
        time=TIME, position=[6778e3, 0.0, 0.0], velocity=[0.0, 7668.0, 0.0], space_weather=WEATHER
    )
    args.update(kwargs)
    with pytest.raises(ValueError, match=name):
        flight_conditions(**args)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(altitude=1500e3), "altitude"),
        (dict(altitude=-5.0), "altitude"),
        (dict(latitude=2.0), "latitude"),
        (dict(speed=-1.0), "speed"),
    ],
)
def test_bad_circular_inputs_name_the_input(kwargs, name):
    args = dict(time=PAPER_TIME, altitude=400e3, latitude=0.0, longitude=0.0, space_weather=WEATHER)
    args.update(kwargs)
    with pytest.raises(ValueError, match=name):
        flight_conditions_circular_orbit(**args)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(position=np.array([7e6, np.nan, 0.0])), "position must be finite"),
        (dict(velocity=np.array([0.0, 7.6e3, np.inf])), "velocity must be finite"),
        (dict(position=np.zeros((1, 3))), "position must be a 3-vector"),
        (dict(velocity=np.array([0.0, 1e200, 1e200])), "speed must be finite"),
        (dict(wind=np.array([1.0, np.nan, 0.0])), "wind must be finite"),
        (dict(ut1_minus_utc=2.0), "ut1_minus_utc"),
        (dict(polar_motion=(1.0, 0.0)), "polar_motion"),
        (dict(precession_nutation="iau1980"), "precession_nutation"),
        (dict(precession_nutation_step=-1.0), "precession_nutation_step"),
        (dict(time=dt.datetime(2101, 1, 1, tzinfo=dt.timezone.utc)), "time"),
        (dict(orientation="R"), "orientation"),
    ],
)
def test_bad_per_message_inputs_name_the_input(kwargs, name):
    args = dict(
        time=TIME,
        position=np.array([6778e3, 0.0, 0.0]),
        velocity=np.array([0.0, 7668.0, 0.0]),
        space_weather=WEATHER,
    )
    args.update(kwargs)
    with pytest.raises(ValueError, match=name):
        flight_conditions(**args)


def same_bits(a, b) -> bool:
    return np.asarray(a, dtype=float).tobytes() == np.asarray(b, dtype=float).tobytes()


def test_conditions_are_values_that_do_not_alias_their_inputs():
    """The vector fields are read-only arrays of their own, the same object at every read;
    copies, dataclasses.replace, repr and as_dict see the same values; a second evaluation gives
    the same numbers."""
    position = np.array([6778e3, 1e3, 2e3])
    velocity = np.array([0.0, 7668.0, 10.0])
    aware = TIME.replace(tzinfo=dt.timezone.utc)
    first = flight_conditions(aware, position, velocity, WEATHER)
    conditions = flight_conditions(aware, position, velocity, WEATHER)
    duplicate = copy.copy(conditions)
    names = (
        "position_eci",
        "position_ecef",
        "velocity_eci",
        "velocity_ecef",
        "relative_velocity_eci",
        "relative_velocity_ecef",
    )
    for name in names:
        value = getattr(conditions, name)
        assert isinstance(value, np.ndarray) and value.shape == (3,) and value.dtype == np.float64
        assert not value.flags.writeable and getattr(conditions, name) is value
        assert same_bits(value, getattr(first, name)) and same_bits(getattr(duplicate, name), value)
        assert not np.shares_memory(value, position) and not np.shares_memory(value, velocity)
    assert same_bits(conditions.position_eci, position)
    assert same_bits(conditions.velocity_eci, velocity)
    position[0] = 0.0  # the caller's array changes, the conditions do not
    assert conditions.position_eci[0] == 6778e3
    rebuilt = dataclasses.replace(conditions, speed=1.0)
    assert rebuilt.speed == 1.0 and same_bits(rebuilt.position_ecef, first.position_ecef)
    assert rebuilt.speed_ratio == pytest.approx(first.speed_ratio / first.speed, rel=1e-15)
    assert conditions.speed == first.speed  # replace made a new value
    assert repr(conditions) == repr(first)
    assert conditions.as_dict() == first.as_dict()


def test_bad_options_are_refused_at_every_call():
    """Every call checks its options: a bad frame, step, alpha or space weather is refused the
    second time too, after good calls with the same arguments otherwise; equivalent spellings
    of good options (upper case, a list for polar motion, an int step) give the same numbers."""
    aware = TIME.replace(tzinfo=dt.timezone.utc)
    position, velocity = np.array([6778e3, 0.0, 0.0]), np.array([0.0, 7668.0, 0.0])
    good = flight_conditions(
        aware, position, velocity, WEATHER, frame="eci", precession_nutation_step=60.0
    )
    for _ in range(2):
        with pytest.raises(ValueError, match="frame"):
            flight_conditions(
                aware, position, velocity, WEATHER, frame="gcrf", precession_nutation_step=60.0
            )
        with pytest.raises(ValueError, match="precession_nutation_step"):
            flight_conditions(aware, position, velocity, WEATHER, precession_nutation_step=7200.0)
        with pytest.raises(ValueError, match="alpha"):
            flight_conditions(
                aware,
                position,
                velocity,
                WEATHER,
                accommodation_model="fixed",
                accommodation_options={"alpha": 1.5},
            )
        with pytest.raises(ValueError, match="space_weather"):
            flight_conditions(
                aware, position, velocity, (121.7, 138.1, 4.0), precession_nutation_step=60.0
            )
    again = flight_conditions(
        aware,
        position,
        velocity,
        WEATHER,
        frame="ECI",
        polar_motion=[0.0, 0.0],
        precession_nutation_step=60,
    )
    assert same_bits(again.relative_velocity_eci, good.relative_velocity_eci)
    assert again.as_dict() == good.as_dict()


def test_options_checked_once_give_the_same_conditions():
    """evaluate_flight_conditions with options checked by conditions_options gives what
    flight_conditions gives with the same options, bit for bit; a bad option is refused when the
    options are made, naming it."""
    r = np.array([6778137.0, 1200.0, -3400.0])
    v = np.array([-5.0, 6000.0, 4800.0])
    options = dict(
        frame="ecef",
        earth_rotation=True,
        wind=(30.0, -10.0, 2.0),
        wind_frame="enu",
        anomalous_oxygen=False,
        accommodation_model="goodman",
        precession_nutation="iau2000b",
        precession_nutation_step=60.0,
    )
    checked = conditions_options(**options)
    once = evaluate_flight_conditions(TIME, r, v, WEATHER, checked)
    every = flight_conditions(TIME, r, v, WEATHER, **options)
    assert json.dumps(once.as_dict()) == json.dumps(every.as_dict())
    for name, value, named in (
        ("frame", "itrf", "frame"),
        ("wind_frame", "ned", "wind_frame"),
        ("wind", (1.0, math.nan, 0.0), "wind"),
        ("accommodation_model", "magic", "accommodation model"),
        ("precession_nutation_step", -1.0, "precession_nutation_step"),
    ):
        with pytest.raises(ValueError, match=named):
            conditions_options(**{**options, name: value})
