"""The gas of a sweep's point: given (speed, temperature, mean molecular mass), or NRLMSISE-00's
at a circular orbit's speed, with optional ``scale.SPECIES`` factors. docs/sweeps.md.
"""

from __future__ import annotations

import datetime as _dt
import math

from adbsat_ros.environment.atmosphere import SpaceWeather
from adbsat_ros.environment.circular_orbit import flight_conditions_circular_orbit
from adbsat_ros.environment.space_weather import weather_source
from adbsat_ros.physics.constants import species_mass_kg
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.sweep.axes import ATMOSPHERE, ATMOSPHERE_DEFAULTS, DEFAULTS
from adbsat_ros.sweep.spec import SweepSpec


def point_inputs(spec: SweepSpec, values: dict) -> dict:
    """Every input of a point: its axis values, the fixed ones, the defaults of the rest."""
    inputs = {**spec.fixed, **values}
    return inputs if spec.atmosphere else {**DEFAULTS, **inputs}


def point_gas(spec: SweepSpec, inputs: dict, made: dict) -> FreeStream:
    """The free stream of a point; ``made`` caches them per chunk by inputs."""
    if not spec.atmosphere:
        return FreeStream(
            inputs["speed"], inputs["temperature"], mean_mass_amu=inputs["mean_mass_amu"]
        )
    values = {**ATMOSPHERE_DEFAULTS, **inputs}
    scales = {species: values[name] for species, name in spec.scales().items()}
    key = tuple(values[k] for k in ATMOSPHERE) + (inputs.get("speed"), *scales.values())
    if key not in made:
        fixed = SpaceWeather(values["f107"], values["f107a"], values["ap"])
        weather = weather_source(spec.space_weather, fixed)
        epoch = _dt.datetime.fromisoformat(spec.time)
        conditions = flight_conditions_circular_orbit(
            epoch + _dt.timedelta(hours=values["time"]),
            1e3 * values["altitude"],
            math.radians(values["latitude"]),
            math.radians(values["longitude"]),
            weather,
            speed=inputs.get("speed"),
            atmosphere_model=spec.atmosphere_model,
        )
        made[key] = scaled(conditions.free_stream(), scales)
    return made[key]


def scaled(flow: FreeStream, scales: dict) -> FreeStream:
    """``flow`` with each species' number density in ``scales`` multiplied by its factor.

    ValueError: a species the gas does not hold, or no molecules left.
    """
    if not scales:
        return flow
    densities = dict(flow.number_densities)
    density = flow.density
    for species, factor in scales.items():
        if species not in densities:
            raise ValueError(
                f"scale.{species}: the atmosphere's gas has no {species} (it has "
                f"{', '.join(densities)})"
            )
        density += (factor - 1.0) * densities[species] * species_mass_kg(species)
        densities[species] *= factor
    return FreeStream(flow.speed, flow.temperature, densities, density=max(density, 0.0))
