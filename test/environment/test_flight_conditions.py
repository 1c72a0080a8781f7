"""Flight conditions: frames, relative wind, free stream, ADBSat parity, validation."""

import dataclasses
import datetime as dt
import json
import math

import numpy as np
import pytest

from adbsat_ros.environment.atmosphere import SpaceWeather, evaluate_atmosphere
from adbsat_ros.environment.earth_frames import EARTH_ROTATION_RATE, earth_orientation, ecef_to_eci
from adbsat_ros.environment.flight_conditions import (
    FlightConditions,
    circular_orbit_speed,
    flight_conditions,
    flight_conditions_circular_orbit,
    interpolated_flight_conditions,
)
from adbsat_ros.environment.geodetic import enu_to_ecef_matrix, geodetic_to_ecef
from adbsat_ros.physics.constants import AVOGADRO, BOLTZMANN, EARTH_MU, MOLAR_MASS_G
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


# ------------------------------------------------- the per-message path against a plain reference
def erfa_orientation(time, ut1_minus_utc, polar_motion, step, model="iau2006a"):
    """GCRS -> ITRS matrix and ECEF rotation vector straight from pyerfa's own time scales."""
    import warnings

    import erfa

    naive = time.astimezone(dt.timezone.utc).replace(tzinfo=None) if time.tzinfo else time
    seconds = naive.second + naive.microsecond * 1e-6
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", erfa.ErfaWarning)  # "dubious year" past ERFA's table
        u1, u2 = erfa.dtf2d(
            "UTC", naive.year, naive.month, naive.day, naive.hour, naive.minute, seconds
        )
        t1, t2 = erfa.taitt(*erfa.utctai(u1, u2))
        b1, b2 = erfa.utcut1(u1, u2, ut1_minus_utc)
    c2i = {"iau2006a": erfa.c2i06a, "iau2000b": erfa.c2i00b}[model]
    if step > 0.0:
        step_days = step / 86400.0
        bucket = math.floor(((t1 - 2451545.0) + t2) / step_days)
        q = c2i(2451545.0, (bucket + 0.5) * step_days)
    else:
        q = c2i(t1, t2)
    if polar_motion == (0.0, 0.0):
        polar = np.eye(3)  # no polar motion given: the TIRS, no TIO locator either (module notes)
    else:
        polar = erfa.pom00(polar_motion[0], polar_motion[1], erfa.sp00(t1, t2))
    return erfa.c2tcio(q, erfa.era00(b1, b2), polar), polar @ np.array(
        [0.0, 0.0, EARTH_ROTATION_RATE]
    )


def reference_conditions(
    time,
    position,
    velocity,
    weather,
    *,
    frame,
    earth_rotation,
    wind,
    wind_frame,
    anomalous_oxygen,
    model,
    options,
    ut1_minus_utc,
    polar_motion,
    step,
):
    """Flight conditions computed the plain way: pyerfa matrices, numpy 3-vectors, public checks."""
    import erfa

    from adbsat_ros.environment.accommodation import accommodation

    matrix, omega = erfa_orientation(time, ut1_minus_utc, polar_motion, step)
    position, velocity = np.array(position, dtype=float), np.array(velocity, dtype=float)
    if frame == "eci":
        r_eci, v_eci = position, velocity
        r_ecef = matrix @ r_eci
        v_ecef = matrix @ v_eci - np.cross(omega, r_ecef)
    else:
        r_ecef, v_ecef = position, velocity
        r_eci = matrix.T @ r_ecef
        v_eci = matrix.T @ (v_ecef + np.cross(omega, r_ecef))
    lon, lat, alt = erfa.gc2gd(1, r_ecef)
    atmosphere = evaluate_atmosphere(
        time, alt, lat, lon, weather, anomalous_oxygen=anomalous_oxygen
    )
    wind_ecef = np.zeros(3)
    if wind is not None:
        wind_ecef = (
            enu_to_ecef_matrix(lat, lon) @ np.asarray(wind)
            if wind_frame == "enu"
            else np.asarray(wind)
        )
    if earth_rotation:
        rel_ecef = v_ecef - wind_ecef
        rel_eci = matrix.T @ rel_ecef
    else:
        rel_eci = v_eci - matrix.T @ wind_ecef
        rel_ecef = matrix @ rel_eci
    speed = float(np.linalg.norm(rel_ecef))
    flow = FreeStream(
        speed=speed,
        temperature=atmosphere.temperature,
        number_densities=atmosphere.mixture_number_densities,
        density=atmosphere.mass_density,
    )
    return dict(
        position_eci=r_eci,
        position_ecef=r_ecef,
        velocity_eci=v_eci,
        velocity_ecef=v_ecef,
        relative_velocity_eci=rel_eci,
        relative_velocity_ecef=rel_ecef,
        latitude=float(lat),
        longitude=float(lon),
        altitude=float(alt),
        speed=speed,
        atmosphere=atmosphere,
        alpha=accommodation(model, atmosphere, speed, **(options or {})),
        flow=flow,
    )


