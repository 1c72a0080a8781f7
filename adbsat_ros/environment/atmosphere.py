"""Thermosphere state from NRLMSISE-00 (Picone et al. 2002), ``gtd7``/``gtd7d`` with SI outputs.
``gtd7d`` (the default, as ADBSat's AnO flag) adds anomalous oxygen to the mass density. Units m,
kg, K, rad. docs/physics.md, section 5.2."""

from __future__ import annotations

import datetime as _dt
import functools
import math
import types
from dataclasses import dataclass
from typing import Mapping

import numpy as np
from nrlmsise00 import _nrlmsise00

from adbsat_ros.bounds import bounded
from adbsat_ros.environment.time_scales import seconds_of_day, utc_datetime, utc_day
from adbsat_ros.physics.constants import AVOGADRO, MOLAR_MASS_G, SPECIES
from adbsat_ros.validation import finite as _finite

#: The atmosphere models: NRLMSISE-00 (the nrlmsise00 package), NRLMSIS 2.0 and 2.1 (pymsis).
ATMOSPHERE_MODELS = ("nrlmsise00", "msis2.0", "msis2.1")
#: Largest altitude NRLMSISE-00 is evaluated at [m].
MAX_ALTITUDE = 1000e3
#: Range of UTC years accepted (the space-weather record starts in the late 1950s).
FIRST_YEAR, LAST_YEAR = 1958, 2100

#: Switches: 0 = SI output (m^-3, kg/m^3), 1..23 = all variations on (the model's standard set).
_SWITCHES_DAILY_AP = [1] * 24
#: As above with switch 9 = -1: use the 7-element Ap history.
_SWITCHES_AP_HISTORY = [1] * 9 + [-1] + [1] * 14
_SPECIES_MASS_KG = {name: MOLAR_MASS_G[name] / (1000.0 * AVOGADRO) for name in SPECIES}
_SPECIES_WITHOUT_ANO = tuple(s for s in SPECIES if s != "AnO")
_UTC = _dt.timezone.utc


@dataclass(frozen=True)
class SpaceWeather:
    """Solar and geomagnetic activity indices as NRLMSISE-00 defines them, each >= 0. ``f107``:
    previous day's F10.7 [sfu]; ``f107a``: its 81-day centred mean; ``ap``: daily Ap;
    ``ap_history``: NRLMSISE-00's 7-value Ap array, used by the storm-time formulation if given.
    ValueError: an index negative or non-finite, or a history not 7 long."""

    f107: float
    f107a: float
    ap: float
    ap_history: tuple | None = None

    def __post_init__(self):
        object.__setattr__(self, "f107", bounded("f107", self.f107))
        object.__setattr__(self, "f107a", bounded("f107a", self.f107a, "f107"))
        object.__setattr__(self, "ap", bounded("ap", self.ap))
        if self.ap_history is not None:
            try:
                history = tuple(self.ap_history)
            except TypeError:
                raise ValueError(f"ap_history must be 7 numbers, got {self.ap_history!r}") from None
            if len(history) != 7:
                raise ValueError(f"ap_history must have 7 elements, got {len(history)}")
            history = tuple(bounded(f"ap_history[{i}]", v, "ap") for i, v in enumerate(history))
            object.__setattr__(self, "ap_history", history)

    def at(self, time) -> "SpaceWeather":
        """The indices at ``time``: these, whatever the time (the ``fixed`` source)."""
        return self


