"""The node's parameters: every setting's name, default and meaning in one table, and the
ROS 2 parameters files that give them values.

:data:`PARAMETERS` is the single table: the node declares its ROS parameters from it,
``config/adbsat.yaml`` documents it, and :class:`~adbsat_ros.estimator.settings.WrenchSettings`
checks values against it (bag analysis reads the same YAML into the same settings).
"""

from __future__ import annotations

import difflib

import yaml

from adbsat_ros.environment.atmosphere import FIRST_YEAR, LAST_YEAR
from adbsat_ros.environment.flight_conditions import STATE_FRAMES
from adbsat_ros.estimator.parameter_ranges import (
    MAX_CONDITIONS_STEP,
    PARAMETER_RANGES,
    WHOLE_NUMBER_PARAMETERS,
)
from adbsat_ros.physics.gsi_models import MODELS
from adbsat_ros.shading.shader import MODES as SHADING_MODES

__all__ = [
    "ATTITUDE_SOURCES",
    "COEFFICIENT_SOURCES",
    "DEFAULT_ECEF_FRAME_IDS",
    "DEFAULT_ECI_FRAME_IDS",
    "EPOCH_UTC_RANGE",
    "EPOCH_UTC_REASON",
    "EXECUTORS",
    "MAX_CONDITIONS_STEP",
    "PARAMETERS",
    "PARAMETER_DEFAULTS",
    "PARAMETER_DESCRIPTIONS",
    "PARAMETER_RANGES",
    "READ_ONLY_PARAMETERS",
    "ROS_PARAMETERS",
    "SHADING_MODES",
    "STATE_FRAMES",
    "TIME_MODES",
    "WHOLE_NUMBER_PARAMETERS",
    "is_ros_parameter",
    "load_parameters_file",
    "parameter_kind",
    "parameter_range_text",
    "typed_parameter_value",
    "unknown_parameter",
]

TIME_MODES = ("unix", "epoch")
ATTITUDE_SOURCES = ("attitude_topic", "odometry")
COEFFICIENT_SOURCES = ("panel", "database")
EXECUTORS = ("events", "single_threaded")
#: Default names (any case, a leading "/" ignored) of an Earth-centred inertial state frame:
#: GCRF/GCRS and ICRF, and J2000/EME2000 (within 0.02 arcsec of GCRF, the frame bias).
DEFAULT_ECI_FRAME_IDS = ("eci", "gcrf", "gcrs", "icrf", "j2000", "eme2000")
#: Default names of the Earth-fixed frame: ITRF/ITRS, WGS 84, and REP 105's ``earth``.
DEFAULT_ECEF_FRAME_IDS = ("ecef", "itrf", "itrs", "wgs84", "earth")

#: The valid range of ``epoch_utc``, in words (the time scales and the atmosphere model's space
#: weather cover these years: :data:`adbsat_ros.environment.atmosphere.FIRST_YEAR`, ``LAST_YEAR``).
EPOCH_UTC_RANGE = f"from {FIRST_YEAR}-01-01T00:00:00 to {LAST_YEAR}-12-31T23:59:59 UTC"
#: Why ``epoch_utc`` has that range.
EPOCH_UTC_REASON = "the years the time scales and the atmosphere model's space weather cover"