def random_case(rng):
    """A random state, instant and set of options (LEO radii, every frame/wind/model option).

    Times from 1972 on: before, UTC had rubber seconds and ERFA's utctai/utcut1 (the reference)
    take TAI - UTC at the instant, the module at noon (TT and UT1 then differ by up to 1 ms).
    """
    time = dt.datetime(1972, 1, 1) + dt.timedelta(
        days=int(rng.integers(0, 128 * 365)),
        seconds=int(rng.integers(0, 86400)),
        microseconds=int(rng.integers(0, 10**6)),
    )
    zone = rng.integers(0, 3)
    if zone == 1:
        time = time.replace(tzinfo=dt.timezone.utc)
    elif zone == 2:
        time = time.replace(tzinfo=dt.timezone.utc).astimezone(
            dt.timezone(dt.timedelta(hours=5, minutes=30))
        )
    direction = rng.normal(size=3)
    position = direction / np.linalg.norm(direction) * rng.uniform(6.6e6, 7.2e6)
    velocity = rng.normal(size=3) * 5e3
    model = ("fixed", "langmuir", "goodman", "sesam")[rng.integers(0, 4)]
    wind = None if rng.random() < 0.4 else rng.normal(size=3) * 100.0
    if rng.random() < 0.3 and wind is not None:
        wind = wind.tolist()  # a list goes through the general input path
    arcsec = math.pi / 180 / 3600
    precise = rng.random() < 0.3
    return dict(
        time=time,
        position=position if rng.random() < 0.8 else position.tolist(),
        velocity=velocity,
        weather=SpaceWeather(
            f107=rng.uniform(60, 250),
            f107a=rng.uniform(60, 250),
            ap=rng.uniform(0, 50),
            ap_history=tuple(rng.uniform(0, 100, 7)) if rng.random() < 0.2 else None,
        ),
        frame=("eci", "ecef")[rng.integers(0, 2)],
        earth_rotation=bool(rng.random() < 0.7),
        wind=wind,
        wind_frame=("enu", "ecef")[rng.integers(0, 2)],
        anomalous_oxygen=bool(rng.random() < 0.7),
        model=model,
        options={"alpha": float(rng.uniform(0, 1))} if model == "fixed" else None,
        ut1_minus_utc=float(rng.uniform(-0.9, 0.9)) if precise else 0.0,
        polar_motion=tuple(rng.uniform(-0.5, 0.5, 2) * arcsec) if precise else (0.0, 0.0),
        step=(0.0, 60.0, 60.0, 1.0)[rng.integers(0, 4)],
    )


def assert_close_vector(actual, expected, name, rel=1e-12):
    assert actual.shape == (3,) and not actual.flags.writeable, name
    error = np.linalg.norm(actual - expected)
    assert error <= rel * np.linalg.norm(expected) + 1e-300, (name, actual, expected)


