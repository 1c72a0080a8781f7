"""Settings of the live aerodynamic wrench computation, shared by the ROS node and bag analysis:
the parameters of :data:`adbsat_ros.estimator.parameters.PARAMETERS` checked into one value,
:class:`WrenchSettings`.
"""

from __future__ import annotations

import datetime as _dt
from dataclasses import dataclass, fields
from typing import NamedTuple

import numpy as np

from adbsat_ros.bounds import bounded
from adbsat_ros.environment.accommodation import accommodation_model_names
from adbsat_ros.environment.atmosphere import FIRST_YEAR, LAST_YEAR
from adbsat_ros.estimator.parameters import (
    ATTITUDE_SOURCES,
    COEFFICIENT_SOURCES,
    EPOCH_UTC_RANGE,
    EPOCH_UTC_REASON,
    EXECUTORS,
    PARAMETER_DEFAULTS,
    PARAMETER_RANGES,
    ROS_PARAMETERS,
    SHADING_MODES,
    STATE_FRAMES,
    TIME_MODES,
    WHOLE_NUMBER_PARAMETERS,
    load_parameters_file,
    unknown_parameter,
)
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.gsi_models import (
    INCIDENT_TEMPERATURE_FORMS,
    ModelOptions,
    canonical_model_name,
)
from adbsat_ros.physics.setup import BodySpec, Setup, ShadingPolicy
from adbsat_ros.physics.surface import SurfaceProperties


def _choice(name, value, allowed):
    value = str(value)
    if value not in allowed:
        raise ValueError(f"parameter {name}: {value!r} is not one of {', '.join(allowed)}")
    return value


def _frame_ids(name, value) -> tuple:
    """Frame names as a tuple of lower-case strings without a leading "/"."""
    if isinstance(value, str) or not all(isinstance(x, str) for x in value):
        raise ValueError(f"parameter {name}: expected a list of frame names, got {value!r}")
    names = tuple(x.strip().lstrip("/").lower() for x in value)
    if not names:
        raise ValueError(f"parameter {name}: {name} must name at least one frame")
    if not all(names):
        raise ValueError(f"parameter {name}: {name}: names must be non-empty, got {value!r}")
    return names


class FrameIds(NamedTuple):
    """The names of each state frame (lower case)."""

    eci: tuple
    ecef: tuple


def _within(name, value, rule) -> float:
    """``value`` within the Bound ``rule``, or ValueError ``"parameter NAME: ..."`` with the range
    and its reason."""
    try:
        return bounded(name, value, rule)
    except ValueError as exc:
        raise ValueError(f"parameter {name.split('[')[0]}: {exc}") from None


def _number(values, name) -> float:
    """The number parameter ``name`` of ``values`` within its :data:`PARAMETER_RANGES` range."""
    number = _within(name, values[name], PARAMETER_RANGES[name])
    if name in WHOLE_NUMBER_PARAMETERS and not number.is_integer():
        raise ValueError(f"parameter {name}: {name} must be a whole number, got {values[name]!r}")
    return int(number) if name in WHOLE_NUMBER_PARAMETERS else number


def _vector3(values, name) -> tuple:
    """The list parameter ``name``: three numbers, each within its range."""
    value = values[name]
    if isinstance(value, str) or not hasattr(value, "__len__") or len(value) != 3:
        raise ValueError(f"parameter {name}: expected three numbers, got {value!r}")
    rule = PARAMETER_RANGES[name]
    return tuple(_within(f"{name}[{axis}]", x, rule) for axis, x in zip("xyz", value))


def _inertia(values) -> tuple | None:
    """The inertia tensor (9 numbers, row-major) checked: each in its range, symmetric and
    positive definite; None when all are 0 (no angular acceleration)."""
    value = values["inertia"]
    if isinstance(value, str) or not hasattr(value, "__len__") or len(value) != 9:
        raise ValueError(f"parameter inertia: expected 9 numbers (3 x 3, row-major), got {value!r}")
    rule = PARAMETER_RANGES["inertia"]
    tensor = tuple(_within(f"inertia[{i}]", x, rule) for i, x in enumerate(value))
    if not any(tensor):
        return None
    matrix = np.array(tensor).reshape(3, 3)
    if np.max(np.abs(matrix - matrix.T)) > 1e-9 * np.max(np.abs(matrix)):
        raise ValueError(f"parameter inertia: the tensor must be symmetric, got {value!r}")
    if np.linalg.eigvalsh(matrix).min() <= 0.0:
        raise ValueError(
            f"parameter inertia: the tensor must be positive definite (every principal moment "
            f"> 0), got {value!r}"
        )
    return tensor


