"""Flight conditions of an orbital state in ECI (GCRF) or ECEF (ITRF) at a UTC time.

Relative velocity ``v_sat - v_air``, the air co-rotating by default. docs/physics.md, section
5.4. Units: m, m/s, kg, K, rad.
"""

from __future__ import annotations

import math
import types
from dataclasses import dataclass
from typing import Mapping

import numpy as np

from adbsat_ros.environment.accommodation import (
    ACCOMMODATION_MODELS,
    checked_options,
    normalize_model_name,
)
from adbsat_ros.environment.atmosphere import (
    ATMOSPHERE_MODELS,
    SpaceWeather,
    check_altitude,
    checked_utc,
    run_model,
)
from adbsat_ros.environment.conditions import FlightConditions
from adbsat_ros.environment.earth_frames import EarthOrientation, check_orientation_options
from adbsat_ros.environment.kinematics import rotation_floats, state_kinematics
from adbsat_ros.environment.time_scales import seconds_of_day, utc_day
from adbsat_ros.validation import finite as _finite

#: Frames an orbital state may be given in.
STATE_FRAMES = ("eci", "ecef")
#: Frames a wind vector may be given in.
WIND_FRAMES = ("enu", "ecef")
#: Default accommodation model.
DEFAULT_ACCOMMODATION_MODEL = "langmuir"


@dataclass(frozen=True)
class ConditionsOptions:
    """The options of :func:`flight_conditions`, checked once for a stream of states."""

    frame: str
    earth_rotation: bool
    wind: tuple | None
    wind_frame: str
    anomalous_oxygen: bool
    accommodation_model: str
    accommodation_options: Mapping
    orientation_options: tuple
    atmosphere_model: str = "nrlmsise00"


def conditions_options(
    *,
    frame: str = "eci",
    earth_rotation: bool = True,
    wind=None,
    wind_frame: str = "enu",
    anomalous_oxygen: bool = True,
    accommodation_model: str = DEFAULT_ACCOMMODATION_MODEL,
    accommodation_options=None,
    ut1_minus_utc: float = 0.0,
    polar_motion=(0.0, 0.0),
    precession_nutation: str = "iau2006a",
    precession_nutation_step: float = 0.0,
    atmosphere_model: str = "nrlmsise00",
) -> ConditionsOptions:
    """The options of :func:`flight_conditions`, checked; ValueError naming a bad one."""
    frame_key = str(frame).lower()
    if frame_key not in STATE_FRAMES:
        raise ValueError(f"frame must be one of {', '.join(STATE_FRAMES)}, got {frame!r}")
    wind_frame_key = str(wind_frame).lower()
    if wind_frame_key not in WIND_FRAMES:
        raise ValueError(f"wind_frame must be one of {', '.join(WIND_FRAMES)}, got {wind_frame!r}")
    model = normalize_model_name(accommodation_model)
    if atmosphere_model not in ATMOSPHERE_MODELS:
        raise ValueError(
            f"atmosphere_model must be one of {', '.join(ATMOSPHERE_MODELS)}, "
            f"got {atmosphere_model!r}"
        )
    return ConditionsOptions(
        frame=frame_key,
        earth_rotation=bool(earth_rotation),
        wind=None if wind is None else _three_floats(wind, "wind"),
        wind_frame=wind_frame_key,
        anomalous_oxygen=bool(anomalous_oxygen),
        accommodation_model=model,
        accommodation_options=types.MappingProxyType(
            checked_options(model, accommodation_options or {})
        ),
        orientation_options=check_orientation_options(
            ut1_minus_utc, polar_motion, precession_nutation, precession_nutation_step
        ),
        atmosphere_model=atmosphere_model,
    )