def test_per_message_path_equals_plain_reference_over_random_states():
    """flight_conditions (float arithmetic, memoised per-day and precession-nutation terms, cheap
    FreeStream construction) agrees with the plain pyerfa/numpy computation to 1e-12 relative."""
    rng = np.random.default_rng(20240611)
    for _ in range(300):
        case = random_case(rng)
        expected = reference_conditions(
            case["time"],
            case["position"],
            case["velocity"],
            case["weather"],
            frame=case["frame"],
            earth_rotation=case["earth_rotation"],
            wind=case["wind"],
            wind_frame=case["wind_frame"],
            anomalous_oxygen=case["anomalous_oxygen"],
            model=case["model"],
            options=case["options"],
            ut1_minus_utc=case["ut1_minus_utc"],
            polar_motion=case["polar_motion"],
            step=case["step"],
        )
        actual = flight_conditions(
            case["time"],
            case["position"],
            case["velocity"],
            case["weather"],
            frame=case["frame"],
            earth_rotation=case["earth_rotation"],
            wind=case["wind"],
            wind_frame=case["wind_frame"],
            anomalous_oxygen=case["anomalous_oxygen"],
            accommodation_model=case["model"],
            accommodation_options=case["options"],
            ut1_minus_utc=case["ut1_minus_utc"],
            polar_motion=case["polar_motion"],
            precession_nutation_step=case["step"],
        )
        for name in (
            "position_eci",
            "position_ecef",
            "velocity_eci",
            "velocity_ecef",
            "relative_velocity_eci",
            "relative_velocity_ecef",
        ):
            assert_close_vector(getattr(actual, name), expected[name], name)
        assert actual.latitude == pytest.approx(expected["latitude"], abs=1e-12)
        assert actual.longitude == pytest.approx(expected["longitude"], abs=1e-12)
        for name in ("altitude", "speed"):
            assert getattr(actual, name) == pytest.approx(expected[name], rel=1e-12), name
        assert_same_atmosphere(actual.atmosphere, expected["atmosphere"], rel=1e-12)
        assert actual.atmosphere.anomalous_oxygen == case["anomalous_oxygen"]
        assert actual.alpha == pytest.approx(expected["alpha"], rel=1e-12)
        time = case["time"] if case["time"].tzinfo else case["time"].replace(tzinfo=dt.timezone.utc)
        assert actual.time == time and actual.time.tzinfo is dt.timezone.utc
        flow, reference_flow = actual.free_stream(), expected["flow"]
        assert flow.species == reference_flow.species
        assert np.array_equal(flow.species_masses, reference_flow.species_masses)
        for name in ("species_number_densities", "speed", "temperature", "density"):
            assert getattr(flow, name) == pytest.approx(getattr(reference_flow, name), rel=1e-12), (
                name
            )
        assert flow.mean_mass == pytest.approx(reference_flow.mean_mass, rel=1e-12)
        assert flow.dynamic_pressure() == pytest.approx(
            reference_flow.dynamic_pressure(), rel=1e-12
        )
        assert actual.speed_ratio == pytest.approx(reference_flow.speed_ratio, rel=1e-12)


def test_free_stream_of_mixture_equals_the_checked_constructor():
    conditions = flight_conditions(TIME, [6778e3, 0.0, 0.0], [0.0, 7668.0, 0.0], WEATHER)
    atmosphere = conditions.atmosphere
    species = atmosphere.mixture_species
    values = [atmosphere.number_densities[s] for s in species]
    fast = FreeStream.of_mixture(7000.0, 900.0, species, values, 3e-12)
    checked = FreeStream(7000.0, 900.0, dict(zip(species, values)), density=3e-12)
    assert fast == checked
    for name in (
        "species",
        "species_number_densities",
        "species_masses",
        "mean_mass",
        "mass_density",
        "speed_ratio",
    ):
        assert np.array_equal(getattr(fast, name), getattr(checked, name)), name
    assert fast.dynamic_pressure() == checked.dynamic_pressure()
    assert fast.species_number_densities.dtype == np.float64
    with pytest.raises(ValueError):
        fast.species_masses[0] = 1.0  # shared between free streams: read-only


@pytest.mark.parametrize(
    "args, name",
    [
        ((0.0, 900.0, ("O", "N2"), [1e14, 1e13], 1e-12), "speed"),
        ((float("inf"), 900.0, ("O", "N2"), [1e14, 1e13], 1e-12), "speed"),
        ((7e3, float("nan"), ("O", "N2"), [1e14, 1e13], 1e-12), "temperature"),
        ((7e3, 900.0, ("O", "N2"), [1e14, -1.0], 1e-12), "number density of N2"),
        ((7e3, 900.0, ("O", "N2"), [float("nan"), 1.0], 1e-12), "number density of O"),
        ((7e3, 900.0, ("O", "N2"), [0.0, 0.0], 1e-12), "at least one species"),
        ((7e3, 900.0, ("O", "Xe"), [1e14, 1e13], 1e-12), "unknown species"),
        ((7e3, 900.0, ("O", "N2"), [1e14, 1e13], -1.0), "density"),
    ],
)
def test_free_stream_of_mixture_refuses_what_the_constructor_refuses(args, name):
    with pytest.raises(ValueError, match=name):
        FreeStream.of_mixture(*args)


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


