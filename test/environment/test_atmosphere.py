"""NRLMSISE-00 through adbsat_ros.environment.atmosphere: published values, units, checks, cost."""

import datetime as dt
import math

import nrlmsise00
import pytest

from adbsat_ros.bounds import BOUNDS
from adbsat_ros.environment.atmosphere import (
    AtmosphereState,
    SpaceWeather,
    checked_utc,
    evaluate_atmosphere,
)

# Reference test case 1 of the NRLMSISE-00 C distribution (nrlmsise-00_test.c, D. Brodowski;
# the same numbers are printed by the original Fortran test driver): day 172, 29000 s UT,
# 400 km, 60 N, 70 W, local solar time 16 h, F10.7 = F10.7A = 150, Ap = 4, all switches on,
# computed with gtd7 (total mass density WITHOUT anomalous oxygen). Published in cgs:
# He, O, N2, O2, Ar [cm^-3], rho [g/cm^3], H, N, anomalous O [cm^-3], T_exo, T [K].
CASE1_CGS = (
    6.665177e05,
    1.138806e08,
    1.998211e07,
    4.022764e05,
    3.557465e03,
    4.074714e-15,
    3.475312e04,
    4.095913e06,
    2.667273e04,
    1.250540e03,
    1.241416e03,
)
CASE1_ORDER = ("He", "O", "N2", "O2", "Ar", None, "H", "N", "AnO")
# Day 172 of 2009 is 21 June; 29000 s = 08:03:20 UT.
CASE1_TIME = dt.datetime(2009, 6, 21, 8, 3, 20)
CASE1_LAT = math.radians(60.0)
CASE1_LON = math.radians(-70.0)
MODERATE = SpaceWeather(f107=150.0, f107a=150.0, ap=4.0)
# NRLMSISE-00 test cases 16 and 17 of the same program: case 1 (and case 17 at 100 km) with the
# 7-element Ap array all 100 and switch 9 = -1; published rho 5.881940E-15 and 2.914304E-10 g/cm^3.
STORM = SpaceWeather(f107=150.0, f107a=150.0, ap=4.0, ap_history=(100.0,) * 7)


def case1(**kwargs):
    return evaluate_atmosphere(
        CASE1_TIME, 400e3, CASE1_LAT, CASE1_LON, MODERATE, local_solar_time_h=16.0, **kwargs
    )


def test_published_case_1_in_si_units():
    state = case1(anomalous_oxygen=False)
    for name, expected in zip(CASE1_ORDER, CASE1_CGS):
        if name is None:
            continue
        # cm^-3 -> m^-3
        assert state.number_densities[name] == pytest.approx(expected * 1e6, rel=1e-6), name
    # g/cm^3 -> kg/m^3: 4.074714e-15 g/cm^3 = 4.074714e-12 kg/m^3
    assert state.mass_density == pytest.approx(4.074714e-12, rel=1e-6)
    assert state.exospheric_temperature == pytest.approx(1250.540, abs=1e-3)
    assert state.temperature == pytest.approx(1241.416, abs=1e-3)
    assert state.anomalous_oxygen is False


def test_anomalous_oxygen_total_is_gtd7d():
    # gtd7d adds the anomalous oxygen to the total with the model's own mass, 16 * 1.66e-24 g
    # (nrlmsise-00.c, gtd7d), i.e. 16 * 1.66e-27 kg per particle in SI.
    without = case1(anomalous_oxygen=False)
    with_ano = case1(anomalous_oxygen=True)
    added = with_ano.mass_density - without.mass_density
    assert added == pytest.approx(16 * 1.66e-27 * without.number_densities["AnO"], rel=1e-6)
    assert with_ano.number_densities == without.number_densities
    assert "AnO" in with_ano.mixture_species and "AnO" not in without.mixture_species


@pytest.mark.parametrize("altitude, rho_g_cm3", [(400e3, 5.881940e-15), (100e3, 2.914304e-10)])
def test_published_cases_16_17_ap_history(altitude, rho_g_cm3):
    state = evaluate_atmosphere(
        CASE1_TIME,
        altitude,
        CASE1_LAT,
        CASE1_LON,
        STORM,
        anomalous_oxygen=False,
        local_solar_time_h=16.0,
    )
    assert state.mass_density == pytest.approx(rho_g_cm3 * 1e3, rel=1e-6)
    # and the history really changes the answer (storm vs quiet: denser at 400 km, cooler and
    # lighter at 100 km)
    quiet = evaluate_atmosphere(
        CASE1_TIME,
        altitude,
        CASE1_LAT,
        CASE1_LON,
        MODERATE,
        anomalous_oxygen=False,
        local_solar_time_h=16.0,
    )
    assert abs(state.mass_density / quiet.mass_density - 1.0) > 0.05


