"""Flight conditions: where a satellite is, what gas it meets and how fast it meets it.

:func:`flight_conditions` takes a UTC time, an orbital state (position [m], velocity [m/s]) in
ECI (GCRF) or ECEF (ITRF) and the space weather, and returns :class:`FlightConditions`: WGS-84
geodetic position, NRLMSISE-00 atmosphere, mean molecular mass, relative velocity, speed ratio and
an accommodation coefficient, plus :meth:`FlightConditions.free_stream` for the gas-surface models.

Relative velocity
-----------------
``relative_velocity_*`` is the velocity of the satellite relative to the local air,
``v_sat - v_air``: the gas flows past the satellite along its negative. With ``earth_rotation``
(the default) the air co-rotates with the Earth, ``v_air = omega x r + wind``, so in ECEF axes
``v_rel = v_sat,ecef - wind``. With ``earth_rotation=False`` the air is at rest in ECI (plus the
wind), as in ADBSat's circular-orbit speed. The ECI and ECEF vectors are the same physical vector
in two sets of axes (no transport term: they differ by the rotation only).

A satellite at rest relative to the air has zero relative speed: :class:`FlightConditions` is
still returned (speed 0, speed ratio 0; accommodation models take the zero-speed limit), but
:meth:`FlightConditions.free_stream` raises ValueError because a free stream needs a speed > 0;
check :attr:`FlightConditions.speed` first if that can happen.

:func:`flight_conditions_circular_orbit` is ADBSat's ``environment.m`` recipe: a geodetic point
and the circular-orbit speed sqrt(mu / (R_E + h)), with no direction (no co-rotation, no wind).

Units: m, m/s, kg, K, rad inside; degrees only in names ending ``_deg``.
"""

from __future__ import annotations

import datetime as _dt
import math
from dataclasses import dataclass, field

import numpy as np

from adbsat_ros.environment.accommodation import accommodation_of, normalize_model_name
from adbsat_ros.environment.atmosphere import (
    _MODEL_STATE_SPECIES,
    FIRST_YEAR,
    LAST_YEAR,
    MAX_ALTITUDE,
    AtmosphereState,
    SpaceWeather,
    check_altitude,
    check_time,
    checked_utc,
    evaluate_atmosphere,
    gas_mixture,
    interpolated_atmosphere,
    run_model,
)
from adbsat_ros.environment.earth_frames import (
    EarthOrientation,
    check_orientation_options,
    earth_orientation,
    rotation_terms,
)
from adbsat_ros.environment.geodetic import enu_to_ecef, geodetic_of_floats, geodetic_to_ecef
from adbsat_ros.environment.time_scales import utc_day
from adbsat_ros.physics.constants import BOLTZMANN, EARTH_MU, EARTH_RADIUS_ADBSAT
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.validation import non_negative as _non_negative

#: Frames an orbital state may be given in.
STATE_FRAMES = ("eci", "ecef")
#: Frames a wind vector may be given in.
WIND_FRAMES = ("enu", "ecef")
#: Default accommodation model.
DEFAULT_ACCOMMODATION_MODEL = "langmuir"