def test_other_array_types_give_the_same_conditions():
    position = np.array([6778e3, 1e3, 2e3])
    velocity = np.array([0.0, 7668.0, 10.0])
    a = flight_conditions(TIME, position, velocity, WEATHER)
    for p, v in (
        (position.tolist(), tuple(velocity)),
        (position.astype(np.float32).astype(np.float64), velocity),
        (position.astype(np.int64), velocity.astype(np.float32).astype(np.float64)),
    ):
        b = flight_conditions(TIME, p, v, WEATHER)
        assert_close_vector(
            b.relative_velocity_ecef, a.relative_velocity_ecef, "relative", rel=1e-6
        )
    b = flight_conditions(TIME, position.astype(np.float32), velocity.astype(np.float32), WEATHER)
    assert_close_vector(b.position_ecef, a.position_ecef, "position_ecef", rel=1e-7)


# ------------------------------------------------------------------ the per-message fast path
def per_message_case(rng):
    """A random case as the node passes it: an aware UTC time and float64 arrays."""
    case = random_case(rng)
    time = case["time"]
    case["time"] = (
        time.astimezone(dt.timezone.utc) if time.tzinfo else time.replace(tzinfo=dt.timezone.utc)
    )
    case["position"] = np.array(case["position"], dtype=float)
    if case["wind"] is not None:
        case["wind"] = np.array(case["wind"], dtype=float)
    return case


def call(case, **changes):
    args = dict(
        time=case["time"],
        position=case["position"],
        velocity=case["velocity"],
        space_weather=case["weather"],
        frame=case["frame"],
        earth_rotation=case["earth_rotation"],
        wind=case["wind"],
        wind_frame=case["wind_frame"],
        anomalous_oxygen=case["anomalous_oxygen"],
        accommodation_model=case["model"],
        accommodation_options=case["options"],
        ut1_minus_utc=case["ut1_minus_utc"],
        polar_motion=case["polar_motion"],
        precession_nutation_step=case["step"],
    )
    args.update(changes)
    return flight_conditions(**args)


def same_bits(a, b) -> bool:
    return np.asarray(a, dtype=float).tobytes() == np.asarray(b, dtype=float).tobytes()


def test_per_message_fast_path_equals_the_checked_path_bit_for_bit(monkeypatch):
    """A repeated call with the options of an earlier one skips the option checks (their checked
    form is looked up) and unpacks the arrays itself: every field and the free stream equal, bit
    for bit, those of the checked path (inputs as lists, which only it takes)."""
    import adbsat_ros.environment.flight_conditions as module

    def no_checked_path(*args):
        raise AssertionError("the per-message case took the checked path")

    rng = np.random.default_rng(4711)
    for _ in range(150):
        case = per_message_case(rng)
        wind = None if case["wind"] is None else case["wind"].tolist()
        # the checked path (which remembers the options)
        expected = call(
            case, position=case["position"].tolist(), velocity=case["velocity"].tolist(), wind=wind
        )
        with monkeypatch.context() as patch:
            patch.setattr(module, "_checked_flight_conditions", no_checked_path)
            actual = call(case)
        for f in dataclasses.fields(FlightConditions):
            a, b = getattr(actual, f.name), getattr(expected, f.name)
            if isinstance(a, np.ndarray):
                assert same_bits(a, b) and not a.flags.writeable, f.name
            elif f.name == "atmosphere":
                assert a == b and a.mean_mass == b.mean_mass
            else:
                assert a == b and type(a) is type(b), f.name
        flow, reference = actual.free_stream(), expected.free_stream()
        assert flow == reference
        for name in ("species_number_densities", "species_masses", "mean_mass", "speed_ratio"):
            assert same_bits(getattr(flow, name), getattr(reference, name)), name
        assert flow.dynamic_pressure() == reference.dynamic_pressure()