def test_year_does_not_matter_only_day_of_year():
    # NRLMSISE-00 ignores the year: day 172 is 20 June in the leap year 2008, 21 June in 2009.
    a = evaluate_atmosphere(CASE1_TIME, 400e3, CASE1_LAT, CASE1_LON, MODERATE)
    b = evaluate_atmosphere(
        dt.datetime(2008, 6, 20, 8, 3, 20), 400e3, CASE1_LAT, CASE1_LON, MODERATE
    )
    c = evaluate_atmosphere(
        dt.datetime(2008, 6, 21, 8, 3, 20), 400e3, CASE1_LAT, CASE1_LON, MODERATE
    )
    assert a == b
    assert a.mass_density != c.mass_density


def test_timezone_aware_time_is_converted_to_utc():
    plus_two = dt.timezone(dt.timedelta(hours=2))
    aware = CASE1_TIME.replace(tzinfo=dt.timezone.utc).astimezone(plus_two)
    assert evaluate_atmosphere(aware, 400e3, CASE1_LAT, CASE1_LON, MODERATE) == evaluate_atmosphere(
        CASE1_TIME, 400e3, CASE1_LAT, CASE1_LON, MODERATE
    )


def test_matches_package_wrapper_with_default_local_time():
    # Independent path: nrlmsise00.msise_model (degrees, km, cgs units, lst = UT + lon/15).
    densities, temperatures = nrlmsise00.msise_model(
        CASE1_TIME, 400.0, 60.0, -70.0, 150.0, 150.0, 4.0, method="gtd7d"
    )
    state = evaluate_atmosphere(CASE1_TIME, 400e3, CASE1_LAT, CASE1_LON, MODERATE)
    for name, index in (
        ("He", 0),
        ("O", 1),
        ("N2", 2),
        ("O2", 3),
        ("Ar", 4),
        ("H", 6),
        ("N", 7),
        ("AnO", 8),
    ):
        assert state.number_densities[name] == pytest.approx(densities[index] * 1e6, rel=1e-12)
    assert state.mass_density == pytest.approx(densities[5] * 1e3, rel=1e-12)
    assert state.temperature == pytest.approx(temperatures[1], rel=1e-12)
    # and the local time matters (16 h vs the 3.39 h implied by UT and longitude)
    assert state.mass_density != pytest.approx(case1().mass_density, rel=1e-3)


def test_mean_mass_is_number_weighted():
    state = case1()
    amu_g = {
        "He": 4.002602,
        "O": 15.9994,
        "N2": 28.0134,
        "O2": 31.9988,
        "Ar": 39.948,
        "H": 1.0079,
        "N": 14.0067,
        "AnO": 15.99,
    }
    n = state.number_densities
    expected = sum(n[k] * amu_g[k] for k in amu_g) / sum(n.values()) / 1000 / 6.02214076e23
    assert state.mean_mass == pytest.approx(expected, rel=1e-12)
    assert isinstance(state, AtmosphereState)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(altitude=-1.0), "altitude"),
        (dict(altitude=1000.001e3), "altitude"),
        (dict(altitude=float("nan")), "altitude"),
        (dict(latitude=float("nan")), "latitude"),
        (dict(latitude=2.0), "latitude"),
        (dict(longitude=float("inf")), "longitude"),
        (dict(time=dt.datetime(1957, 12, 31, 23)), "time"),
        (dict(time=dt.datetime(2101, 1, 1)), "time"),
        (dict(time="2015-01-19"), "time"),
        (dict(time=dt.date(2015, 1, 19)), "time"),
        (dict(local_solar_time_h=float("nan")), "local_solar_time_h"),
        (dict(space_weather=(150, 150, 4)), "space_weather"),
    ],
)
def test_bad_inputs_name_the_input(kwargs, name):
    args = dict(
        time=CASE1_TIME,
        altitude=400e3,
        latitude=CASE1_LAT,
        longitude=CASE1_LON,
        space_weather=MODERATE,
    )
    args.update(kwargs)
    with pytest.raises(ValueError, match=name):
        evaluate_atmosphere(**args)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(f107=-1.0), "f107"),
        (dict(f107=float("nan")), "f107"),
        (dict(f107a=-0.1), "f107a"),
        (dict(f107a=float("inf")), "f107a"),
        (dict(ap=-4.0), "ap"),
        (dict(ap=float("nan")), "ap"),
        (dict(ap_history=(4.0,) * 6), "ap_history"),
        (dict(ap_history=(4.0,) * 6 + (-1.0,)), r"ap_history\[6\]"),
        (dict(ap_history=(4.0,) * 6 + (float("nan"),)), r"ap_history\[6\]"),
    ],
)
def test_bad_space_weather_names_the_index(kwargs, name):
    args = dict(f107=150.0, f107a=150.0, ap=4.0)
    args.update(kwargs)
    with pytest.raises(ValueError, match=name):
        SpaceWeather(**args)