#: Units of the numeric fields of :meth:`FlightConditions.as_dict`.
_UNITS = {
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


_FLOAT64 = np.dtype(np.float64)
_NDARRAY = np.ndarray
_SHAPE3 = (3,)
_UTC = _dt.timezone.utc
#: The vector fields flight_conditions makes on first read, in the order of ``_vectors``.
_VECTOR_FIELDS = (
    "position_eci",
    "position_ecef",
    "velocity_eci",
    "velocity_ecef",
    "relative_velocity_eci",
    "relative_velocity_ecef",
)
#: Checked option arguments of flight_conditions (frame and wind-frame keys, model name, Earth-
#: orientation options) by the arguments as given: a message stream repeats the same options,
#: so they are checked once (by the full checks, with their errors) and looked up afterwards.
_CHECKED_OPTIONS: dict = {}
_MAX_CHECKED_OPTIONS = 64


def _readonly(array):
    """Make a freshly computed (never a caller's) array read-only."""
    if array is not None:
        array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class FlightConditions:
    """Conditions a spacecraft flies in at one instant.

    Attributes
    ----------
    time : datetime.datetime
        UTC instant (timezone-aware, UTC).
    position_eci, position_ecef : numpy.ndarray, shape (3,)
        Position in ECI (GCRF) and ECEF (ITRF) [m].
    velocity_eci : numpy.ndarray or None
        Inertial velocity in ECI axes [m/s]; None for the circular-orbit convenience.
    velocity_ecef : numpy.ndarray or None
        Velocity relative to the rotating Earth, ECEF axes [m/s]; None as above.
    latitude, longitude : float
        WGS-84 geodetic latitude and east longitude [rad].
    altitude : float
        Height above the WGS-84 ellipsoid [m].
    atmosphere : AtmosphereState
        NRLMSISE-00 state (densities [m^-3], mass density [kg/m^3], temperatures [K]).
    mean_molecular_mass : float
        Number-weighted mean molecular mass of the mixture [kg] (as ADBSat).
    relative_velocity_eci, relative_velocity_ecef : numpy.ndarray or None
        Velocity of the satellite relative to the air (satellite minus co-rotating atmosphere
        minus wind) in ECI and ECEF axes [m/s]; None when only a speed is known (circular orbit).
    speed : float
        |relative velocity| [m/s], >= 0.
    speed_ratio : float
        s = speed / sqrt(2 k_B T / m) [-].
    accommodation_model : str
        Name of the accommodation model used.
    accommodation_coefficient : float
        Energy accommodation coefficient alpha [-].
    earth_rotation : bool
        Whether the air co-rotates with the Earth.
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
    mean_molecular_mass: float
    relative_velocity_eci: np.ndarray | None
    relative_velocity_ecef: np.ndarray | None
    speed: float
    speed_ratio: float
    accommodation_model: str
    accommodation_coefficient: float
    earth_rotation: bool = True
    space_weather: SpaceWeather | None = field(default=None, repr=False)

    @property
    def alpha(self) -> float:
        """Shorthand for :attr:`accommodation_coefficient`."""
        return self.accommodation_coefficient

    @property
    def temperature(self) -> float:
        """Local gas temperature [K]."""
        return self.atmosphere.temperature

    @property
    def mass_density(self) -> float:
        """Total mass density [kg/m^3] (with anomalous O if the atmosphere includes it)."""
        return self.atmosphere.mass_density

    def relative_velocity_floats(self, frame: str) -> tuple | None:
        """The relative velocity in ``frame`` ('eci' or 'ecef') axes as three Python floats [m/s].

        The same numbers as ``relative_velocity_eci`` / ``relative_velocity_ecef``, without making
        the array (for per-message code working on floats); None when only a speed is known.
        """
        relative = self.__dict__.get("_relative")
        if relative is not None and (frame == "eci" or frame == "ecef"):  # interpolated conditions
            return relative[frame == "ecef"]
        index = _VECTOR_FIELDS.index(f"relative_velocity_{frame}")
        vectors = self.__dict__.get("_vectors")
        if vectors is not None and _VECTOR_FIELDS[index] not in self.__dict__:
            return vectors[index]
        vector = getattr(self, _VECTOR_FIELDS[index])
        return None if vector is None else tuple(vector.tolist())

    @property
    def flow_direction_ecef(self) -> np.ndarray | None:
        """Unit vector along which the gas moves past the satellite, ECEF axes: -v_rel / |v_rel|.

        None if the speed is zero or only a speed is known.
        """
        if self.relative_velocity_ecef is None or self.speed == 0.0:
            return None
        return -self.relative_velocity_ecef / self.speed

    def as_dict(self) -> dict:
        """Every field as JSON-ready Python values, in SI units (rad, m, m/s, kg, K, m^-3).

        Vectors become lists (or None), the time an ISO 8601 string; ``units`` maps each
        numeric field to its unit.
        """

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
            "units": dict(_UNITS),
        }

    def free_stream(self) -> FreeStream:
        """The free stream for the gas-surface models.

        speed = |v_rel|, temperature = local T, number_densities = the mixture's species
        (with "AnO" iff the atmosphere includes anomalous oxygen), density = total mass density.

        Raises
        ------
        ValueError
            If the relative speed is zero (a free stream needs speed > 0).
        """
        speed = self.speed
        if not speed > 0.0:
            raise ValueError(
                "relative speed is 0 m/s (the satellite is at rest in the air): "
                "no free stream; check FlightConditions.speed before asking for one"
            )
        fields = self.__dict__
        mixture = fields.get("_free_stream_mixture")
        if mixture is not None:  # interpolated conditions: their mixture, checked (gas_mixture)
            species, values, temperature, mass_density, mean_mass = mixture
            return FreeStream._of_checked_mixture(
                speed, temperature, species, values, mass_density, mean_mass
            )
        atmosphere = self.atmosphere
        mixture = atmosphere.__dict__.get("_free_stream_mixture")
        if mixture is not None and type(speed) is float and speed < math.inf:
            # an atmosphere of run_model, whose mixture passed of_mixture's checks there
            species, values, mean_mass = mixture
            return FreeStream._of_checked_mixture(
                speed,
                atmosphere.temperature,
                species,
                values,
                atmosphere.mass_density,
                mean_mass,
            )
        return FreeStream.of_mixture(
            speed,
            atmosphere.temperature,
            atmosphere.mixture_species,
            atmosphere._mixture_densities,
            atmosphere.mass_density,
        )


class _VectorOnFirstRead:
    """A vector field of :class:`FlightConditions` as :func:`flight_conditions` makes it.

    The function keeps the six vectors as float tuples (``_vectors``) and each becomes its
    read-only array when first read (callers read one or two of them per message), then an
    ordinary instance attribute. A non-data descriptor: conditions made by the constructor hold
    their arrays in the instance, which takes precedence.
    """

    __slots__ = ("name", "index")

    def __init__(self, name: str, index: int):
        self.name = name
        self.index = index

    def __get__(self, instance, owner=None):
        if instance is None:
            return self
        fields = instance.__dict__
        if "_vectors" not in fields and "_interpolation" in fields:
            _complete_interpolation(fields)
        try:
            vector = fields["_vectors"][self.index]
        except KeyError:
            raise AttributeError(
                f"{type(instance).__name__!r} object has no attribute {self.name!r}"
            ) from None
        if vector is not None:
            vector = np.array(vector)
            vector.setflags(write=False)
        return fields.setdefault(self.name, vector)


for _index, _name in enumerate(_VECTOR_FIELDS):
    setattr(FlightConditions, _name, _VectorOnFirstRead(_name, _index))
del _index, _name


class _InterpolatedOnFirstRead:
    """A field of :class:`FlightConditions` that :func:`interpolated_flight_conditions` leaves to
    its first read: the geodetic position and the atmosphere (a message's wrench needs neither).
    All of them are made then (:func:`_complete_interpolation`), and become instance attributes.
    A non-data descriptor, like :class:`_VectorOnFirstRead`."""

    __slots__ = ("name",)

    def __init__(self, name: str):
        self.name = name

    def __get__(self, instance, owner=None):
        if instance is None:
            return self
        fields = instance.__dict__
        if "_interpolation" not in fields:
            raise AttributeError(
                f"{type(instance).__name__!r} object has no attribute {self.name!r}"
            )
        _complete_interpolation(fields)
        return fields[self.name]


#: The fields interpolated_flight_conditions defers (with the six vectors, _vectors).
_DEFERRED_FIELDS = ("latitude", "longitude", "altitude", "atmosphere")
for _name in _DEFERRED_FIELDS:
    setattr(FlightConditions, _name, _InterpolatedOnFirstRead(_name))
del _name


def _vector_floats(conditions: FlightConditions) -> tuple:
    """The six vectors of ``conditions`` (order of ``_VECTOR_FIELDS``) as float tuples or None."""
    vectors = conditions.__dict__.get("_vectors")
    if vectors is not None:
        return vectors
    return tuple(
        None if (v := getattr(conditions, name)) is None else tuple(v.tolist())
        for name in _VECTOR_FIELDS
    )


def interpolated_flight_conditions(
    a: FlightConditions, b: FlightConditions, weight: float, time: _dt.datetime
) -> FlightConditions:
    """The flight conditions at ``time``, a fraction ``weight`` (0..1) of the way from ``a`` to ``b``.

    ``a`` and ``b`` are :func:`flight_conditions` of one orbital state propagated to two nearby
    instants (the same options and space weather; ``b`` at the later one). Every vector, the
    atmosphere (:func:`adbsat_ros.environment.atmosphere.interpolated_atmosphere`) and the accommodation
    coefficient are interpolated linearly; the geodetic position is that of the interpolated ECEF
    position (exact, also over a pole), and the speed and speed ratio are recomputed from the
    interpolated relative velocity and atmosphere. For a first-order propagated state the positions
    are linear in time, so the interpolated position is the propagated one (to rounding); the other
    fields are smooth along the orbit, and the error is of order (h/L)^2 for knots h metres apart and
    fields that vary over L (hundreds of km horizontally, tens of km vertically): about 2e-9 of the
    density at 77 m (10 ms at 7.7 km/s), see test_flight_conditions. NRLMSISE-00's own steps (e.g.
    at exactly 300 km) are spread over the interval that crosses them.

    What a message's wrench reads (speed, speed ratio, mean mass, alpha, relative velocity,
    :meth:`FlightConditions.free_stream`) is made at once; the geodetic position, the atmosphere
    and the other vectors on first read, from the same mixes (so the same numbers whichever comes
    first): in a warm loop 6 instead of 10 us per call (docs/benchmarks.md, session 10).

    Raises
    ------
    ValueError
        If the two conditions were made with different options (accommodation model, Earth rotation,
        space weather, anomalous oxygen).
    """
    if (
        a.accommodation_model != b.accommodation_model
        or a.earth_rotation != b.earth_rotation
        or (a.space_weather is not b.space_weather and a.space_weather != b.space_weather)
    ):
        raise ValueError("interpolated_flight_conditions: a and b were made with different options")
    if weight == 0.0:  # a itself, at the time given (its fields are immutable or read-only arrays)
        conditions = _new_conditions(FlightConditions)
        conditions.__dict__.update(a.__dict__)
        conditions.__dict__["time"] = time
        return conditions
    numbers_a, numbers_b = _interpolation_numbers(a), _interpolation_numbers(b)
    if numbers_a is not None and numbers_b is not None:
        v = 1.0 - weight
        # each number as _complete_interpolation and interpolated_atmosphere mix it
        rx, ry, rz, ex, ey, ez, temperature, mass_density, he, o, n2, o2, ar, h, n, ano, alpha = [
            v * p + weight * q for p, q in zip(numbers_a, numbers_b)
        ]
        anomalous_oxygen = a.atmosphere.anomalous_oxygen
        species, values, mean_mass, usable = gas_mixture(
            he, o, n2, o2, ar, h, n, ano, mass_density, temperature, anomalous_oxygen
        )
        if usable and anomalous_oxygen == b.atmosphere.anomalous_oxygen:
            speed = math.sqrt(ex * ex + ey * ey + ez * ez)
            conditions = _new_conditions(FlightConditions)
            conditions.__dict__.update(
                {
                    "time": time,
                    "_interpolation": (a, b, weight),
                    "_relative": ((rx, ry, rz), (ex, ey, ez)),
                    "_free_stream_mixture": (species, values, temperature, mass_density, mean_mass),
                    "mean_molecular_mass": mean_mass,
                    "speed": speed,
                    "speed_ratio": _speed_ratio(speed, temperature, mean_mass),
                    "accommodation_model": a.accommodation_model,
                    "accommodation_coefficient": alpha,
                    "earth_rotation": a.earth_rotation,
                    "space_weather": a.space_weather,
                }
            )
            return conditions
    # (no relative velocity, or a mixture a free stream would not take: everything now, the same way)
    whole = {"_interpolation": (a, b, weight)}
    _complete_interpolation(whole)
    vectors = whole["_vectors"]
    if vectors[5] is None:
        speed = (1.0 - weight) * a.speed + weight * b.speed
    else:
        x, y, z = vectors[5]
        speed = math.sqrt(x * x + y * y + z * z)
    return _made_conditions(
        time,
        vectors,
        whole["latitude"],
        whole["longitude"],
        whole["altitude"],
        whole["atmosphere"],
        speed,
        a.accommodation_model,
        (1.0 - weight) * a.accommodation_coefficient + weight * b.accommodation_coefficient,
        a.earth_rotation,
        a.space_weather,
    )


def _interpolation_numbers(conditions: FlightConditions) -> tuple | None:
    """The numbers :func:`interpolated_flight_conditions` mixes of conditions it interpolates
    between (relative velocity in ECI and ECEF, temperature, mass density, the eight number
    densities of :func:`adbsat_ros.environment.atmosphere.interpolated_atmosphere`, alpha), kept with them;
    None without a relative velocity or an atmosphere of the model's species."""
    fields = conditions.__dict__
    numbers = fields.get("_interpolation_numbers")
    if numbers is None and "_interpolation_numbers" not in fields:
        vectors = _vector_floats(conditions)
        atmosphere = conditions.atmosphere
        densities = atmosphere.number_densities
        if (
            vectors[4] is None
            or vectors[5] is None
            or any(name not in densities for name in _MODEL_STATE_SPECIES)
        ):
            numbers = None
        else:
            numbers = (
                *vectors[4],
                *vectors[5],
                atmosphere.temperature,
                atmosphere.mass_density,
                *(densities[name] for name in _MODEL_STATE_SPECIES),
                conditions.accommodation_coefficient,
            )
        fields["_interpolation_numbers"] = numbers
    return numbers


