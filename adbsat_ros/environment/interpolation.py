"""Flight conditions between two knots, mixed linearly number by number."""

from __future__ import annotations

import dataclasses
import datetime as _dt
import functools
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
    """A knot: its exact ``conditions`` and, made when first mixed, :attr:`mixing`."""

    def __init__(self, conditions: FlightConditions):
        self.conditions = conditions

    @functools.cached_property
    def mixing(self) -> tuple:
        """Every number of the conditions in mixing order (read-only) and which of the six
        vectors are not None."""
        conditions = self.conditions
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
    (a_numbers, a_vectors), (b_numbers, b_vectors) = a.mixing, b.mixing
    mixed = a_numbers * (1.0 - weight)
    mixed += b_numbers * weight
    mixed.setflags(write=False)
    values = mixed.tolist()
    vectors = [mixed[k : k + 3] for k in range(0, 18, 3)]  # read-only views
    if a_vectors != b_vectors or not all(a_vectors):
        vectors = [v if p and q else None for v, p, q in zip(vectors, a_vectors, b_vectors)]
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
        *vectors[:4],
        latitude,
        longitude,
        altitude,
        atmosphere,
        *vectors[4:],
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