def test_per_message_free_stream_equals_the_checked_constructor():
    rng = np.random.default_rng(99)
    for _ in range(50):
        conditions = call(per_message_case(rng))
        atmosphere = conditions.atmosphere
        flow = conditions.free_stream()
        species = atmosphere.mixture_species
        checked = FreeStream(
            conditions.speed,
            atmosphere.temperature,
            {name: atmosphere.number_densities[name] for name in species},
            density=atmosphere.mass_density,
        )
        assert flow == checked and flow.species == species
        for name in (
            "species_number_densities",
            "species_masses",
            "mean_mass",
            "mass_density",
            "speed_ratio",
            "thermal_speed",
            "specific_gas_constant",
        ):
            assert same_bits(getattr(flow, name), getattr(checked, name)), name
        assert same_bits(flow.mass_fractions(), checked.mass_fractions())
        assert same_bits(flow.species_speed_ratios(), checked.species_speed_ratios())
        assert flow.species_number_densities.dtype == np.float64
        assert flow.mean_mass == conditions.mean_molecular_mass == atmosphere.mean_mass
        # the mean mass is summed in species order; numpy's dot and sum differ by rounding only
        n, m = checked.species_number_densities, checked.species_masses
        assert flow.mean_mass == pytest.approx(float(np.dot(n, m) / n.sum()), rel=1e-15, abs=0.0)
        assert (
            dataclasses.replace(flow, speed=2.0 * flow.speed).speed_ratio == 2.0 * flow.speed_ratio
        )
        # each free stream owns its number densities
        flow.number_densities["O"] = -1.0
        assert (
            conditions.free_stream().number_densities["O"]
            == atmosphere.number_densities["O"]
            >= 0.0
        )


def test_per_message_conditions_behave_as_constructed_ones():
    """The vector fields made on first read: read-only copies, the same object at every read, and
    dataclasses.replace, repr and copy see them as fields."""
    import copy

    position = np.array([6778e3, 1e3, 2e3])
    velocity = np.array([0.0, 7668.0, 10.0])
    aware = TIME.replace(tzinfo=dt.timezone.utc)
    first = flight_conditions(aware, position, velocity, WEATHER)
    conditions = flight_conditions(aware, position, velocity, WEATHER)  # the per-message path
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
    assert same_bits(conditions.position_eci, position) and same_bits(
        conditions.velocity_eci, velocity
    )
    fresh = flight_conditions(aware, position, velocity, WEATHER)
    assert same_bits(
        [getattr(fresh, name) for name in names], [getattr(first, name) for name in names]
    )
    rebuilt = dataclasses.replace(flight_conditions(aware, position, velocity, WEATHER), speed=1.0)
    assert rebuilt.speed == 1.0 and same_bits(rebuilt.position_ecef, first.position_ecef)
    assert repr(flight_conditions(aware, position, velocity, WEATHER)) == repr(first)
    assert flight_conditions(aware, position, velocity, WEATHER).as_dict() == first.as_dict()
    with pytest.raises(AttributeError, match="no attribute 'position_eci'"):
        object.__new__(FlightConditions).position_eci


def test_remembered_options_never_skip_the_checks_of_bad_ones():
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
    import adbsat_ros.environment.flight_conditions as module

    for i in range(200):  # a new UT1 - UTC at every call: the remembered options stay few
        flight_conditions(aware, position, velocity, WEATHER, ut1_minus_utc=i * 1e-3)
    assert len(module._CHECKED_OPTIONS) <= module._MAX_CHECKED_OPTIONS


# ------------------------------------------------------------------ interpolated flight conditions
def _orbit_point(rng, radius, radial_speed):
    """A point on a random inclined circular orbit, with a radial velocity added [m, m/s]."""
    theta, inclination = rng.uniform(0.0, 2.0 * math.pi), rng.uniform(0.0, math.pi)
    along = np.array(
        [
            math.cos(theta),
            math.sin(theta) * math.cos(inclination),
            math.sin(theta) * math.sin(inclination),
        ]
    )
    across = np.array(
        [
            -math.sin(theta),
            math.cos(theta) * math.cos(inclination),
            math.cos(theta) * math.sin(inclination),
        ]
    )
    speed = math.sqrt(EARTH_MU / radius)
    return radius * along, speed * across + radial_speed * along