def _complete_interpolation(fields: dict) -> None:
    """Fill in the deferred fields of interpolated conditions (their ``__dict__``): the six
    vectors mixed linearly, the geodetic position of the mixed ECEF position (exact, also over a
    pole) and the interpolated atmosphere."""
    a, b, weight = fields["_interpolation"]
    v = 1.0 - weight

    def mix(p, q):
        if p is None:
            return None
        return v * p[0] + weight * q[0], v * p[1] + weight * q[1], v * p[2] + weight * q[2]

    pa, qa, ra, sa, ta, ua = _vector_floats(a)
    pb, qb, rb, sb, tb, ub = _vector_floats(b)
    vectors = (mix(pa, pb), mix(qa, qb), mix(ra, rb), mix(sa, sb), mix(ta, tb), mix(ua, ub))
    latitude, longitude, altitude = geodetic_of_floats(*vectors[1])
    fields.update(
        {
            "_vectors": vectors,
            "latitude": latitude,
            "longitude": longitude,
            "altitude": altitude,
            "atmosphere": interpolated_atmosphere(a.atmosphere, b.atmosphere, weight),
        }
    )


def _three_floats(value, name: str) -> tuple:
    """The three finite floats of a 3-vector (checked as :func:`_vector3`, faster for arrays)."""
    if type(value) is np.ndarray and value.dtype is _FLOAT64 and value.shape == (3,):
        x, y, z = value.tolist()
        if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z)):
            raise ValueError(f"{name} must be finite, got {value!r}")
        return x, y, z
    return tuple(_vector3(value, name).tolist())


