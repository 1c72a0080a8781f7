"""Accommodation models: Langmuir (Pilinski 2010), Goodman, SESAM (Pilinski 2013), fixed."""

import datetime as dt
import math

import numpy as np
import pytest
from scipy.integrate import quad

from adbsat_ros.environment.accommodation import (
    ACCOMMODATION_MODELS,
    SESAM_ADSORPTION_ENERGY,
    SESAM_TRANSITION_TEMPERATURE,
    accommodation,
    accommodation_model_names,
    goodman_accommodation,
    langmuir_accommodation,
    sesam_accommodation,
    sesam_oxygen_pressure,
    sesam_sticking_fraction,
)
from adbsat_ros.environment.atmosphere import AtmosphereState, SpaceWeather, evaluate_atmosphere
from adbsat_ros.physics.constants import AMU, BOLTZMANN, species_mass_kg

# ADBSat validation paper (Sinpetru, Crisp et al. 2022, "ADBSat: Verification and validation of a
# novel panel method for quick aerodynamic analysis of satellites", Comput. Phys. Commun. 275),
# conditions of its accommodation values: 2015-01-19 00:00 UT, 0 N 0 E, F10.7 = 121.7,
# F10.7A = 138.1, Ap 2.9-9 (we use 4); Langmuir alpha = 1, 1, 0.97, 0.81 at 100, 200, 300,
# 400 km (physics.md, top).
PAPER_TIME = dt.datetime(2015, 1, 19)
PAPER_WEATHER = SpaceWeather(f107=121.7, f107a=138.1, ap=4.0)


def paper_atmosphere(altitude):
    return evaluate_atmosphere(PAPER_TIME, altitude, 0.0, 0.0, PAPER_WEATHER)


@pytest.mark.parametrize("altitude, expected", [(300e3, 0.97), (400e3, 0.81)])
def test_langmuir_reproduces_validation_paper(altitude, expected):
    alpha = accommodation("langmuir", paper_atmosphere(altitude), 7700.0)
    assert alpha == pytest.approx(expected, abs=0.02)


def test_langmuir_is_one_at_low_altitude_and_falls_with_altitude():
    altitudes = np.arange(100e3, 700e3, 50e3)
    alphas = [accommodation("langmuir", paper_atmosphere(h), 7700.0) for h in altitudes]
    assert alphas[0] > 0.999  # 100 km: alpha = 1 in the paper
    assert alphas[1] > 0.99  # 200 km: alpha = 1 in the paper
    assert all(b < a for a, b in zip(alphas, alphas[1:]))
    assert alphas[-1] < 0.5


def test_langmuir_formula():
    # x = K n_O T = 7.5e-17 * 1e14 * 1000 = 7.5 -> alpha = 7.5 / 8.5
    assert langmuir_accommodation(1e14, 1000.0) == pytest.approx(7.5 / 8.5, rel=1e-14)
    assert langmuir_accommodation(0.0, 1000.0) == 0.0
    assert langmuir_accommodation(1e14, 1000.0, langmuir_constant=1.5e-16) == pytest.approx(15 / 16)


def test_goodman_closed_form():
    # alpha = K_s m_g m_s / (m_g + m_s)^2: 2.4 * 16 * 65 / 81^2 = 2496 / 6561
    assert goodman_accommodation(16 * AMU) == pytest.approx(2496 / 6561, rel=1e-12)
    # maximum K_s / 4 when the masses are equal
    assert goodman_accommodation(65 * AMU, substrate_coefficient=3.6) == pytest.approx(
        0.9, rel=1e-12
    )


def test_sesam_sticking_fraction_matches_numerical_integral():
    # s_o = int_0^sqrt(E_b) g / int_0^inf g, g(x) = x exp(-(x - sqrt(E_r))^2 / (k T_ab)).
    w = math.sqrt(BOLTZMANN * SESAM_TRANSITION_TEMPERATURE)
    a = math.sqrt(SESAM_ADSORPTION_ENERGY)
    for speed in (7000.0, 7600.0, 7800.0, 8000.0, 8500.0, 9000.0):
        r = math.sqrt(0.5 * species_mass_kg("O") * speed**2)

        def g(x):
            return x * math.exp(-(((x - r) / w) ** 2))

        low, high = max(0.0, r - 15 * w), r + 15 * w
        below = (
            quad(g, low, min(a, high), points=[r] if low < r < a else None, limit=200)[0]
            if a > low
            else 0.0
        )
        total = quad(g, low, high, points=[r], limit=200)[0]
        assert sesam_sticking_fraction(0.5 * species_mass_kg("O") * speed**2) == pytest.approx(
            below / total, rel=1e-6, abs=1e-12
        ), speed


def test_sesam_sticking_fraction_limits():
    assert sesam_sticking_fraction(0.0) == pytest.approx(1.0, abs=1e-12)
    assert sesam_sticking_fraction(20 * SESAM_ADSORPTION_ENERGY) < 1e-12
    # centred on the threshold: a little under one half (the weight x favours energies above it)
    assert 0.45 < sesam_sticking_fraction(SESAM_ADSORPTION_ENERGY) < 0.5


