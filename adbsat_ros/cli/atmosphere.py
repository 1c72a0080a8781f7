"""``adbsat-ros atmosphere``: flight conditions (NRLMSISE-00 atmosphere, speed, accommodation)
at a geodetic point (circular-orbit speed, as ADBSat's environment.m) or an orbital state.
"""

from __future__ import annotations

import datetime as _dt
import json
import math
import os
import sys

from adbsat_ros.cli.options import (
    CommandLineError,
    checked,
    errors_as,
    flag,
    number,
    option,
    parse_vector3,
)

#: Space weather used when not given: the NRLMSISE-00 reference test point (moderate activity).
DEFAULT_F107 = 150.0
DEFAULT_F107A = 150.0
DEFAULT_AP = 4.0
#: The ``--json`` keys of FlightConditions.as_dict's fields, named with their units as the CSV
#: columns are (docs/outputs.md); angles in degrees, as the table shows them and the options take.
JSON_KEYS = {
    "latitude": "latitude_deg",
    "longitude": "longitude_deg",
    "altitude": "altitude_m",
    "f107": "f107_sfu",
    "f107a": "f107a_sfu",
    "number_densities": "number_densities_per_m3",
    "mass_density": "density_kg_m3",
    "exospheric_temperature": "exospheric_temperature_K",
    "temperature": "temperature_K",
    "mean_molecular_mass": "mean_molecular_mass_kg",
    "speed": "relative_speed_m_s",
}
for _name, _unit in (("position", "m"), ("velocity", "m_s"), ("relative_velocity", "m_s")):
    for _frame in ("eci", "ecef"):
        JSON_KEYS[f"{_name}_{_frame}"] = f"{_name}_{_frame}_{_unit}"


def add_flight_arguments(parser, *, time_required: bool, with_alpha: bool) -> None:
    """Add the flight-condition options (time, place or state, space weather, gas)."""
    from adbsat_ros.environment.accommodation import accommodation_model_names

    help = "UTC time, e.g. 2015-01-19T00:00:00Z (no offset means UTC)"
    option(parser, "--time", help, required=time_required, metavar="ISO8601")
    where = parser.add_argument_group("geodetic point (WGS-84)")
    help = "height above the WGS-84 ellipsoid [km], 0..1000"
    option(where, "--altitude", help, bound="altitude", metavar="KM")
    option(where, "--lat", "geodetic latitude [deg], -90..90", bound="latitude", metavar="DEG")
    option(where, "--lon", "east longitude [deg], -360..360", bound="longitude", metavar="DEG")
    state = parser.add_argument_group("orbital state")
    option(state, "--position", "position [m] in --frame", metavar="X,Y,Z")
    help = "velocity [m/s] in --frame (inertial for eci, Earth-relative for ecef)"
    option(state, "--velocity", help, metavar="X,Y,Z")
    help = "frame of --position/--velocity: eci = GCRF, ecef = ITRF (default eci)"
    option(state, "--frame", help, choices=("eci", "ecef"), default=None)
    help = "wind [m/s] in local East-North-Up axes (needs --velocity)"
    option(state, "--wind", help, metavar="E,N,U")
    flag(
        state, "--no-earth-rotation", "air at rest in ECI instead of co-rotating (needs --velocity)"
    )
    weather = parser.add_argument_group("space weather")
    help = f"F10.7 of the previous day (default {DEFAULT_F107:g})"
    option(weather, "--f107", help, bound="f107", default=DEFAULT_F107, metavar="SFU")
    help = f"81-day average F10.7 (default {DEFAULT_F107A:g})"
    option(weather, "--f107a", help, bound="f107", default=DEFAULT_F107A, metavar="SFU")
    help = f"daily Ap (default {DEFAULT_AP:g})"
    option(weather, "--ap", help, bound="ap", default=DEFAULT_AP, metavar="AP")
    help = "NRLMSISE-00's 7-element Ap array (storm-time formulation)"
    option(weather, "--ap-history", help, metavar="A0,...,A6")
    help = (
        "fixed (--f107, --f107a, --ap, default) or historical (the indices of --time from "
        "CelesTrak's record, with the 3-hourly ap history)"
    )
    choices = ("fixed", "historical")
    option(weather, "--space-weather", help, choices=choices, default="fixed")
    help = "historical: a CelesTrak SW file (SW-All.txt format) instead of the shipped record"
    option(weather, "--space-weather-file", help, metavar="PATH")
    help = "nrlmsise00 (default), msis2.0 or msis2.1 (NRLMSIS 2.x through pymsis)"
    choices = ("nrlmsise00", "msis2.0", "msis2.1")
    option(weather, "--atmosphere-model", help, choices=choices, default="nrlmsise00")
    gas = parser.add_argument_group("gas and surface")
    help = "leave anomalous oxygen out of the mixture and the mass density (gtd7)"
    flag(gas, "--no-anomalous-oxygen", help)
    if with_alpha:  # the flight conditions' default model
        from adbsat_ros.environment.flight_conditions import DEFAULT_ACCOMMODATION_MODEL as default
    else:
        default = "fixed"
    help = f"accommodation model (default {default}; fixed uses --alpha)"
    names = accommodation_model_names()
    option(gas, "--accommodation", help, type=str.lower, choices=names, default=default)
    if with_alpha:
        help = "accommodation coefficient for --accommodation fixed, 0..1"
        option(gas, "--alpha", help, number, metavar="ALPHA")