def _rotate(m, x, y, z) -> tuple:
    """``M @ (x, y, z)`` for a 3x3 matrix M given as 9 floats, row-major."""
    return (
        m[0] * x + m[1] * y + m[2] * z,
        m[3] * x + m[4] * y + m[5] * z,
        m[6] * x + m[7] * y + m[8] * z,
    )


def _rotate_back(m, x, y, z) -> tuple:
    """``M.T @ (x, y, z)`` (the inverse rotation) for M given as 9 floats, row-major."""
    return (
        m[0] * x + m[3] * y + m[6] * z,
        m[1] * x + m[4] * y + m[7] * z,
        m[2] * x + m[5] * y + m[8] * z,
    )


def _minus(a, b) -> tuple:
    """a - b of two 3-tuples."""
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _vector3(value, name: str) -> np.ndarray:
    """A new float array of shape (3,) (a copy: results never alias the caller's arrays)."""
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be three numbers, got {value!r}") from None
    if array.shape != (3,):
        raise ValueError(f"{name} must be a 3-vector, got shape {array.shape}")
    if not all(map(math.isfinite, array.tolist())):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return array


def _speed_ratio(speed: float, temperature: float, mean_mass: float) -> float:
    """s = V / sqrt(2 k_B T / m) for a speed [m/s], temperature [K] and mean molecular mass [kg]."""
    return speed / math.sqrt(2.0 * BOLTZMANN * temperature / mean_mass)


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
) -> FlightConditions:
    """Flight conditions of a satellite from its orbital state.

    Parameters
    ----------
    time : datetime.datetime
        UTC instant, timezone-aware or naive meaning UTC, years 1958..2100.
    position : array_like, shape (3,)
        Position [m] in ``frame``.
    velocity : array_like, shape (3,)
        Velocity [m/s] in ``frame``: inertial velocity in ECI axes for ``"eci"``, velocity
        relative to the rotating Earth in ECEF axes for ``"ecef"``.
    space_weather : SpaceWeather
        F10.7 (previous day), F10.7 81-day average, Ap (+ optional Ap history).
    frame : {"eci", "ecef"}, optional
        Frame of ``position`` and ``velocity``: ECI = GCRF, ECEF = ITRF.
    earth_rotation : bool, optional
        Air co-rotating with the Earth (default True) or at rest in ECI.
    wind : array_like, shape (3,), optional
        Wind velocity relative to the co-rotating Earth [m/s], in ``wind_frame``.
    wind_frame : {"enu", "ecef"}, optional
        Local East-North-Up at the satellite's geodetic position (default) or ECEF axes.
    anomalous_oxygen : bool, optional
        Include NRLMSISE-00's anomalous oxygen in the mixture and mass density (default True).
    accommodation_model : str, optional
        ``fixed``, ``langmuir`` (default), ``goodman`` or ``sesam``
        (see :mod:`adbsat_ros.environment.accommodation`).
    accommodation_options : mapping, optional
        Options of the model, e.g. ``{"alpha": 0.9}`` for ``fixed``.
    orientation : EarthOrientation, optional
        Precomputed Earth orientation at ``time`` (saves ~40 us when evaluating several states at
        one instant); the three options below are then ignored.
    ut1_minus_utc, polar_motion, precession_nutation, precession_nutation_step
        Earth-orientation options, see :func:`adbsat_ros.environment.earth_frames.earth_orientation`.

    Returns
    -------
    FlightConditions

    Raises
    ------
    ValueError
        Naming the input: bad frame names, non-finite or mis-shaped vectors, an altitude outside
        0..1000 km, a time outside 1958..2100, invalid space weather or accommodation options.
    """
    # The per-message case: the options of an earlier call, an aware UTC time, float64 3-vectors.
    # Anything else (and any input these few tests do not pass) takes the checked path, which
    # checks every input as documented and raises its error.
    try:
        options = _CHECKED_OPTIONS[
            frame,
            wind_frame,
            accommodation_model,
            ut1_minus_utc,
            polar_motion,
            precession_nutation,
            precession_nutation_step,
        ]
    except (KeyError, TypeError):
        options = None
    if (
        options is not None
        and orientation is None
        and type(time) is _dt.datetime
        and time.tzinfo is _UTC
        and FIRST_YEAR <= time.year <= LAST_YEAR
        and type(position) is _NDARRAY
        and position.dtype is _FLOAT64
        and position.shape == _SHAPE3
        and type(velocity) is _NDARRAY
        and velocity.dtype is _FLOAT64
        and velocity.shape == _SHAPE3
    ):
        x, y, z = position.tolist()
        vx, vy, vz = velocity.tolist()
        total = x + y + z + vx + vy + vz
        if wind is not None:
            if type(wind) is _NDARRAY and wind.dtype is _FLOAT64 and wind.shape == _SHAPE3:
                wind = tuple(wind.tolist())
                total += wind[0] + wind[1] + wind[2]
            else:
                total = math.nan
        if total - total == 0.0:  # all finite (an overflowing sum just takes the checked path)
            frame_key, wind_frame_key, model, orientation_options = options
            return _evaluate(
                time,
                (x, y, z),
                (vx, vy, vz),
                wind,
                space_weather,
                frame_key,
                earth_rotation,
                wind_frame_key,
                anomalous_oxygen,
                model,
                accommodation_options,
                orientation_options,
                None,
            )
    return _checked_flight_conditions(
        time,
        position,
        velocity,
        space_weather,
        frame,
        earth_rotation,
        wind,
        wind_frame,
        anomalous_oxygen,
        accommodation_model,
        accommodation_options,
        orientation,
        ut1_minus_utc,
        polar_motion,
        precession_nutation,
        precession_nutation_step,
    )


