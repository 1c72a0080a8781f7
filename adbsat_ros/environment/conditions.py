"""The conditions a spacecraft flies in at one instant (m, m/s, kg, K, rad)."""

from __future__ import annotations

import datetime as _dt
import math
from dataclasses import dataclass, field

import numpy as np

from adbsat_ros.environment.atmosphere import AtmosphereState, SpaceWeather
from adbsat_ros.physics.constants import BOLTZMANN
from adbsat_ros.physics.freestream import FreeStream

#: Units of the numeric fields of :meth:`FlightConditions.as_dict`.
UNITS = {
    "latitude": "rad",
    "longitude": "rad",
    "altitude": "m",
    "position_eci": "m",
    "position_ecef": "m",
    "velocity_eci": "m/s",
    "velocity_ecef": "m/s",
    "space_weather.f107": "sfu (1e-22 W m^-2 Hz^-1)",
    "space_weather.f107a": "sfu (1e-22 W m^-2 Hz^-1)",
    "space_weather.ap": "1",
    "number_densities": "m^-3",
    "mass_density": "kg/m^3",
    "exospheric_temperature": "K",
    "temperature": "K",
    "mean_molecular_mass": "kg",
    "relative_velocity_eci": "m/s",
    "relative_velocity_ecef": "m/s",
    "speed": "m/s",
    "speed_ratio": "1",
    "accommodation_coefficient": "1",
}


def speed_ratio(speed: float, temperature: float, mean_mass: float) -> float:
    """Speed ratio s = V / sqrt(2 k_B T / m) [-]; V [m/s], T [K], m [kg]."""
    return speed / math.sqrt(2.0 * BOLTZMANN * temperature / mean_mass)


@dataclass(frozen=True, eq=False)
class FlightConditions:
    """Conditions a spacecraft flies in at one instant: frozen, with read-only vectors.

    Positions [m] in ECI (GCRF) and ECEF (ITRF); ``velocity_eci`` inertial, ``velocity_ecef`` and
    ``relative_velocity_*`` (minus co-rotating air and wind) [m/s], None for the circular orbit;
    WGS-84 geodetic latitude, longitude [rad], altitude [m].
    """

    time: _dt.datetime
    position_eci: np.ndarray
    position_ecef: np.ndarray
    velocity_eci: np.ndarray | None
    velocity_ecef: np.ndarray | None
    latitude: float
    longitude: float
    altitude: float
    atmosphere: AtmosphereState
    relative_velocity_eci: np.ndarray | None
    relative_velocity_ecef: np.ndarray | None
    speed: float
    accommodation_model: str
    accommodation_coefficient: float
    earth_rotation: bool = True
    space_weather: SpaceWeather | None = field(default=None, repr=False)

    @property
    def alpha(self) -> float:
        """Shorthand for :attr:`accommodation_coefficient`."""
        return self.accommodation_coefficient

    @property
    def mean_molecular_mass(self) -> float:
        """Mean molecular mass of the mixture [kg]."""
        return self.atmosphere.mean_mass

    @property
    def speed_ratio(self) -> float:
        """Molecular speed ratio s = speed / sqrt(2 k_B T / m) [-]."""
        atmosphere = self.atmosphere
        return speed_ratio(self.speed, atmosphere.temperature, atmosphere.mean_mass)

    @property
    def temperature(self) -> float:
        """Local gas temperature [K]."""
        return self.atmosphere.temperature

    @property
    def mass_density(self) -> float:
        """Total mass density [kg/m^3] (with anomalous O if the atmosphere includes it)."""
        return self.atmosphere.mass_density

    @property
    def flow_direction_ecef(self) -> np.ndarray | None:
        """-v_rel / |v_rel|, ECEF axes; None at zero speed or with only a speed known."""
        if self.relative_velocity_ecef is None or self.speed == 0.0:
            return None
        return -self.relative_velocity_ecef / self.speed

    def as_dict(self) -> dict:
        """Every field as JSON-ready values (SI; time ISO 8601); ``units`` names each unit."""

        def vector(value):
            return None if value is None else [float(x) for x in value]

        atmosphere = self.atmosphere
        weather = self.space_weather
        return {
            "time": self.time.isoformat(),
            "latitude": self.latitude,
            "longitude": self.longitude,
            "altitude": self.altitude,
            "position_eci": vector(self.position_eci),
            "position_ecef": vector(self.position_ecef),
            "velocity_eci": vector(self.velocity_eci),
            "velocity_ecef": vector(self.velocity_ecef),
            "space_weather": None
            if weather is None
            else {
                "f107": weather.f107,
                "f107a": weather.f107a,
                "ap": weather.ap,
                "ap_history": None if weather.ap_history is None else list(weather.ap_history),
            },
            "anomalous_oxygen": atmosphere.anomalous_oxygen,
            "number_densities": {k: float(v) for k, v in atmosphere.number_densities.items()},
            "mass_density": float(atmosphere.mass_density),
            "exospheric_temperature": float(atmosphere.exospheric_temperature),
            "temperature": float(atmosphere.temperature),
            "mean_molecular_mass": self.mean_molecular_mass,
            "earth_rotation": self.earth_rotation,
            "relative_velocity_eci": vector(self.relative_velocity_eci),
            "relative_velocity_ecef": vector(self.relative_velocity_ecef),
            "speed": self.speed,
            "speed_ratio": self.speed_ratio,
            "accommodation_model": self.accommodation_model,
            "accommodation_coefficient": self.accommodation_coefficient,
            "units": dict(UNITS),
        }

    def free_stream(self) -> FreeStream:
        """The free stream of these conditions (docs/physics.md, section 5.3).

        ValueError: zero relative speed, or a gas a free stream does not take.
        """
        if not self.speed > 0.0:
            raise ValueError(
                "relative speed is 0 m/s (the satellite is at rest in the air): "
                "no free stream; check FlightConditions.speed before asking for one"
            )
        atmosphere = self.atmosphere
        return FreeStream(
            self.speed,
            atmosphere.temperature,
            atmosphere.mixture_number_densities,
            density=atmosphere.mass_density,
        )
