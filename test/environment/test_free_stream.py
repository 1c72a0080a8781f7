"""The free stream of an atmospheric mixture: species order, mean mass, checks naming the input."""

import dataclasses
import datetime as dt

import numpy as np
import pytest

from adbsat_ros.environment.atmosphere import SpaceWeather
from adbsat_ros.environment.flight_conditions import flight_conditions
from adbsat_ros.physics.constants import SPECIES, species_mass_kg
from adbsat_ros.physics.freestream import FreeStream

TIME = dt.datetime(2015, 1, 19, 6, 30)
WEATHER = SpaceWeather(f107=121.7, f107a=138.1, ap=4.0)


def test_free_stream_of_a_mixture_has_its_species_in_order_and_the_mean_mass_summed():
    conditions = flight_conditions(TIME, [6778e3, 0.0, 0.0], [0.0, 7668.0, 0.0], WEATHER)
    atmosphere = conditions.atmosphere
    species = atmosphere.mixture_species
    values = [atmosphere.number_densities[s] for s in species]
    flow = FreeStream(7000.0, 900.0, dict(zip(species, values)), density=3e-12)
    assert flow.species == species == SPECIES
    assert flow.species_number_densities.dtype == np.float64
    assert flow.species_number_densities.tolist() == values
    assert flow.species_masses.tolist() == [species_mass_kg(s) for s in species]
    total = weighted = 0.0  # summed in species order, as ADBSat's environment.m
    for s, n in zip(species, values):
        total += n
        weighted += n * species_mass_kg(s)
    assert flow.mean_mass == weighted / total == atmosphere.mean_mass
    n, m = flow.species_number_densities, flow.species_masses
    assert flow.mean_mass == pytest.approx(float(np.dot(n, m) / n.sum()), rel=1e-15, abs=0.0)
    assert flow.mass_density == 3e-12 and flow.dynamic_pressure() == 0.5 * 3e-12 * 7000.0**2
    assert FreeStream(7000.0, 900.0, dict(zip(species, values))).mass_density == pytest.approx(
        float(np.dot(n, m)), rel=1e-15
    )
    other = FreeStream(7100.0, 950.0, dict(zip(species, values)), density=3e-12)
    other.species_masses[0] = 1.0  # each free stream's arrays are its own
    assert flow.species_masses[0] == species_mass_kg(species[0])
    assert dataclasses.replace(flow, speed=2.0 * flow.speed).speed_ratio == pytest.approx(
        2.0 * flow.speed_ratio, rel=1e-15
    )


@pytest.mark.parametrize(
    "args, name",
    [
        ((0.0, 900.0, ("O", "N2"), [1e14, 1e13], 1e-12), "speed"),
        ((float("inf"), 900.0, ("O", "N2"), [1e14, 1e13], 1e-12), "speed"),
        ((7e3, float("nan"), ("O", "N2"), [1e14, 1e13], 1e-12), "temperature"),
        ((7e3, 900.0, ("O", "N2"), [1e14, -1.0], 1e-12), "number density of N2"),
        ((7e3, 900.0, ("O", "N2"), [float("nan"), 1.0], 1e-12), "number density of O"),
        ((7e3, 900.0, ("O", "N2"), [1.0, float("inf")], 1e-12), "number density of N2"),
        ((7e3, 900.0, ("O", "N2"), ["many", 1.0], 1e-12), "number density of O"),
        ((7e3, 900.0, ("O", "N2"), [0.0, 0.0], 1e-12), "at least one species"),
        ((7e3, 900.0, ("O", "Xe"), [1e14, 1e13], 1e-12), "unknown species 'Xe'"),
        ((7e3, 900.0, ("O", "N2"), [1e14, 1e13], -1.0), "density"),
    ],
)
def test_free_stream_refuses_a_bad_mixture_naming_it(args, name):
    speed, temperature, species, values, density = args
    with pytest.raises(ValueError, match=name):
        FreeStream(speed, temperature, dict(zip(species, values)), density=density)


def test_free_stream_takes_finite_densities_whose_total_overflows():
    flow = FreeStream(7e3, 900.0, {"O": 1e308, "N2": 1e308})
    assert flow.number_densities == {"O": 1e308, "N2": 1e308}