def _checked_flight_conditions(
    time,
    position,
    velocity,
    space_weather,
    frame,
    earth_rotation,
    wind,
    wind_frame,
    anomalous_oxygen,
    accommodation_model,
    accommodation_options,
    orientation,
    ut1_minus_utc,
    polar_motion,
    precession_nutation,
    precession_nutation_step,
) -> FlightConditions:
    """:func:`flight_conditions` with every input checked (ValueError naming it) and normalised;
    remembers the checked options for the per-message case."""
    utc = checked_utc(time)
    frame_key = str(frame).lower()
    if frame_key not in STATE_FRAMES:
        raise ValueError(f"frame must be one of {', '.join(STATE_FRAMES)}, got {frame!r}")
    wind_frame_key = str(wind_frame).lower()
    if wind_frame_key not in WIND_FRAMES:
        raise ValueError(f"wind_frame must be one of {', '.join(WIND_FRAMES)}, got {wind_frame!r}")
    model = normalize_model_name(accommodation_model)
    position = _three_floats(position, "position")
    velocity = _three_floats(velocity, "velocity")
    wind_vector = None if wind is None else _three_floats(wind, "wind")
    orientation_options = None
    if orientation is None:
        orientation_options = check_orientation_options(
            ut1_minus_utc, polar_motion, precession_nutation, precession_nutation_step
        )
        key = (
            frame,
            wind_frame,
            accommodation_model,
            ut1_minus_utc,
            polar_motion,
            precession_nutation,
            precession_nutation_step,
        )
        if len(_CHECKED_OPTIONS) >= _MAX_CHECKED_OPTIONS:
            _CHECKED_OPTIONS.clear()
        try:
            _CHECKED_OPTIONS[key] = (frame_key, wind_frame_key, model, orientation_options)
        except TypeError:  # an unhashable argument (e.g. polar_motion as a list): not remembered
            pass
    elif not isinstance(orientation, EarthOrientation):
        raise ValueError(
            f"orientation must be an EarthOrientation, got {type(orientation).__name__}"
        )
    else:
        naive = utc.replace(tzinfo=None)
        if orientation.time != naive:
            raise ValueError(
                f"orientation is for {orientation.time.isoformat()}, not for time {naive.isoformat()}"
            )
    return _evaluate(
        utc,
        position,
        velocity,
        wind_vector,
        space_weather,
        frame_key,
        earth_rotation,
        wind_frame_key,
        anomalous_oxygen,
        model,
        accommodation_options,
        orientation_options,
        orientation,
    )