@pytest.mark.parametrize("step, density_rel", [(0.01, 1e-8), (0.1, 1e-6)])
def test_interpolated_conditions_match_the_exact_ones_between_two_knots(step, density_rel):
    """Between exact conditions h seconds apart along a first-order propagated state, linear
    interpolation errs by about (h v / L)^2 / 8 for fields varying over L along the path: at
    350 km (clear of NRLMSISE-00's steps, see the next test), with up to 150 m/s of radial
    speed, the density error is ~2e-9 at 10 ms and ~2e-7 at 100 ms (h^2, as it should)."""
    rng = np.random.default_rng(7)
    weather = SpaceWeather(150.0, 150.0, 4.0)
    start = dt.datetime(2026, 3, 1, tzinfo=dt.timezone.utc)
    for _ in range(60):
        position, velocity = _orbit_point(rng, 6378137.0 + 350e3, rng.uniform(-150.0, 150.0))
        t0 = start + dt.timedelta(seconds=float(rng.uniform(0.0, 86400.0)))
        a = flight_conditions(t0, position, velocity, weather)
        b = flight_conditions(
            t0 + dt.timedelta(seconds=step), position + velocity * step, velocity, weather
        )
        f = float(rng.uniform())
        exact = flight_conditions(
            t0 + dt.timedelta(seconds=f * step), position + velocity * (f * step), velocity, weather
        )
        mixed = interpolated_flight_conditions(a, b, f, exact.time)
        assert mixed.time == exact.time
        assert mixed.mass_density == pytest.approx(exact.mass_density, rel=density_rel)
        assert mixed.temperature == pytest.approx(exact.temperature, rel=density_rel / 10)
        assert mixed.speed_ratio == pytest.approx(exact.speed_ratio, rel=density_rel / 10)
        assert mixed.speed == pytest.approx(exact.speed, rel=1e-10)
        assert mixed.alpha == pytest.approx(exact.alpha, rel=density_rel)
        assert mixed.mean_molecular_mass == pytest.approx(
            exact.mean_molecular_mass, rel=density_rel
        )
        # positions are linear in time; the ECEF ones differ by the exact path's UTC rounding to 1 us
        np.testing.assert_allclose(mixed.position_eci, exact.position_eci, rtol=0, atol=1e-6)
        np.testing.assert_allclose(mixed.position_ecef, exact.position_ecef, rtol=0, atol=2e-3)
        np.testing.assert_allclose(
            mixed.relative_velocity_eci, exact.relative_velocity_eci, rtol=0, atol=1e-9
        )
        assert mixed.altitude == pytest.approx(exact.altitude, abs=0.02)
        assert mixed.latitude == pytest.approx(exact.latitude, abs=1e-8)
        assert math.remainder(mixed.longitude - exact.longitude, 2 * math.pi) == pytest.approx(
            0.0, abs=1e-7
        )
        flow = mixed.free_stream()  # a free stream of the interpolated gas
        assert flow.density == mixed.mass_density and flow.temperature == mixed.temperature


def test_interpolated_conditions_defer_what_a_wrench_does_not_read_and_agree_with_it_bit_for_bit():
    """interpolated_flight_conditions makes the speed, speed ratio, mean mass, alpha, relative
    velocity and free stream at once and the geodetic position, the atmosphere and the other vectors
    on first read. Both are the same mixes of the knots: the free stream equals one made from the
    deferred atmosphere (FreeStream.of_mixture's own checks and sums), the speed is the norm of the
    mixed ECEF relative velocity, and so on, to the last bit, whatever is read first."""
    rng = np.random.default_rng(11)
    weather = SpaceWeather(150.0, 150.0, 4.0)
    for case in range(12):
        position, velocity = _orbit_point(rng, 6378137.0 + 350e3, rng.uniform(-150.0, 150.0))
        model = ("fixed", "langmuir", "sesam")[case % 3]
        options = dict(
            anomalous_oxygen=bool(case % 2),
            accommodation_model=model,
            accommodation_options={"alpha": 0.9} if model == "fixed" else None,
        )
        a = flight_conditions(TIME, position, velocity, weather, **options)
        b = flight_conditions(
            TIME + dt.timedelta(seconds=0.01),
            position + 0.01 * velocity,
            velocity,
            weather,
            **options,
        )
        f = float(rng.uniform(0.01, 0.99))
        first, second = (interpolated_flight_conditions(a, b, f, TIME) for _ in range(2))
        assert "atmosphere" not in first.__dict__ and "latitude" not in first.__dict__  # deferred
        flow = first.free_stream()
        speed, alpha = first.speed, first.alpha
        relative = (first.relative_velocity_floats("eci"), first.relative_velocity_floats("ecef"))
        atmosphere = first.atmosphere  # now the deferred fields
        reference = FreeStream.of_mixture(
            speed,
            atmosphere.temperature,
            atmosphere.mixture_species,
            atmosphere._mixture_densities,
            atmosphere.mass_density,
        )
        for name in (
            "speed",
            "temperature",
            "density",
            "mean_mass",
            "speed_ratio",
            "number_densities",
        ):
            assert getattr(flow, name) == getattr(reference, name), name
        assert first.mean_molecular_mass == atmosphere.mean_mass
        ex, ey, ez = first.relative_velocity_ecef.tolist()
        assert speed == math.sqrt(ex * ex + ey * ey + ez * ez)
        assert first.speed_ratio == speed / math.sqrt(
            2.0 * BOLTZMANN * atmosphere.temperature / atmosphere.mean_mass
        )
        assert relative == (tuple(first.relative_velocity_eci.tolist()), (ex, ey, ez))
        with pytest.raises(ValueError):
            first.relative_velocity_floats("enu")  # not a frame of the conditions
        assert alpha == (1.0 - f) * a.alpha + f * b.alpha
        # the other order: deferred fields first, then what a wrench reads
        assert second.latitude == first.latitude and second.altitude == first.altitude
        assert second.atmosphere.number_densities == atmosphere.number_densities
        assert second.free_stream().number_densities == flow.number_densities
        assert second.speed_ratio == first.speed_ratio
        for name in ("position_eci", "position_ecef", "velocity_eci", "velocity_ecef"):
            np.testing.assert_array_equal(getattr(second, name), getattr(first, name))
        assert repr(second) == repr(first) and second.as_dict() == first.as_dict()