#: (name, default, description) of every setting. Units in the description; SI throughout.
PARAMETERS = (
    (
        "mesh",
        "example",
        "mesh file (.obj .stl .ply .off ...), a URDF at zero joint positions, or a bundled "
        "body ('example', 'example-articulated', 'example-finned', 'grooved-cylinder', "
        "'cylinder', 'intake-box'); read once at start-up",
    ),
    ("mesh_scale", 1.0, "factor from mesh file units to metres (1e-3 for millimetres)"),
    (
        "mesh_accept_size",
        False,
        "take a mesh (at mesh_scale 1) under 1 mm or over 200 m across, which is otherwise "
        "refused as probably not in metres",
    ),
    (
        "robot_description",
        "",
        "URDF text of an articulated body (links with geometry, joints), as "
        "robot_state_publisher takes it; when set it is the body instead of mesh, and the "
        "joint positions come from the joint_states topic; read once at start-up",
    ),
    ("body_frame_id", "body", "frame_id of published wrenches: the mesh frame, fixed to the body"),
    (
        "center_of_mass",
        [0.0, 0.0, 0.0],
        "centre of mass in the mesh frame [m]; torques are about it",
    ),
    (
        "mass",
        0.0,
        "satellite mass [kg] for the acceleration topic (the force over the mass); 0: the "
        "topic is not published",
    ),
    (
        "inertia",
        [0.0] * 9,
        "inertia tensor about the centre of mass, body frame, row-major 3 x 3 [kg m^2], "
        "symmetric and positive definite, for the angular part of the acceleration topic "
        "(inertia^-1 torque); all 0: angular part 0",
    ),
    ("gsi_model", "sentman", "gas-surface model: " + ", ".join(MODELS)),
    ("alpha", 1.0, "energy accommodation coefficient [-] (used when accommodation_model is fixed)"),
    ("alpha_n", 1.0, "CLL normal energy accommodation [-]"),
    ("sigma_n", 1.0, "normal momentum accommodation [-] (schaaf, storch)"),
    ("sigma_t", 1.0, "tangential momentum accommodation [-] (schaaf, storch, cll)"),
    ("wall_temperature", 300.0, "wall temperature [K]"),
    (
        "specular_reflectivity",
        0.0,
        "fraction of sunlight reflected specularly [-] (solar radiation pressure)",
    ),
    (
        "diffuse_reflectivity",
        0.0,
        "fraction of sunlight reflected diffusely [-] (solar radiation pressure); the two "
        "reflectivities sum to at most 1, the rest is absorbed",
    ),
    (
        "material_overrides",
        [""],
        "per-material values, 'NAME:key=value,key=value' (keys as the parameters above)",
    ),
    (
        "incident_temperature",
        "energy",
        "incident temperature form for sentman/dria: energy (ADBSat) or kinetic",
    ),
    (
        "adbsat_compat",
        False,
        "reproduce ADBSat's coded quirks (maxwell two-sided plate, cll species weights)",
    ),
    (
        "accommodation_model",
        "fixed",
        "fixed (use alpha), langmuir, goodman or sesam (alpha from the atmosphere)",
    ),
    (
        "solar_pressure",
        False,
        "also compute the solar radiation pressure (sun from an ephemeris, Earth's shadow, the "
        "body's own shading of sunlit panels): published as solar_wrench, and with the "
        "aerodynamic wrench as total_wrench",
    ),
    ("shading", "raycast", "shading mode: none, projection (ADBSat), raycast (exact)"),
    ("shading_samples", 16, "ray samples per panel for raycast shading"),
    ("shading_cache_resolution_deg", 0.25, "angular resolution of the shading cache [deg]"),
    (
        "shading_cache_size",
        20000,
        "maximum number of flow directions kept in the shading cache (articulated bodies: in "
        "all configurations together, each keeping shading_cache_size // "
        "joint_shading_cache_size)",
    ),
    (
        "shading_interpolation",
        True,
        "blend the cached shading of the three cell centres around the flow direction "
        "(continuous in attitude) instead of the nearest cell's",
    ),
    (
        "joint_state_timeout",
        1.0,
        "articulated bodies: a joint position older than this at the attitude stamp is stale "
        "and the attitude refused [s]",
    ),
    (
        "joint_shading_resolution_deg",
        0.25,
        "articulated bodies: the shading is cached per configuration on a grid of this step "
        "in every revolute or continuous joint [deg] (the geometry itself is exact)",
    ),
    (
        "joint_shading_resolution_m",
        0.001,
        "articulated bodies: the configuration grid's step in every prismatic joint [m]",
    ),
    (
        "joint_shading_interpolation",
        False,
        "articulated bodies: blend the shading of the (at most joints + 1) grid configurations "
        "around the joint positions (continuous in them: no steps in the joint efforts; as "
        "accurate on a 2 deg grid as the nearest point of a 0.25 deg one) instead of the "
        "nearest one's; costs that many configurations' shading",
    ),
    (
        "joint_shading_cache_size",
        64,
        "articulated bodies: joint configurations whose shading is kept",
    ),
    (
        "joint_shading_exact",
        False,
        "articulated bodies: shade the body posed at each attitude's joint positions for its "
        "own flow direction, with no configuration grid or direction cache (one shading per "
        "attitude, no cache error: for joints that move with every message)",
    ),
    ("f107", 150.0, "F10.7 solar flux of the previous day [sfu]"),
    ("f107a", 150.0, "81-day average F10.7 [sfu]"),
    ("ap", 4.0, "daily geomagnetic Ap index [-]"),
    (
        "ap_history",
        [0.0],
        "optional NRLMSISE-00 7-element Ap history; a single element means unused",
    ),
    ("anomalous_oxygen", True, "include NRLMSISE-00 anomalous oxygen in the gas"),
    (
        "time_mode",
        "unix",
        "how header stamps map to UTC: unix (stamp is UNIX time) or epoch (epoch_utc + stamp)",
    ),
    ("epoch_utc", "2026-01-01T00:00:00", "UTC epoch of stamp 0 for time_mode epoch (ISO 8601)"),
    ("state_frame", "eci", "frame of the Odometry position: eci (GCRF) or ecef (ITRF)"),
    (
        "eci_frame_ids",
        list(DEFAULT_ECI_FRAME_IDS),
        "Odometry frame_id names that mean ECI (any case); a name in neither list is refused",
    ),
    (
        "ecef_frame_ids",
        list(DEFAULT_ECEF_FRAME_IDS),
        "Odometry frame_id names that mean ECEF (any case)",
    ),
    ("earth_rotation", True, "the atmosphere co-rotates with the Earth"),
    ("wind_ecef", [0.0, 0.0, 0.0], "wind relative to the rotating Earth, ECEF axes [m/s]"),
    (
        "attitude_source",
        "attitude_topic",
        "attitude from the attitude topic or from the Odometry pose (odometry)",
    ),
    ("state_timeout", 1.0, "a state older than this at the attitude stamp is stale [s]"),
    (
        "min_altitude",
        120e3,
        "states below this geodetic altitude [m] are refused: the flow about a metre-sized body "
        "is no longer free-molecular there (Kn about 3 at 120 km, 0.1 at 100 km)",
    ),
    (
        "knudsen_warning",
        10.0,
        "/diagnostics warns while the Knudsen number (mean free path over reference_length) of "
        "the latest wrench is below this",
    ),
    (
        "time_jump_reset",
        1.0,
        "a message stamped more than this [s] before the latest of its kind restarts the history "
        "(a bag played again); one less far back is refused alone as out of order",
    ),
    (
        "conditions_step",
        0.01,
        "flight conditions (NRLMSISE-00, Earth orientation, relative wind) are evaluated "
        "exactly at the stamps that are multiples of this [s] and interpolated linearly in between "
        "(density within "
        "about 2e-9 at 0.01 s); 0 evaluates them at every stamp",
    ),
    (
        "max_quaternion_norm_error",
        1e-3,
        "quaternions with | |q| - 1 | above this are rejected; below, normalised",
    ),
    ("min_relative_speed", 1e-3, "below this relative speed [m/s] the wrench is zero"),
    ("qos_depth", 10, "history depth of subscriptions and publications"),
    ("diagnostics_period", 1.0, "period of /diagnostics messages [s]"),
    (
        "marker_period",
        1.0,
        "period of the panel_marker topic [s] (the mesh coloured by panel pressure, for RViz), "
        "published while it has a subscriber",
    ),
    (
        "executor",
        "events",
        "rclpy executor of adbsat_node: events (rclpy.experimental.EventsExecutor, about half "
        "the per-message overhead; single_threaded when this rclpy lacks it) or single_threaded",
    ),
    (
        "coefficients_source",
        "panel",
        "panel (live panel method) or database (interpolated from database_path)",
    ),
    (
        "database_path",
        "",
        "database (.npz) made by 'adbsat-ros database' for coefficients_source database; it must "
        "be made for the same mesh, gsi_model, surface properties and reference area/length, "
        "else it is refused",
    ),
)