def configure(parser) -> None:
    """Configure ``adbsat-ros atmosphere``."""
    parser.description = (
        "Evaluate NRLMSISE-00 and the flight conditions at a geodetic point "
        "(--altitude/--lat/--lon, circular-orbit speed as ADBSat) or at an orbital state "
        "(--position [--velocity] in --frame eci|ecef). --json keys name their units."
    )
    add_flight_arguments(parser, time_required=True, with_alpha=True)
    flag(parser, "--json", "print JSON, every key named with its unit (angles in degrees, else SI)")
    parser.set_defaults(func=run)


def _parse_time(text: str) -> _dt.datetime:
    from adbsat_ros.environment.atmosphere import FIRST_YEAR, LAST_YEAR

    try:
        time = _dt.datetime.fromisoformat(text.strip())
    except ValueError:
        raise CommandLineError(
            f"--time: {text!r} is not an ISO 8601 date-time (e.g. 2015-01-19T00:00:00Z)"
        ) from None
    if time.tzinfo is not None:
        time = time.astimezone(_dt.timezone.utc).replace(tzinfo=None)
    if not FIRST_YEAR <= time.year <= LAST_YEAR:
        raise CommandLineError(
            f"--time: must be between {FIRST_YEAR} and {LAST_YEAR}, got {text!r}"
        )
    return time


def _space_weather(args, time):
    """The indices in force at ``time`` (--space-weather)."""
    from adbsat_ros.environment.atmosphere import SpaceWeather
    from adbsat_ros.environment.space_weather import weather_source

    if args.space_weather_file and args.space_weather != "historical":
        raise CommandLineError("--space-weather-file: only valid with --space-weather historical")

    history = None
    if args.ap_history is not None:
        try:
            history = [float(v) for v in args.ap_history.split(",")]
        except ValueError:
            history = []
        if len(history) != 7 or not all(math.isfinite(v) and v >= 0 for v in history):
            raise CommandLineError(
                f"--ap-history: expected 7 finite numbers >= 0, got {args.ap_history!r}"
            )
    fixed = SpaceWeather(f107=args.f107, f107a=args.f107a, ap=args.ap, ap_history=history)
    return weather_source(args.space_weather, fixed, args.space_weather_file or "").at(time)