def _flag(values, name) -> bool:
    """The boolean parameter ``name`` (a string such as "false" is not taken for True)."""
    value = values[name]
    if not isinstance(value, bool):
        raise ValueError(f"parameter {name}: expected true or false, got {value!r}")
    return value


def parse_utc(name, text) -> _dt.datetime:
    """Parse an ISO 8601 UTC time (a trailing Z or +00:00 allowed) into an aware datetime, within
    the years of :data:`~adbsat_ros.estimator.parameters.EPOCH_UTC_RANGE`."""
    try:
        t = _dt.datetime.fromisoformat(str(text).replace("Z", "+00:00"))
        if t.tzinfo is None:
            t = t.replace(tzinfo=_dt.timezone.utc)
        t = t.astimezone(_dt.timezone.utc)
    except ValueError:
        raise ValueError(f"parameter {name}: not an ISO 8601 time: {text!r}") from None
    except OverflowError:  # (an offset that takes it outside the years datetime has)
        t = None
    if t is None or not FIRST_YEAR <= t.year <= LAST_YEAR:
        raise ValueError(
            f"parameter {name}: {name} must be {EPOCH_UTC_RANGE} ({EPOCH_UTC_REASON}), got {text!r}"
        )
    return t


@dataclass(frozen=True)
class WrenchSettings:
    """Validated settings of the wrench computation: the node's parameters as values.

    Build with :meth:`from_parameters` (the node's parameter values, a params YAML's, or
    keyword overrides of the defaults), which checks every value and raises ValueError naming
    the parameter and its allowed values. The fields are the parameters of :data:`PARAMETERS`
    (name, default, meaning and unit), in SI units, with ``epoch_utc`` parsed to an aware UTC
    datetime; :meth:`as_parameters` gives the parameter values back.
    """

    mesh: str
    mesh_scale: float
    mesh_accept_size: bool
    robot_description: str
    body_frame_id: str
    center_of_mass: tuple
    mass: float
    inertia: tuple | None
    gsi_model: str
    alpha: float
    alpha_n: float
    specular_reflectivity: float
    diffuse_reflectivity: float
    sigma_n: float
    sigma_t: float
    wall_temperature: float
    material_overrides: tuple
    incident_temperature: str
    adbsat_compat: bool
    accommodation_model: str
    solar_pressure: bool
    shading: str
    shading_samples: int
    shading_cache_resolution_deg: float
    shading_cache_size: int
    shading_interpolation: bool
    joint_state_timeout: float
    joint_shading_resolution_deg: float
    joint_shading_resolution_m: float
    joint_shading_interpolation: bool
    joint_shading_cache_size: int
    joint_shading_exact: bool
    f107: float
    f107a: float
    ap: float
    ap_history: tuple | None
    anomalous_oxygen: bool
    time_mode: str
    epoch_utc: _dt.datetime
    state_frame: str
    eci_frame_ids: tuple
    ecef_frame_ids: tuple
    earth_rotation: bool
    wind_ecef: tuple
    attitude_source: str
    state_timeout: float
    min_altitude: float
    knudsen_warning: float
    time_jump_reset: float
    conditions_step: float
    max_quaternion_norm_error: float
    min_relative_speed: float
    qos_depth: int
    diagnostics_period: float
    marker_period: float
    executor: str
    coefficients_source: str
    database_path: str

    @classmethod
    def from_parameters(cls, values=None, **overrides) -> "WrenchSettings":
        """Validate a mapping of parameter names to values (missing names take their defaults).

        Raises
        ------
        ValueError
            ``"parameter NAME: reason"`` for the first bad value or an unknown name.
        """
        merged = dict(PARAMETER_DEFAULTS)
        for source in (values or {}), overrides:
            for key, value in source.items():
                if key not in merged:
                    raise ValueError(unknown_parameter(key))
                merged[key] = value
        v = merged
        history = v["ap_history"]
        if isinstance(history, str) or not hasattr(history, "__len__"):
            raise ValueError(f"parameter ap_history: expected a list of numbers, got {history!r}")
        ap_history = None
        if len(history) > 1:
            rule = PARAMETER_RANGES["ap_history"]
            ap_history = tuple(_within(f"ap_history[{i}]", x, rule) for i, x in enumerate(history))
        if ap_history is not None and len(ap_history) != 7:
            raise ValueError(
                f"parameter ap_history: needs 7 values (or one to leave it unused), "
                f"got {len(ap_history)}"
            )
        try:
            model = canonical_model_name(v["gsi_model"])
        except ValueError as exc:
            raise ValueError(f"parameter gsi_model: {exc}") from None
        mesh = str(v["mesh"]).strip()
        if not mesh:
            raise ValueError("parameter mesh: empty")
        settings = cls(
            mesh=mesh,
            mesh_scale=_number(v, "mesh_scale"),
            mesh_accept_size=_flag(v, "mesh_accept_size"),
            robot_description=str(v["robot_description"]).strip(),
            body_frame_id=str(v["body_frame_id"]).lstrip("/") or "body",
            center_of_mass=_vector3(v, "center_of_mass"),
            mass=_number(v, "mass"),
            inertia=_inertia(v),
            gsi_model=model,
            alpha=_number(v, "alpha"),
            alpha_n=_number(v, "alpha_n"),
            specular_reflectivity=_number(v, "specular_reflectivity"),
            diffuse_reflectivity=_number(v, "diffuse_reflectivity"),
            sigma_n=_number(v, "sigma_n"),
            sigma_t=_number(v, "sigma_t"),
            wall_temperature=_number(v, "wall_temperature"),
            material_overrides=tuple(
                s for s in (str(x).strip() for x in v["material_overrides"]) if s
            ),
            incident_temperature=_choice(
                "incident_temperature", v["incident_temperature"], INCIDENT_TEMPERATURE_FORMS
            ),
            adbsat_compat=_flag(v, "adbsat_compat"),
            accommodation_model=_choice(
                "accommodation_model",
                str(v["accommodation_model"]).lower(),
                accommodation_model_names(),
            ),
            solar_pressure=_flag(v, "solar_pressure"),
            shading=_choice("shading", v["shading"], SHADING_MODES),
            shading_samples=_number(v, "shading_samples"),
            shading_cache_resolution_deg=_number(v, "shading_cache_resolution_deg"),
            shading_cache_size=_number(v, "shading_cache_size"),
            shading_interpolation=_flag(v, "shading_interpolation"),
            joint_state_timeout=_number(v, "joint_state_timeout"),
            joint_shading_resolution_deg=_number(v, "joint_shading_resolution_deg"),
            joint_shading_resolution_m=_number(v, "joint_shading_resolution_m"),
            joint_shading_interpolation=_flag(v, "joint_shading_interpolation"),
            joint_shading_cache_size=_number(v, "joint_shading_cache_size"),
            joint_shading_exact=_flag(v, "joint_shading_exact"),
            f107=_number(v, "f107"),
            f107a=_number(v, "f107a"),
            ap=_number(v, "ap"),
            ap_history=ap_history,
            anomalous_oxygen=_flag(v, "anomalous_oxygen"),
            time_mode=_choice("time_mode", v["time_mode"], TIME_MODES),
            epoch_utc=parse_utc("epoch_utc", v["epoch_utc"]),
            state_frame=_choice("state_frame", str(v["state_frame"]).lower(), STATE_FRAMES),
            eci_frame_ids=_frame_ids("eci_frame_ids", v["eci_frame_ids"]),
            ecef_frame_ids=_frame_ids("ecef_frame_ids", v["ecef_frame_ids"]),
            earth_rotation=_flag(v, "earth_rotation"),
            wind_ecef=_vector3(v, "wind_ecef"),
            attitude_source=_choice("attitude_source", v["attitude_source"], ATTITUDE_SOURCES),
            state_timeout=_number(v, "state_timeout"),
            min_altitude=_number(v, "min_altitude"),
            knudsen_warning=_number(v, "knudsen_warning"),
            time_jump_reset=_number(v, "time_jump_reset"),
            conditions_step=_number(v, "conditions_step"),
            max_quaternion_norm_error=_number(v, "max_quaternion_norm_error"),
            min_relative_speed=_number(v, "min_relative_speed"),
            qos_depth=_number(v, "qos_depth"),
            diagnostics_period=_number(v, "diagnostics_period"),
            marker_period=_number(v, "marker_period"),
            executor=_choice("executor", v["executor"], EXECUTORS),
            coefficients_source=_choice(
                "coefficients_source", v["coefficients_source"], COEFFICIENT_SOURCES
            ),
            database_path=str(v["database_path"]),
        )
        both = set(settings.eci_frame_ids) & set(settings.ecef_frame_ids)
        if both:
            raise ValueError(
                f"parameters eci_frame_ids and ecef_frame_ids: '{sorted(both)[0]}' names both "
                "frames"
            )
        reflected = settings.specular_reflectivity + settings.diffuse_reflectivity
        if reflected > 1.0:
            raise ValueError(
                "parameters specular_reflectivity and diffuse_reflectivity: they sum to "
                f"{reflected:g}; at most 1 of the sunlight can be reflected"
            )
        if settings.coefficients_source == "database" and not settings.database_path:
            raise ValueError("parameter database_path: needed when coefficients_source is database")
        return settings

    @property
    def frame_ids(self) -> "FrameIds":
        """The state frame names, lower case, as :func:`~.state.odometry_inputs` takes them."""
        return FrameIds(self.eci_frame_ids, self.ecef_frame_ids)

    def as_parameters(self) -> dict:
        """The settings as ROS-parameter-compatible values (inverse of from_parameters)."""
        out = {}
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "epoch_utc":
                value = value.isoformat()
            elif f.name == "ap_history":
                value = list(value) if value else [0.0]
            elif f.name == "inertia":
                value = list(value) if value else [0.0] * 9
            elif f.name == "material_overrides":
                value = list(value) or [""]
            elif isinstance(value, tuple):
                value = list(value)
            out[f.name] = value
        return out