@dataclass(frozen=True)
class AtmosphereState:
    """Neutral atmosphere at one place and time (NRLMSISE-00 output in SI units).
    ``number_densities`` [m^-3] by species (with "AnO"; O, H, N 0 below 72.5 km);
    ``mass_density`` [kg/m^3], with anomalous oxygen iff ``anomalous_oxygen``; temperatures [K]."""

    number_densities: Mapping[str, float]
    mass_density: float
    exospheric_temperature: float
    temperature: float
    anomalous_oxygen: bool = True

    def __post_init__(self):
        object.__setattr__(
            self, "number_densities", types.MappingProxyType(dict(self.number_densities))
        )
        object.__setattr__(self, "anomalous_oxygen", bool(self.anomalous_oxygen))

    @property
    def mixture_species(self) -> tuple:
        """Species of the gas mixture: the seven thermal species, plus "AnO" if included."""
        return SPECIES if self.anomalous_oxygen else _SPECIES_WITHOUT_ANO

    @property
    def mixture_densities(self) -> tuple:
        """Number densities [m^-3] of :attr:`mixture_species`, in that order."""
        densities = self.number_densities
        return tuple([densities[name] for name in self.mixture_species])

    @property
    def mixture_number_densities(self) -> Mapping[str, float]:
        """Number densities [m^-3] of :attr:`mixture_species`, read-only, in that order."""
        densities = self.number_densities
        if self.anomalous_oxygen and tuple(densities) == SPECIES:
            return densities
        return types.MappingProxyType({name: densities[name] for name in self.mixture_species})

    @property
    def total_number_density(self) -> float:
        """Sum of the mixture's number densities [m^-3]."""
        return sum(self.mixture_densities)

    @functools.cached_property
    def mean_mass(self) -> float:
        """Mean molecular mass [kg] summed as ``FreeStream.mean_mass`` (bit-equal)."""
        densities = self.number_densities
        total = 0.0
        weighted = 0.0
        for name in self.mixture_species:
            n = densities[name]
            total += n
            weighted += n * _SPECIES_MASS_KG[name]
        return weighted / total


def check_time(time) -> _dt.datetime:
    """Return ``time`` as a naive UTC datetime; ValueError naming it outside years 1958..2100."""
    time = utc_datetime(time)
    if not FIRST_YEAR <= time.year <= LAST_YEAR:
        raise ValueError(
            f"time must be between {FIRST_YEAR}-01-01 and {LAST_YEAR}-12-31 UTC, "
            f"got {time.isoformat()}"
        )
    return time


def checked_utc(time) -> _dt.datetime:
    """``time`` as a timezone-aware UTC datetime, checked as :func:`check_time`."""
    if type(time) is _dt.datetime and time.tzinfo is _UTC and FIRST_YEAR <= time.year <= LAST_YEAR:
        return time
    return check_time(time).replace(tzinfo=_UTC)


def check_altitude(altitude) -> float:
    """``altitude`` [m] as a float; ValueError naming it outside [0, 1000 km]."""
    altitude = _finite("altitude", altitude)
    if not 0.0 <= altitude <= MAX_ALTITUDE:
        raise ValueError(
            f"altitude must be between 0 and {MAX_ALTITUDE / 1e3:g} km (NRLMSISE-00 range), "
            f"got {altitude / 1e3:g} km"
        )
    return altitude


def evaluate_atmosphere(
    time,
    altitude: float,
    latitude: float,
    longitude: float,
    space_weather: SpaceWeather,
    *,
    anomalous_oxygen: bool = True,
    local_solar_time_h: float | None = None,
    model: str = "nrlmsise00",
) -> AtmosphereState:
    """Evaluate the atmosphere ``model`` (:data:`ATMOSPHERE_MODELS`) at one point.
    time: UTC (aware, or naive meaning UTC), years 1958 to 2100.
    altitude: above the WGS-84 ellipsoid [m], 0 to 1000 km.
    latitude, longitude: geodetic latitude [rad] in [-pi/2, pi/2], east longitude [rad].
    anomalous_oxygen: in the mixture and mass density (``gtd7d``, default) or not (``gtd7``).
    space_weather: a SpaceWeather, or a source of them (``at(time)``, space_weather.py).
    local_solar_time_h: [h]; default UT + longitude [deg] / 15 (override for published cases).
    ValueError: an input out of range, non-finite or of the wrong type (named)."""
    time = check_time(time)
    altitude = check_altitude(altitude)
    latitude = _finite("latitude", latitude)
    if abs(latitude) > math.pi / 2:
        raise ValueError(f"latitude must be in [-pi/2, pi/2] rad, got {latitude!r}")
    longitude = _finite("longitude", longitude)
    seconds = seconds_of_day(time)
    if local_solar_time_h is not None:
        local_solar_time_h = _finite("local_solar_time_h", local_solar_time_h)
    if not isinstance(space_weather, SpaceWeather) and hasattr(space_weather, "at"):
        space_weather = space_weather.at(time)
    return run_model(
        time.year,
        utc_day(time.year, time.month, time.day)[2],
        seconds,
        altitude,
        latitude,
        longitude,
        space_weather,
        anomalous_oxygen,
        local_solar_time_h,
        model,
    )


