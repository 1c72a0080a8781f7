"""Flight conditions against a plain reference: pyerfa matrices, numpy vectors, public checks.

Over random states, instants and options, :func:`flight_conditions` (float arithmetic, memoised
per-day and precession-nutation terms) agrees with a computation written the plain way; its free
stream is the one FreeStream's constructor makes of the atmosphere; inputs as lists or arrays
give the same bits.
"""

import dataclasses
import datetime as dt
import math
import warnings

import erfa
import numpy as np
import pytest

from adbsat_ros.environment.accommodation import accommodation
from adbsat_ros.environment.atmosphere import SpaceWeather, evaluate_atmosphere
from adbsat_ros.environment.earth_frames import EARTH_ROTATION_RATE
from adbsat_ros.environment.flight_conditions import FlightConditions, flight_conditions
from adbsat_ros.environment.geodetic import enu_to_ecef_matrix
from adbsat_ros.physics.freestream import FreeStream

TIME = dt.datetime(2015, 1, 19, 6, 30)
WEATHER = SpaceWeather(f107=121.7, f107a=138.1, ap=4.0)


def assert_same_atmosphere(a, b, rel=1e-9):
    assert a.mass_density == pytest.approx(b.mass_density, rel=rel)
    assert a.temperature == pytest.approx(b.temperature, rel=rel)
    for name, value in a.number_densities.items():
        assert value == pytest.approx(b.number_densities[name], rel=rel), name


def erfa_orientation(time, ut1_minus_utc, polar_motion, step, model="iau2006a"):
    """GCRS -> ITRS matrix and ECEF rotation vector straight from pyerfa's own time scales."""
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
    velocity *= min(1.0, 12e3 / np.linalg.norm(velocity))  # an Earth orbit's speed at most
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
    """flight_conditions (float arithmetic, memoised per-day and precession-nutation terms)
    agrees with the plain pyerfa/numpy computation to 1e-12 relative."""
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


def test_vectors_as_lists_or_arrays_give_the_same_conditions_bit_for_bit():
    """The inputs are read as three floats whatever their container: lists, tuples and float64
    arrays give every field and the free stream, bit for bit."""
    rng = np.random.default_rng(4711)
    for _ in range(150):
        case = per_message_case(rng)
        wind = None if case["wind"] is None else case["wind"].tolist()
        expected = call(
            case,
            position=case["position"].tolist(),
            velocity=tuple(case["velocity"].tolist()),
            wind=wind,
        )
        actual = call(case)
        for f in dataclasses.fields(FlightConditions):
            a, b = getattr(actual, f.name), getattr(expected, f.name)
            if isinstance(a, np.ndarray):
                assert same_bits(a, b) and not a.flags.writeable, f.name
            elif f.name == "atmosphere":
                assert a == b and a.mean_mass == b.mean_mass
            else:
                assert a == b and type(a) is type(b), f.name
        assert actual.speed_ratio == expected.speed_ratio
        assert actual.mean_molecular_mass == expected.mean_molecular_mass
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