def test_sesam_pressure_limits():
    n_o, mass = 1e14, species_mass_kg("O")
    # large s: e^{-s^2} vanishes and erf(s) = 1, f(s) = 2 + 2/s^2 - 1/(2 s^4) -> P -> rho_O V^2
    p = sesam_oxygen_pressure(n_o, 7800.0, 50.0)
    assert p / (0.5 * n_o * mass * 7800.0**2) == pytest.approx(
        2 + 2 / 50**2 - 0.5 / 50**4, rel=1e-12
    )
    # continuous across the small-s switch at 1e-3, and zero at rest
    below = sesam_oxygen_pressure(n_o, 0.999e-3, 0.999e-3) / 0.999e-3
    above = sesam_oxygen_pressure(n_o, 1.001e-3, 1.001e-3) / 1.001e-3
    assert below == pytest.approx(above, rel=1e-5)
    assert sesam_oxygen_pressure(n_o, 0.0, 0.0) == 0.0


def test_sesam_between_goodman_and_one():
    atmosphere = paper_atmosphere(400e3)
    goodman = accommodation("goodman", atmosphere, 7668.0)
    sesam = accommodation("sesam", atmosphere, 7668.0)
    assert goodman < sesam < 1.0
    # no oxygen: clean surface (Goodman); lots of oxygen: alpha -> 1
    mean_mass = atmosphere.mean_mass
    assert sesam_accommodation(0.0, mean_mass, 7668.0, 8.0) == pytest.approx(goodman, rel=1e-12)
    assert sesam_accommodation(1e20, mean_mass, 7668.0, 8.0) > 0.9999
    # at rest the Langmuir coverage vanishes (P_O = 0): Goodman again, no crash
    assert accommodation("sesam", atmosphere, 0.0) == pytest.approx(goodman, rel=1e-12)
    # SESAM falls with altitude too
    assert accommodation("sesam", paper_atmosphere(300e3), 7725.0) > sesam


def test_fixed_and_registry():
    atmosphere = paper_atmosphere(400e3)
    assert accommodation("fixed", atmosphere, 7700.0, alpha=0.42) == 0.42
    assert accommodation("SESAM", atmosphere, 7700.0) == accommodation("sesam", atmosphere, 7700.0)
    assert accommodation_model_names() == ("fixed", "langmuir", "goodman", "sesam")
    assert set(ACCOMMODATION_MODELS) == set(accommodation_model_names())


@pytest.mark.parametrize(
    "name, speed, options, message",
    [
        ("cook", 7700.0, {}, "fixed, langmuir, goodman, sesam"),
        ("fixed", 7700.0, {}, "alpha"),
        ("fixed", 7700.0, {"alpha": 1.5}, "alpha"),
        ("fixed", 7700.0, {"alpha": float("nan")}, "alpha"),
        ("langmuir", 7700.0, {"alpha": 0.5}, "alpha"),
        ("langmuir", 7700.0, {"langmuir_constant": -1.0}, "langmuir_constant"),
        ("goodman", 7700.0, {"substrate_coefficient": 5.0}, "substrate_coefficient"),
        ("sesam", 7700.0, {"surface_mass_amu": 0.0}, "surface_mass_amu"),
        ("sesam", -1.0, {}, "speed"),
        ("langmuir", float("inf"), {}, "speed"),
    ],
)
def test_bad_inputs_name_the_input(name, speed, options, message):
    with pytest.raises(ValueError, match=message):
        accommodation(name, paper_atmosphere(400e3), speed, **options)


def test_atmosphere_must_be_an_atmosphere_state():
    with pytest.raises(ValueError, match="atmosphere"):
        accommodation("langmuir", {"O": 1e14}, 7700.0)


def test_registry_fixed_and_langmuir_equal_the_model_functions():
    """The registry's fixed alpha and Langmuir isotherm give what the model functions give, bit for
    bit, for model states and for hand-made ones of other number types."""
    for altitude in (200e3, 400e3, 700e3):
        atmosphere = paper_atmosphere(altitude)
        n_o, temperature = atmosphere.number_densities["O"], atmosphere.temperature
        expected = langmuir_accommodation(n_o, temperature)
        assert accommodation("langmuir", atmosphere, 7700.0) == expected
        assert accommodation("langmuir", atmosphere, 7700.0, langmuir_constant=7.5e-17) == expected
        numpy_state = AtmosphereState(
            {"O": np.float64(n_o)}, 1e-12, 1000.0, np.float64(temperature)
        )
        assert accommodation("langmuir", numpy_state, 7700.0) == expected
        for alpha in (0.0, 0.37, 1.0, np.float64(0.5), 1):
            assert accommodation("fixed", atmosphere, 7700.0, alpha=alpha) == float(alpha)
    with pytest.raises(ValueError, match="oxygen_number_density"):
        accommodation("langmuir", AtmosphereState({"O": -1.0}, 1e-12, 1000.0, 900.0), 7700.0)
    with pytest.raises(ValueError, match="temperature"):
        accommodation("langmuir", AtmosphereState({"O": 1e14}, 1e-12, 1000.0, float("inf")), 7700.0)