def _evaluate(
    utc,
    position,
    velocity,
    wind,
    space_weather,
    frame_key,
    earth_rotation,
    wind_frame_key,
    anomalous_oxygen,
    model,
    accommodation_options,
    orientation_options,
    orientation,
) -> FlightConditions:
    """The flight conditions from checked inputs: an aware UTC time, position, velocity and wind
    (or None) as float 3-tuples, the frame keys, the model name, and either the checked
    Earth-orientation options or an :class:`EarthOrientation` at ``utc``.

    The work is done on Python floats (3-vectors as tuples, the rotation as 9 floats, row-major):
    for single states this is several times faster than numpy; the result keeps the vectors as
    tuples and makes its arrays when they are read.
    """
    jd1, tt_minus_utc, day_of_year = utc_day(utc.year, utc.month, utc.day)
    seconds = (
        utc.hour * 3600.0 + utc.minute * 60.0 + utc.second + utc.microsecond * 1e-6
    )  # seconds_of_day
    if orientation is None:
        matrix, _, omega = rotation_terms(
            jd1, seconds / 86400.0, tt_minus_utc, *orientation_options
        )
    else:
        matrix = tuple(orientation.celestial_to_terrestrial.ravel().tolist())
        omega = tuple(orientation.rotation_vector_ecef.tolist())
    m0, m1, m2, m3, m4, m5, m6, m7, m8 = matrix  # R: r_ecef = R r_eci
    w0, w1, w2 = omega
    if frame_key == "eci":
        # r_ecef = R r_eci; v_ecef = R v_eci - omega x r_ecef
        position_eci = x, y, z = position
        velocity_eci = vx, vy, vz = velocity
        px = m0 * x + m1 * y + m2 * z
        py = m3 * x + m4 * y + m5 * z
        pz = m6 * x + m7 * y + m8 * z
        velocity_ecef = (
            (m0 * vx + m1 * vy + m2 * vz) - (w1 * pz - w2 * py),
            (m3 * vx + m4 * vy + m5 * vz) - (w2 * px - w0 * pz),
            (m6 * vx + m7 * vy + m8 * vz) - (w0 * py - w1 * px),
        )
        position_ecef = (px, py, pz)
    else:
        # r_eci = R^T r_ecef; v_eci = R^T (v_ecef + omega x r_ecef)
        position_ecef = px, py, pz = position
        velocity_ecef = vx, vy, vz = velocity
        position_eci = _rotate_back(matrix, px, py, pz)
        velocity_eci = _rotate_back(
            matrix, vx + (w1 * pz - w2 * py), vy + (w2 * px - w0 * pz), vz + (w0 * py - w1 * px)
        )
    latitude, longitude, altitude = geodetic_of_floats(px, py, pz)
    if not 0.0 <= altitude <= MAX_ALTITUDE:
        try:
            check_altitude(altitude)
        except ValueError as exc:
            raise ValueError(f"position: {exc}") from None
    atmosphere = run_model(
        utc.year,
        day_of_year,
        seconds,
        altitude,
        latitude,
        longitude,
        space_weather,
        anomalous_oxygen,
    )
    if wind is not None and wind_frame_key == "enu":
        wind = enu_to_ecef(latitude, longitude, *wind)
    if earth_rotation:
        # v_rel,ecef = v_ecef - wind; v_rel,eci = R^T v_rel,ecef
        relative_ecef = velocity_ecef if wind is None else _minus(velocity_ecef, wind)
        x, y, z = relative_ecef
        relative_eci = (
            m0 * x + m3 * y + m6 * z,
            m1 * x + m4 * y + m7 * z,
            m2 * x + m5 * y + m8 * z,
        )
    else:
        relative_eci = (
            velocity_eci if wind is None else _minus(velocity_eci, _rotate_back(matrix, *wind))
        )
        relative_ecef = x, y, z = _rotate(matrix, *relative_eci)
    speed = math.sqrt(x * x + y * y + z * z)
    if not speed < math.inf:
        _non_negative("speed", speed)  # raises, naming the speed
    if type(accommodation_options) is not dict:
        accommodation_options = dict(accommodation_options or {})
    alpha = accommodation_of(model, atmosphere, speed, accommodation_options)
    return _made_conditions(
        utc,
        (position_eci, position_ecef, velocity_eci, velocity_ecef, relative_eci, relative_ecef),
        latitude,
        longitude,
        altitude,
        atmosphere,
        speed,
        model,
        float(alpha),
        bool(earth_rotation),
        space_weather,
    )