def run_model(
    year: int,
    day_of_year: int,
    seconds: float,
    altitude: float,
    latitude: float,
    longitude: float,
    space_weather: SpaceWeather,
    anomalous_oxygen: bool = True,
    local_solar_time_h: float | None = None,
    model: str = "nrlmsise00",
) -> AtmosphereState:
    """The atmosphere ``model`` at one point (``altitude`` [m], angles [rad], UTC ``seconds`` of
    the day); ``local_solar_time_h`` is NRLMSISE-00's only."""
    if not isinstance(space_weather, SpaceWeather):
        raise ValueError(
            f"space_weather must be a SpaceWeather(f107, f107a, ap), "
            f"got {type(space_weather).__name__}"
        )
    longitude_deg = (math.degrees(longitude) + 180.0) % 360.0 - 180.0
    if model != "nrlmsise00":
        densities, temperatures = _run_pymsis(
            model, year, day_of_year, seconds, altitude, latitude, longitude_deg, space_weather,
            anomalous_oxygen,
        )  # fmt: skip
    else:
        if local_solar_time_h is None:
            local_solar_time_h = (seconds / 3600.0 + longitude_deg / 15.0) % 24.0
        history = {"flags": _SWITCHES_DAILY_AP}
        if space_weather.ap_history is not None:
            history = {"ap_a": list(space_weather.ap_history), "flags": _SWITCHES_AP_HISTORY}
        gtd7 = _nrlmsise00.gtd7d if anomalous_oxygen else _nrlmsise00.gtd7
        # altitude in km and latitude in degrees, as the model takes them
        densities, temperatures = gtd7(
            year,
            day_of_year,
            seconds,
            altitude * 1e-3,
            math.degrees(latitude),
            longitude_deg,
            local_solar_time_h,
            space_weather.f107a,
            space_weather.f107,
            space_weather.ap,
            **history,
        )
    he, o, n2, o2, ar, rho, h, n, ano = densities  # NRLMSISE-00's order
    return AtmosphereState(
        {"He": he, "O": o, "N2": n2, "O2": o2, "Ar": ar, "H": h, "N": n, "AnO": ano},
        rho,
        temperatures[0],
        temperatures[1],
        anomalous_oxygen,
    )


def _run_pymsis(
    model, year, day_of_year, seconds, altitude, latitude, longitude_deg, weather, anomalous_oxygen
) -> tuple:
    """NRLMSIS 2.0 or 2.1 through pymsis, the indices passed (never looked up), as NRLMSISE-00's
    ``(densities, (exospheric temperature, temperature))``; the exospheric temperature is the
    model's at 1000 km (the asymptote of its Bates profile)."""
    import pymsis

    if model not in ATMOSPHERE_MODELS:
        raise ValueError(
            f"atmosphere_model must be one of {', '.join(ATMOSPHERE_MODELS)}, got {model!r}"
        )
    date = np.datetime64(f"{year:04d}-01-01") + np.timedelta64(
        round((day_of_year - 1) * 86400e6 + seconds * 1e6), "us"
    )
    history = weather.ap_history
    aps = [weather.ap] * 7 if history is None else list(history)
    out = pymsis.calculate(
        [date, date],
        [longitude_deg] * 2,
        [math.degrees(latitude)] * 2,
        [altitude * 1e-3, MAX_ALTITUDE * 1e-3],
        [weather.f107] * 2,
        [weather.f107a] * 2,
        [aps, aps],
        version=model[4:],
        geomagnetic_activity=1 if history is None else -1,
    ).astype(float)
    rho, n2, o2, o, he, h, ar, n, ano, _, temperature = np.nan_to_num(out[0]).tolist()
    if anomalous_oxygen:  # (NRLMSIS 2.x leaves it out of its mass density; gtd7d adds it)
        rho += ano * _SPECIES_MASS_KG["AnO"]
    return (he, o, n2, o2, ar, rho, h, n, ano), (float(out[1, 10]), temperature)