def _accommodation_options(args) -> dict:
    if args.accommodation == "fixed":
        if args.alpha is None:
            raise CommandLineError("--alpha: required with --accommodation fixed")
        if not 0.0 <= args.alpha <= 1.0:
            raise CommandLineError(f"--alpha: must be in [0, 1], got {args.alpha:g}")
        return {"alpha": args.alpha}
    if args.alpha is not None:
        raise CommandLineError(
            f"--alpha: only valid with --accommodation fixed (not {args.accommodation})"
        )
    return {}


def compute(args, accommodation_options=None):
    """The flight conditions the options give, the NRLMSISE-00 library's prints sent to stderr."""
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        os.dup2(2, 1)
        return _compute(args, accommodation_options)
    finally:
        os.dup2(saved, 1)
        os.close(saved)


def _compute(args, accommodation_options=None):
    """CommandLineError naming a bad option; ``accommodation_options`` replaces ``--alpha``'s."""
    from adbsat_ros.environment.atmosphere import MAX_ALTITUDE
    from adbsat_ros.environment.circular_orbit import flight_conditions_circular_orbit
    from adbsat_ros.environment.earth_frames import earth_orientation
    from adbsat_ros.environment.flight_conditions import flight_conditions
    from adbsat_ros.environment.geodetic import ecef_to_geodetic

    time = _parse_time(args.time)
    weather = _space_weather(args, time)
    options = (
        _accommodation_options(args) if accommodation_options is None else accommodation_options
    )
    gas = {
        "anomalous_oxygen": not args.no_anomalous_oxygen,
        "accommodation_model": args.accommodation,
        "accommodation_options": options,
        "atmosphere_model": args.atmosphere_model,
    }
    geodetic = [name for name in ("altitude", "lat", "lon") if getattr(args, name) is not None]
    if args.position is not None and geodetic:
        raise CommandLineError(
            f"--position: give either --position or --altitude/--lat/--lon, not both "
            f"(also got --{geodetic[0]})"
        )
    if args.position is None:
        for option in ("--velocity", "--frame", "--wind"):
            if getattr(args, option[2:]) is not None:
                raise CommandLineError(f"{option}: only valid with --position")
        if args.no_earth_rotation:
            raise CommandLineError("--no-earth-rotation: only valid with --position and --velocity")
        missing = [f"--{name}" for name in ("altitude", "lat", "lon") if name not in geodetic]
        if missing:
            raise CommandLineError(
                f"{missing[0]}: required (give --altitude, --lat and --lon, or --position)"
            )
        latitude, longitude = math.radians(args.lat), math.radians(args.lon)
        altitude = args.altitude * 1e3  # (--altitude and --lat are in range: their types check)
        return flight_conditions_circular_orbit(time, altitude, latitude, longitude, weather, **gas)
    frame = args.frame or "eci"
    position = parse_vector3(args.position, "--position")
    distance = math.hypot(*position.tolist())  # (before the geodetic conversion: overflows)
    checked("--position: the distance from the Earth's centre", distance, "position_radius")
    orientation = earth_orientation(time)
    position_ecef = position if frame == "ecef" else orientation.eci_to_ecef(position)[0]
    latitude, longitude, altitude = ecef_to_geodetic(position_ecef)
    if not 0.0 <= altitude <= MAX_ALTITUDE:
        raise CommandLineError(
            f"--position: altitude {altitude / 1e3:.6g} km is outside 0..{MAX_ALTITUDE / 1e3:g} km"
        )
    if args.velocity is None:
        if args.wind is not None:
            raise CommandLineError("--wind: only valid with --velocity")
        if args.no_earth_rotation:
            raise CommandLineError("--no-earth-rotation: only valid with --velocity")
        return flight_conditions_circular_orbit(time, altitude, latitude, longitude, weather, **gas)
    velocity = parse_vector3(args.velocity, "--velocity")
    checked("--velocity: the speed", math.hypot(*velocity.tolist()), "orbital_speed")
    wind = None if args.wind is None else parse_vector3(args.wind, "--wind", "wind")
    return flight_conditions(
        time,
        position,
        velocity,
        weather,
        frame=frame,
        earth_rotation=not args.no_earth_rotation,
        wind=wind,
        wind_frame="enu",
        orientation=orientation,
        **gas,
    )