def _made_conditions(
    time,
    vectors,
    latitude,
    longitude,
    altitude,
    atmosphere,
    speed,
    model,
    alpha,
    earth_rotation,
    space_weather,
) -> FlightConditions:
    """FlightConditions as FlightConditions(...) makes them, from checked values (the six vectors
    as float tuples in the order of ``_VECTOR_FIELDS``, made into arrays on first access); the
    mean mass and speed ratio follow from the atmosphere and the speed."""
    mean_mass = atmosphere.mean_mass
    conditions = _new_conditions(FlightConditions)
    conditions.__dict__.update(
        {
            "time": time,
            "_vectors": vectors,
            "latitude": latitude,
            "longitude": longitude,
            "altitude": altitude,
            "atmosphere": atmosphere,
            "mean_molecular_mass": mean_mass,
            "speed": speed,
            "speed_ratio": _speed_ratio(speed, atmosphere.temperature, mean_mass),
            "accommodation_model": model,
            "accommodation_coefficient": alpha,
            "earth_rotation": earth_rotation,
            "space_weather": space_weather,
        }
    )
    return conditions


_new_conditions = object.__new__


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
) -> FlightConditions:
    """Flight conditions at a geodetic point with the circular-orbit speed (ADBSat parity).

    As ADBSat's ``environment.m``: the atmosphere at (time, altitude, latitude, longitude) and the
    speed sqrt(mu / (R_E + h)) (:func:`circular_orbit_speed`), with no co-rotation and no wind.
    No direction is known, so the velocity and relative-velocity vectors are None.

    Parameters
    ----------
    time : datetime.datetime
        UTC instant (aware, or naive meaning UTC), years 1958..2100.
    altitude : float
        Height above the WGS-84 ellipsoid [m], 0..1000 km.
    latitude, longitude : float
        Geodetic latitude and east longitude [rad].
    space_weather : SpaceWeather
    anomalous_oxygen, accommodation_model, accommodation_options
        As :func:`flight_conditions`.
    speed : float, optional
        Relative speed [m/s] to use instead of the circular-orbit speed (>= 0).
    precession_nutation : str, optional
        Only used to express the position in ECI.

    Returns
    -------
    FlightConditions
    """
    time = check_time(time)
    model = normalize_model_name(accommodation_model)
    altitude = check_altitude(altitude)
    position_ecef = geodetic_to_ecef(latitude, longitude, altitude)
    atmosphere = evaluate_atmosphere(
        time, altitude, latitude, longitude, space_weather, anomalous_oxygen=anomalous_oxygen
    )
    if speed is None:
        speed = circular_orbit_speed(altitude)
    else:
        speed = float(speed)
        if not math.isfinite(speed) or speed < 0.0:
            raise ValueError(f"speed must be a finite number >= 0, got {speed!r}")
    orientation = earth_orientation(time, precession_nutation=precession_nutation)
    position_eci = position_ecef @ orientation.celestial_to_terrestrial
    return _assemble(
        time.replace(tzinfo=_dt.timezone.utc),
        _readonly(position_eci),
        _readonly(position_ecef),
        None,
        None,
        float(latitude),
        float(longitude),
        altitude,
        atmosphere,
        None,
        None,
        speed,
        model,
        accommodation_options,
        False,
        space_weather,
    )


def _assemble(
    time,
    position_eci,
    position_ecef,
    velocity_eci,
    velocity_ecef,
    latitude,
    longitude,
    altitude,
    atmosphere,
    relative_eci,
    relative_ecef,
    speed,
    model,
    accommodation_options,
    earth_rotation,
    space_weather,
) -> FlightConditions:
    mean_mass = atmosphere.mean_mass
    alpha = accommodation_of(model, atmosphere, speed, dict(accommodation_options or {}))
    return FlightConditions(
        time=time,
        position_eci=position_eci,
        position_ecef=position_ecef,
        velocity_eci=velocity_eci,
        velocity_ecef=velocity_ecef,
        latitude=float(latitude),
        longitude=float(longitude),
        altitude=float(altitude),
        atmosphere=atmosphere,
        mean_molecular_mass=mean_mass,
        relative_velocity_eci=relative_eci,
        relative_velocity_ecef=relative_ecef,
        speed=speed,
        speed_ratio=_speed_ratio(speed, atmosphere.temperature, mean_mass),
        accommodation_model=model,
        accommodation_coefficient=float(alpha),
        earth_rotation=earth_rotation,
        space_weather=space_weather,
    )