def flight_conditions(
    time,
    position,
    velocity,
    space_weather: SpaceWeather,
    *,
    frame: str = "eci",
    earth_rotation: bool = True,
    wind=None,
    wind_frame: str = "enu",
    anomalous_oxygen: bool = True,
    accommodation_model: str = DEFAULT_ACCOMMODATION_MODEL,
    accommodation_options=None,
    orientation: EarthOrientation | None = None,
    ut1_minus_utc: float = 0.0,
    polar_motion=(0.0, 0.0),
    precession_nutation: str = "iau2006a",
    precession_nutation_step: float = 0.0,
    atmosphere_model: str = "nrlmsise00",
) -> FlightConditions:
    """Flight conditions of a satellite from its orbital state.

    Parameters
    ----------
    time : UTC (aware, or naive meaning UTC), years 1958..2100
    space_weather : a source of indices (a SpaceWeather, or a HistoricalWeather of the record)
    position : (3,) [m] in ``frame``
    velocity : (3,) [m/s], inertial in ECI axes, or relative to the rotating Earth in ECEF axes
    frame : ``"eci"`` (GCRF) or ``"ecef"`` (ITRF)
    earth_rotation : air co-rotating with the Earth (default) or at rest in ECI
    wind : (3,) relative to the co-rotating Earth [m/s], in ``wind_frame`` (``"enu"`` or ``"ecef"``)
    accommodation_model : ``fixed``, ``langmuir`` (default), ``goodman`` or ``sesam``
    orientation : an EarthOrientation at ``time`` (then the Earth orientation options are ignored)
    atmosphere_model : ``nrlmsise00`` (default), ``msis2.0`` or ``msis2.1``

    ValueError: a bad frame, vector, altitude (0..1000 km), time, space weather or option (named).
    """
    options = conditions_options(
        frame=frame,
        earth_rotation=earth_rotation,
        wind=wind,
        wind_frame=wind_frame,
        anomalous_oxygen=anomalous_oxygen,
        accommodation_model=accommodation_model,
        accommodation_options=accommodation_options,
        ut1_minus_utc=ut1_minus_utc,
        polar_motion=polar_motion,
        precession_nutation=precession_nutation,
        precession_nutation_step=precession_nutation_step,
        atmosphere_model=atmosphere_model,
    )
    return evaluate_flight_conditions(time, position, velocity, space_weather, options, orientation)


def evaluate_flight_conditions(
    time,
    position,
    velocity,
    space_weather: SpaceWeather,
    options: ConditionsOptions,
    orientation: EarthOrientation | None = None,
) -> FlightConditions:
    """:func:`flight_conditions` with options from :func:`conditions_options`."""
    utc = checked_utc(time)
    frame_key = options.frame
    model = options.accommodation_model
    position = _three_floats(position, "position")
    velocity = _three_floats(velocity, "velocity")
    jd1, tt_minus_utc, day_of_year = utc_day(utc.year, utc.month, utc.day)
    seconds = seconds_of_day(utc)
    if orientation is None:
        matrix, _, omega = rotation_floats(
            jd1, seconds / 86400.0, tt_minus_utc, *options.orientation_options
        )
    elif not isinstance(orientation, EarthOrientation):
        raise ValueError(
            f"orientation must be an EarthOrientation, got {type(orientation).__name__}"
        )
    elif orientation.time != utc.replace(tzinfo=None):
        raise ValueError(
            f"orientation is for {orientation.time.isoformat()}, "
            f"not for time {utc.replace(tzinfo=None).isoformat()}"
        )
    else:
        matrix = tuple(orientation.celestial_to_terrestrial.ravel().tolist())  # r_ecef = R r_eci
        omega = tuple(orientation.rotation_vector_ecef.tolist())
    vectors, latitude, longitude, altitude, speed = state_kinematics(
        matrix,
        omega,
        frame_key,
        position,
        velocity,
        options.wind,
        options.wind_frame,
        options.earth_rotation,
    )
    try:
        check_altitude(altitude)
    except ValueError as exc:
        raise ValueError(f"position: {exc}") from None
    if not isinstance(space_weather, SpaceWeather) and hasattr(space_weather, "at"):
        space_weather = space_weather.at(utc)  # (the indices of this time)
    atmosphere = run_model(
        utc.year,
        day_of_year,
        seconds,
        altitude,
        latitude,
        longitude,
        space_weather,
        options.anomalous_oxygen,
        model=options.atmosphere_model,
    )
    speed = _finite("speed", speed)  # (an infinite speed is refused by name)
    # (the options' names were checked with the options; the model checks their values)
    alpha = ACCOMMODATION_MODELS[model](atmosphere, speed, **options.accommodation_options)
    vectors = np.array(vectors)
    vectors.setflags(write=False)  # one read-only (6, 3) array, the fields its rows
    return FlightConditions(
        time=utc,
        position_eci=vectors[0],
        position_ecef=vectors[1],
        velocity_eci=vectors[2],
        velocity_ecef=vectors[3],
        latitude=latitude,
        longitude=longitude,
        altitude=altitude,
        atmosphere=atmosphere,
        relative_velocity_eci=vectors[4],
        relative_velocity_ecef=vectors[5],
        speed=speed,
        accommodation_model=model,
        accommodation_coefficient=float(alpha),
        earth_rotation=options.earth_rotation,
        space_weather=space_weather,
    )


def _three_floats(value, name: str) -> tuple:
    """The three finite floats of a 3-vector, or ValueError naming ``name``."""
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be three numbers, got {value!r}") from None
    if array.shape != (3,):
        raise ValueError(f"{name} must be a 3-vector, got shape {array.shape}")
    x, y, z = array.tolist()
    if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z)):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return x, y, z