def _vector_text(vector, scale=1.0, digits=6) -> str:
    if vector is None:
        return "-"
    return "(" + ", ".join(f"{x * scale:.{digits}g}" for x in vector) + ")"


def format_table(conditions) -> str:
    """The conditions as a table (degrees and km beside the SI values)."""
    atmosphere = conditions.atmosphere
    weather = conditions.space_weather
    rows = [
        ("time (UTC)", conditions.time.isoformat()),
        ("F10.7, 81-day F10.7, Ap", f"{weather.f107:g} sfu, {weather.f107a:g} sfu, {weather.ap:g}"),
        ("ap history", "-" if weather.ap_history is None else _vector_text(weather.ap_history)),
        ("latitude", f"{math.degrees(conditions.latitude):.6f} deg"),
        ("longitude", f"{math.degrees(conditions.longitude):.6f} deg"),
        ("altitude", f"{conditions.altitude / 1e3:.6f} km"),
        ("position ECEF", _vector_text(conditions.position_ecef) + " m"),
        ("position ECI", _vector_text(conditions.position_eci) + " m"),
    ]
    for name, value in atmosphere.number_densities.items():
        rows.append((f"n({name})", f"{value:.6e} m^-3"))
    rows += [
        (
            "mass density",
            f"{atmosphere.mass_density:.6e} kg/m^3"
            + (" (incl. anomalous O)" if atmosphere.anomalous_oxygen else " (excl. anomalous O)"),
        ),
        ("exospheric temperature", f"{atmosphere.exospheric_temperature:.3f} K"),
        ("temperature", f"{atmosphere.temperature:.3f} K"),
        ("mean molecular mass", f"{conditions.mean_molecular_mass:.6e} kg"),
        ("relative velocity ECI", _vector_text(conditions.relative_velocity_eci) + " m/s"),
        ("relative velocity ECEF", _vector_text(conditions.relative_velocity_ecef) + " m/s"),
        (
            "speed",
            f"{conditions.speed:.3f} m/s"
            + ("" if conditions.relative_velocity_ecef is not None else " (circular orbit)"),
        ),
        ("speed ratio", f"{conditions.speed_ratio:.6f}"),
        (
            f"alpha ({conditions.accommodation_model})",
            f"{conditions.accommodation_coefficient:.6f}",
        ),
    ]
    width = max(len(label) for label, _ in rows)
    return "\n".join(f"{label:<{width}}  {value}" for label, value in rows)


def json_document(conditions) -> dict:
    """``conditions.as_dict()`` under :data:`JSON_KEYS`, angles in degrees, no ``units`` table."""
    data = conditions.as_dict()
    del data["units"]
    data["latitude"], data["longitude"] = map(math.degrees, (data["latitude"], data["longitude"]))
    if data["space_weather"] is not None:
        data["space_weather"] = {JSON_KEYS.get(k, k): v for k, v in data["space_weather"].items()}
    return {JSON_KEYS.get(k, k): v for k, v in data.items()}


def run(args) -> int:
    """Run ``adbsat-ros atmosphere``; the exit status."""
    with errors_as(CommandLineError, ValueError):  # a library's check: still a bad value
        conditions = compute(args)
    if args.json:
        try:  # (made whole first: a refused number must not leave half a document)
            text = json.dumps(json_document(conditions), indent=2, allow_nan=False)
        except ValueError:
            raise CommandLineError(
                "the atmosphere model gave a number that is not finite for these inputs"
            ) from None
        sys.stdout.write(text + "\n")
    else:
        print(format_table(conditions))
    return 0