def test_interpolated_conditions_without_a_relative_velocity_are_made_whole_at_once():
    """Conditions that know only a speed (the circular-orbit recipe) have no vectors to mix for
    the wind: everything is interpolated at once, the speed linearly."""
    weather = SpaceWeather(150.0, 150.0, 4.0)
    a = flight_conditions_circular_orbit(TIME, 300e3, LAT, LON, weather)
    b = flight_conditions_circular_orbit(TIME, 301e3, LAT, LON, weather)
    mixed = interpolated_flight_conditions(a, b, 0.25, TIME)
    assert "atmosphere" in mixed.__dict__ and mixed.relative_velocity_eci is None
    assert mixed.speed == 0.75 * a.speed + 0.25 * b.speed
    assert mixed.mass_density == 0.75 * a.mass_density + 0.25 * b.mass_density
    assert mixed.free_stream().density == mixed.mass_density


def test_interpolation_takes_the_short_way_round_the_antimeridian():
    weather = SpaceWeather(150.0, 150.0, 4.0)
    r, v = 6378137.0 + 350e3, 7700.0
    position = np.array([-r, 1.0, 0.0])  # just east of -180 deg in ECEF, moving west across it
    velocity = np.array([0.0, -v, 0.0])
    a = flight_conditions(TIME, position, velocity, weather, frame="ecef")
    b = flight_conditions(
        TIME + dt.timedelta(seconds=0.01),
        position + 0.01 * velocity,
        velocity,
        weather,
        frame="ecef",
    )
    assert a.longitude > 3.0 and b.longitude < -3.0  # the two knots on either side of +-180 deg
    exact = flight_conditions(
        TIME + dt.timedelta(seconds=0.005),
        position + 0.005 * velocity,
        velocity,
        weather,
        frame="ecef",
    )
    mixed = interpolated_flight_conditions(a, b, 0.5, exact.time)
    assert abs(mixed.longitude) > 3.14  # not the mean of +pi and -pi, which would be 0
    assert math.remainder(mixed.longitude - exact.longitude, 2 * math.pi) == pytest.approx(
        0.0, abs=1e-9
    )
    assert -math.pi <= mixed.longitude <= math.pi
    assert mixed.mass_density == pytest.approx(exact.mass_density, rel=1e-9)