def settings_from_file(path, node_name: str = "adbsat_node") -> WrenchSettings:
    """The settings a ROS 2 ``--params-file`` gives ``node_name``, checked (parameters it does
    not set take their defaults; rclpy's own, :data:`ROS_PARAMETERS`, are allowed and ignored).

    Raises
    ------
    ValueError
        ``"PATH: ..."``: the file cannot be read, or ``"PATH: parameter NAME: reason"`` for an
        unknown name (with the closest known one) or a value out of its range.
    """
    values = load_parameters_file(path, node_name)
    own = {key: value for key, value in values.items() if key not in ROS_PARAMETERS}
    try:
        return WrenchSettings.from_parameters(own)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None


def setup_from_settings(settings: WrenchSettings) -> Setup:
    """The set-up the settings describe: the body of ``mesh`` (or ``robot_description``), the
    default surface with ``material_overrides``, the centre of mass as moment point, the model,
    the shading policy; ValueError naming ``material_overrides`` for an override that cannot be
    read."""
    s = settings
    return Setup(
        body=BodySpec(s.mesh, s.mesh_scale, s.mesh_accept_size, urdf=s.robot_description),
        model=s.gsi_model,
        options=ModelOptions(s.incident_temperature, s.adbsat_compat),
        surface=SurfaceProperties(
            alpha=s.alpha,
            alpha_n=s.alpha_n,
            sigma_n=s.sigma_n,
            sigma_t=s.sigma_t,
            wall_temperature=s.wall_temperature,
            specular_reflectivity=s.specular_reflectivity,
            diffuse_reflectivity=s.diffuse_reflectivity,
        ),
        overrides=s.material_overrides,
        reference=Reference(moment_point=s.center_of_mass),
        shading=ShadingPolicy(
            s.shading,
            s.shading_samples,
            s.shading_cache_resolution_deg,
            s.shading_cache_size,
            s.shading_interpolation,
            s.joint_shading_resolution_deg,
            s.joint_shading_resolution_m,
            s.joint_shading_interpolation,
            s.joint_shading_cache_size,
            s.joint_shading_exact,
        ),
        labels=(
            ("materials", "parameter material_overrides"),
            ("moment_point", "parameter center_of_mass: center_of_mass"),
            ("samples", "parameter shading_samples: shading_samples"),
        ),
    )
