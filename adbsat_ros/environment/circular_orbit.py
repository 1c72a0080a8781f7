"""ADBSat's flight conditions (``environment.m``): a geodetic point, the circular-orbit speed; no
direction, co-rotation or wind, for parity with ADBSat. docs/physics.md, section 5.5."""

from __future__ import annotations

import datetime as _dt
import math

import numpy as np

from adbsat_ros.environment.accommodation import accommodation_of, normalize_model_name
from adbsat_ros.environment.atmosphere import (
    SpaceWeather,
    check_altitude,
    check_time,
    evaluate_atmosphere,
)
from adbsat_ros.environment.conditions import FlightConditions
from adbsat_ros.environment.earth_frames import earth_orientation
from adbsat_ros.environment.flight_conditions import DEFAULT_ACCOMMODATION_MODEL
from adbsat_ros.environment.geodetic import geodetic_to_ecef
from adbsat_ros.physics.constants import EARTH_MU, EARTH_RADIUS_ADBSAT


def circular_orbit_speed(altitude: float) -> float:
    """Circular-orbit speed sqrt(mu / (R_E + h)) [m/s] with ADBSat's mu and R_E = 6378.13649 km."""
    return math.sqrt(EARTH_MU / (EARTH_RADIUS_ADBSAT + float(altitude)))


def flight_conditions_circular_orbit(
    time,
    altitude: float,
    latitude: float,
    longitude: float,
    space_weather: SpaceWeather,
    *,
    anomalous_oxygen: bool = True,
    accommodation_model: str = DEFAULT_ACCOMMODATION_MODEL,
    accommodation_options=None,
    speed: float | None = None,
    precession_nutation: str = "iau2006a",
    atmosphere_model: str = "nrlmsise00",
) -> FlightConditions:
    """Flight conditions at a geodetic point at circular-orbit speed; no vectors but positions.
    time: UTC (aware, or naive meaning UTC), years 1958..2100; altitude: above the WGS-84
    ellipsoid [m], 0..1000 km; latitude, longitude: geodetic [rad]; speed: relative speed [m/s]
    >= 0 instead of the circular-orbit speed. Other options and ValueError as
    :func:`flight_conditions`."""
    time = check_time(time)
    model = normalize_model_name(accommodation_model)
    altitude = check_altitude(altitude)
    position_ecef = geodetic_to_ecef(latitude, longitude, altitude)
    space_weather = space_weather.at(time) if hasattr(space_weather, "at") else space_weather
    atmosphere = evaluate_atmosphere(
        time,
        altitude,
        latitude,
        longitude,
        space_weather,
        anomalous_oxygen=anomalous_oxygen,
        model=atmosphere_model,
    )
    if speed is None:
        speed = circular_orbit_speed(altitude)
    else:
        speed = float(speed)
        if not math.isfinite(speed) or speed < 0.0:
            raise ValueError(f"speed must be a finite number >= 0, got {speed!r}")
    orientation = earth_orientation(time, precession_nutation=precession_nutation)
    position_eci = position_ecef @ orientation.celestial_to_terrestrial
    return FlightConditions(
        time=time.replace(tzinfo=_dt.timezone.utc),
        position_eci=_read_only(position_eci),
        position_ecef=_read_only(position_ecef),
        velocity_eci=None,
        velocity_ecef=None,
        latitude=float(latitude),
        longitude=float(longitude),
        altitude=altitude,
        atmosphere=atmosphere,
        relative_velocity_eci=None,
        relative_velocity_ecef=None,
        speed=speed,
        accommodation_model=model,
        accommodation_coefficient=float(
            accommodation_of(model, atmosphere, speed, dict(accommodation_options or {}))
        ),
        earth_rotation=False,
        space_weather=space_weather,
    )


def _read_only(vector) -> np.ndarray:
    """A read-only float copy of a 3-vector."""
    array = np.array(vector, dtype=float)
    array.setflags(write=False)
    return array