def test_interpolation_over_a_pole_keeps_the_geodetic_position_exact():
    """Over a pole the latitude turns back and the longitude jumps by 180 deg between two knots:
    the geodetic position comes from the interpolated ECEF position, not from the knots' angles."""
    weather = SpaceWeather(150.0, 150.0, 4.0)
    r, v = 6378137.0 + 350e3, 7700.0
    position = np.array([-30.0, 0.0, r])  # 30 m short of the north pole, moving over it along +x
    velocity = np.array([v, 0.0, 0.0])
    a = flight_conditions(TIME, position, velocity, weather, frame="ecef")
    b = flight_conditions(
        TIME + dt.timedelta(seconds=0.01),
        position + 0.01 * velocity,
        velocity,
        weather,
        frame="ecef",
    )
    assert abs(math.remainder(a.longitude - b.longitude, 2 * math.pi)) == pytest.approx(math.pi)
    for f in (0.1, 0.3, 0.6):
        exact = flight_conditions(
            TIME + dt.timedelta(seconds=0.01 * f),
            position + 0.01 * f * velocity,
            velocity,
            weather,
            frame="ecef",
        )
        mixed = interpolated_flight_conditions(a, b, f, exact.time)
        assert mixed.latitude == pytest.approx(exact.latitude, abs=1e-12)
        assert math.remainder(mixed.longitude - exact.longitude, 2 * math.pi) == pytest.approx(
            0.0, abs=1e-9
        )
        assert mixed.altitude == pytest.approx(exact.altitude, abs=1e-6)


def test_interpolation_ends_are_the_knots_and_mixed_options_are_refused():
    weather = SpaceWeather(150.0, 150.0, 4.0)
    position, velocity = np.array([6378137.0 + 350e3, 0.0, 0.0]), np.array([0.0, 7700.0, 0.0])
    a = flight_conditions(TIME, position, velocity, weather)
    b = flight_conditions(
        TIME + dt.timedelta(seconds=0.01), position + 0.01 * velocity, velocity, weather
    )
    for weight, end in ((0.0, a), (1.0, b)):
        mixed = interpolated_flight_conditions(a, b, weight, end.time)
        assert mixed.mass_density == end.mass_density
        assert mixed.atmosphere.number_densities == end.atmosphere.number_densities
        assert mixed.speed_ratio == pytest.approx(end.speed_ratio, rel=1e-15)
        np.testing.assert_allclose(mixed.position_eci, end.position_eci, rtol=1e-15)
    other = flight_conditions(
        TIME,
        position,
        velocity,
        weather,
        accommodation_model="fixed",
        accommodation_options={"alpha": 0.9},
    )
    with pytest.raises(ValueError, match="different options"):
        interpolated_flight_conditions(a, other, 0.5, TIME)


def test_nrlmsise00_steps_at_300_km_and_interpolation_stays_between_the_knots():
    """NRLMSISE-00 switches some corrections at fixed altitudes: at exactly 300 km its O density
    steps (here by 3e-5 of itself, ten times its change over the same 0.2 m of altitude below), and
    N and H with it. Evaluated at every stamp the wrench steps at that altitude; interpolated
    between knots, the step is spread over the one knot interval that crosses it."""
    weather = SpaceWeather(150.0, 150.0, 4.0)
    below = evaluate_atmosphere(TIME, 299.9999e3, LAT, LON, weather)
    above = evaluate_atmosphere(TIME, 300.0001e3, LAT, LON, weather)
    smooth = evaluate_atmosphere(TIME, 299.9997e3, LAT, LON, weather)  # the trend just below
    trend = below.number_densities["O"] - smooth.number_densities["O"]  # O change per 0.2 m
    step = above.number_densities["O"] - below.number_densities["O"]
    assert abs(step) > 5.0 * abs(trend)  # a step, not the altitude trend
    # a descending state whose knots straddle 300 km
    position = geodetic_to_ecef(LAT, LON, 300.00005e3)  # 5 cm above 300 km
    down = -position / np.linalg.norm(position)
    velocity = 0.1 * down / 0.01  # 10 cm per 10 ms, straight down (ECEF, at rest otherwise)
    a = flight_conditions(TIME, position, velocity, weather, frame="ecef")
    b = flight_conditions(
        TIME + dt.timedelta(seconds=0.01),
        position + 0.01 * velocity,
        velocity,
        weather,
        frame="ecef",
    )
    assert a.altitude > 300e3 > b.altitude
    for f in (0.25, 0.5, 0.75):
        mixed = interpolated_flight_conditions(a, b, f, TIME)
        o = mixed.atmosphere.number_densities["O"]
        assert min(a.atmosphere.number_densities["O"], b.atmosphere.number_densities["O"]) <= o
        assert o <= max(a.atmosphere.number_densities["O"], b.atmosphere.number_densities["O"])
