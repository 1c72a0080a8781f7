"""Flight conditions between two knots, mixed linearly number by number."""

from __future__ import annotations

import dataclasses
import datetime as _dt
import math

import numpy as np

from adbsat_ros.environment.atmosphere import AtmosphereState
from adbsat_ros.environment.conditions import FlightConditions
from adbsat_ros.environment.kinematics import geodetic_of_floats

#: The vector fields of FlightConditions, in the order of the interpolation numbers.
_VECTORS = (
    "position_eci",
    "position_ecef",
    "velocity_eci",
    "velocity_ecef",
    "relative_velocity_eci",
    "relative_velocity_ecef",
)
#: Index of the first scalar in the interpolation numbers (after the six vectors).
_SPEED, _ALPHA, _MASS_DENSITY, _EXOSPHERIC, _TEMPERATURE, _DENSITIES = range(18, 24)


class KnotEnds:
    """A knot: its exact ``conditions`` and the numbers mixed, made when first asked for."""

    __slots__ = ("conditions", "_numbers", "_vectors")

    def __init__(self, conditions: FlightConditions):
        self.conditions = conditions
        self._numbers = None
        self._vectors = ()

    @property
    def numbers(self) -> np.ndarray:
        """Read-only: every number of a knot, in mixing order."""
        if self._numbers is None:
            self._numbers, self._vectors = _numbers_of(self.conditions)
        return self._numbers

    @property
    def vectors(self) -> tuple:
        """Which of the six vectors are not None."""
        self.numbers  # (made with the numbers)
        return self._vectors


def _numbers_of(conditions: FlightConditions) -> tuple:
    """(numbers, vectors) of :class:`KnotEnds`."""
    atmosphere = conditions.atmosphere
    values = []
    present = []
    for name in _VECTORS:
        vector = getattr(conditions, name)
        values.extend((0.0, 0.0, 0.0) if vector is None else vector.tolist())
        present.append(vector is not None)
    values += (
        conditions.speed,
        conditions.accommodation_coefficient,
        atmosphere.mass_density,
        atmosphere.exospheric_temperature,
        atmosphere.temperature,
        *atmosphere.number_densities.values(),
    )
    numbers = np.array(values, dtype=float)
    numbers.setflags(write=False)
    return numbers, tuple(present)


def check_ends(a: FlightConditions, b: FlightConditions) -> None:
    """ValueError unless ``a`` and ``b`` were made with the same options and species."""
    if (
        a.accommodation_model != b.accommodation_model
        or a.earth_rotation != b.earth_rotation
        or (a.space_weather is not b.space_weather and a.space_weather != b.space_weather)
        or a.atmosphere.anomalous_oxygen != b.atmosphere.anomalous_oxygen
        or a.atmosphere.number_densities.keys() != b.atmosphere.number_densities.keys()
    ):
        raise ValueError("interpolated_flight_conditions: a and b were made with different options")


def mixed_conditions(
    a: KnotEnds, b: KnotEnds, weight: float, time: _dt.datetime
) -> FlightConditions:
    """The conditions ``(1 - weight) a + weight b`` at ``time``, number by number."""
    mixed = a.numbers * (1.0 - weight)
    mixed += b.numbers * weight
    mixed.setflags(write=False)
    values = mixed.tolist()
    vectors = list(mixed[:18].reshape(6, 3))  # read-only views
    if a.vectors != b.vectors or not all(a.vectors):
        vectors = [v if p and q else None for v, p, q in zip(vectors, a.vectors, b.vectors)]
    speed = values[_SPEED] if vectors[5] is None else math.hypot(*values[15:18])
    # (ERFA's gc2gd in floats, bit for bit: test/environment/test_kinematics.py)
    latitude, longitude, altitude = geodetic_of_floats(*values[3:6])
    ends = a.conditions
    atmosphere = AtmosphereState(
        dict(zip(ends.atmosphere.number_densities, values[_DENSITIES:])),
        values[_MASS_DENSITY],
        values[_EXOSPHERIC],
        values[_TEMPERATURE],
        ends.atmosphere.anomalous_oxygen,
    )
    return FlightConditions(
        time,
        vectors[0],
        vectors[1],
        vectors[2],
        vectors[3],
        latitude,
        longitude,
        altitude,
        atmosphere,
        vectors[4],
        vectors[5],
        speed,
        ends.accommodation_model,
        values[_ALPHA],
        ends.earth_rotation,
        ends.space_weather,
    )


def interpolated_flight_conditions(
    a: FlightConditions, b: FlightConditions, weight: float, time: _dt.datetime
) -> FlightConditions:
    """The conditions at UTC ``time``, ``weight`` (0..1) of the way from a to b, mixed linearly.

    ValueError: ``a`` and ``b`` made with different options.
    """
    check_ends(a, b)
    if weight == 0.0:
        return dataclasses.replace(a, time=time)
    return mixed_conditions(KnotEnds(a), KnotEnds(b), weight, time)