PARAMETER_DEFAULTS = {name: default for name, default, _ in PARAMETERS}
PARAMETER_DESCRIPTIONS = {name: text for name, _, text in PARAMETERS}
#: Settings that need the mesh or its shading structures rebuilt; the node keeps them read-only.
READ_ONLY_PARAMETERS = (
    "mesh",
    "mesh_scale",
    "mesh_accept_size",
    "robot_description",
    "qos_depth",
    "body_frame_id",
    "executor",
)


#: Parameters rclpy declares on every node: a params file may set them, the settings ignore them.
ROS_PARAMETERS = ("use_sim_time", "start_type_description_service", "qos_overrides")


def is_ros_parameter(name: str) -> bool:
    """Whether ``name`` is one of rclpy's own parameters (:data:`ROS_PARAMETERS`; a QoS
    override's name, ``qos_overrides./topic.publisher.depth``, is one too)."""
    return any(name == own or name.startswith(own + ".") for own in ROS_PARAMETERS)


def _is_integer(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def typed_parameter_value(name: str, value):
    """``value`` of parameter ``name`` in the type of the parameter's default, where the rule
    allows it; any other value unchanged (the node refuses a value of another type).

    The rule: an integer given to a number parameter (``f107: 150``) is that number as a float,
    and each integer of a list given to a list of numbers likewise; a float with a whole value
    given to a whole-number parameter (``shading_samples: 32.0``) is that integer, a float with a
    fraction stays a float (refused).
    """
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
    """What parameter ``name`` takes, in words: ``"a number"``, ``"a whole number"``,
    ``"true or false"``, ``"a string"``, ``"a list of numbers"`` or ``"a list of strings"``."""
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


def unknown_parameter(name: str) -> str:
    """The error text for a parameter ``name`` that is not in :data:`PARAMETERS`, with the
    closest known name when one is close."""
    close = difflib.get_close_matches(str(name), list(PARAMETER_DEFAULTS), n=1)
    if close:
        return f"parameter {name}: unknown (did you mean {close[0]}?)"
    return f"parameter {name}: unknown; known parameters are {', '.join(PARAMETER_DEFAULTS)}"


def load_parameters_file(path, node_name: str = "adbsat_node") -> dict:
    """Read a ROS 2 ``--params-file`` YAML and return the parameters for ``node_name``.

    Keys under ``/**`` apply to every node, keys under the node's name override them.

    Raises
    ------
    ValueError
        Naming the file: it cannot be read, is no YAML, or holds no parameters for the node.
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
    """The valid range of a parameter in words (empty for one without a range), e.g.
    ``"in [0, 1]: an accommodation coefficient ..."``; ``"each in ..."`` for a list of numbers;
    :data:`EPOCH_UTC_RANGE` for ``epoch_utc``."""
    if name == "epoch_utc":
        return f"{EPOCH_UTC_RANGE}: {EPOCH_UTC_REASON}"
    rule = PARAMETER_RANGES.get(name)
    if rule is None:
        return ""
    each = "each " if isinstance(PARAMETER_DEFAULTS[name], list) else ""
    whole = ", a whole number" if name in WHOLE_NUMBER_PARAMETERS else ""
    return f"{each}in {rule.text()}{whole}: {rule.reason}"