def test_boundaries_are_accepted():
    for altitude in (0.0, 1000e3):
        state = evaluate_atmosphere(dt.datetime(1958, 1, 1), altitude, 0.0, 0.0, MODERATE)
        assert state.mass_density > 0
    evaluate_atmosphere(dt.datetime(2100, 12, 31, 23, 59), 400e3, 0.0, 0.0, MODERATE)


def test_repeated_calls_give_the_same_state_whatever_came_between():
    """The model keeps nothing from one call to the next: the same inputs give the same state,
    bit for bit, call after call and after calls with other inputs. (Its cost per call is
    measured by bench/bench_flight_conditions.py, not here.)"""
    first = evaluate_atmosphere(CASE1_TIME, 400e3, CASE1_LAT, CASE1_LON, MODERATE)
    for k in range(200):
        other = evaluate_atmosphere(
            CASE1_TIME + dt.timedelta(hours=k),
            150e3 + 2e3 * k,
            -CASE1_LAT,
            math.radians(k),
            MODERATE,
        )
        assert other != first
        assert evaluate_atmosphere(CASE1_TIME, 400e3, CASE1_LAT, CASE1_LON, MODERATE) == first


def test_checked_utc_is_an_aware_utc_time_or_the_time_error():
    aware = dt.datetime(2015, 1, 19, 6, 30, tzinfo=dt.timezone.utc)
    assert checked_utc(aware) is aware  # already what is needed: returned as it is
    naive = checked_utc(dt.datetime(2015, 1, 19, 6, 30))
    assert naive == aware and naive.tzinfo is dt.timezone.utc
    shifted = checked_utc(aware.astimezone(dt.timezone(dt.timedelta(hours=-5))))
    assert shifted == aware and shifted.tzinfo is dt.timezone.utc and shifted.hour == 6
    for bad in (
        dt.datetime(2101, 1, 1, tzinfo=dt.timezone.utc),
        dt.datetime(1957, 12, 31),
        "2015-01-19",
        dt.date(2015, 1, 19),
    ):
        with pytest.raises(ValueError, match="time"):
            checked_utc(bad)


def test_model_states_equal_the_constructed_state_and_its_derived_values():
    """A model state and AtmosphereState(...) made of its fields by hand are equal, and so are
    their derived values (mixture, mean mass, total), bit for bit; both are read-only."""
    weather = SpaceWeather(f107=150.0, f107a=150.0, ap=4.0)
    for anomalous_oxygen in (True, False):
        for altitude in (90e3, 400e3, 950e3):
            state = evaluate_atmosphere(
                dt.datetime(2015, 1, 19, 6),
                altitude,
                0.3,
                -1.2,
                weather,
                anomalous_oxygen=anomalous_oxygen,
            )
            fresh = AtmosphereState(
                dict(state.number_densities),
                state.mass_density,
                state.exospheric_temperature,
                state.temperature,
                anomalous_oxygen,
            )
            assert state == fresh and type(state.anomalous_oxygen) is bool
            assert state.mixture_species == fresh.mixture_species
            assert state.mixture_number_densities == fresh.mixture_number_densities
            assert state.mean_mass == fresh.mean_mass  # the same sums in the same order
            assert state.total_number_density == fresh.total_number_density
            assert len(state.mixture_species) == (8 if anomalous_oxygen else 7)
            for read_only in (state, fresh):
                with pytest.raises(TypeError):
                    read_only.number_densities["O"] = 0.0


def test_nrlmsise00_stays_silent_and_finite_over_the_valid_inputs(capfd):
    """Its C code prints "dnet log error" to stdout (into ``atmosphere --json``) for space
    weather far outside what it was fitted to; over the corners of the ranges the inputs are
    checked against, from the ground to 1000 km, it prints nothing and every number is finite."""
    f107, ap = BOUNDS["f107"], BOUNDS["ap"]
    t = dt.datetime(2025, 3, 1, tzinfo=dt.timezone.utc)
    for flux in (f107.low, f107.high):
        for index in (ap.low, ap.high):
            weather = SpaceWeather(flux, flux, index, (index,) * 7)
            for altitude in (0.0, 20e3, 90e3, 120e3, 300e3, 1000e3):
                for latitude in (-math.pi / 2, 0.3, math.pi / 2):
                    state = evaluate_atmosphere(t, altitude, latitude, 2.0, weather)
                    assert math.isfinite(state.mass_density) and state.mass_density > 0
                    assert all(math.isfinite(n) for n in state.number_densities.values())
    assert capfd.readouterr().out == ""
