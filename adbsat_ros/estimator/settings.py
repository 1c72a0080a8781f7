"""Settings of the wrench computation, shared by the node and bag analysis: the parameters of
:data:`~.parameters.PARAMETERS` checked into one :class:`WrenchSettings`, and their set-up."""

from __future__ import annotations

import datetime as _dt
from dataclasses import make_dataclass
from typing import NamedTuple

from adbsat_ros.estimator.parameters import (
    PARAMETER_DEFAULTS,
    PARAMETERS,
    ROS_PARAMETERS,
    load_parameters_file,
    unknown_parameter,
)
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.gsi_models import ModelOptions
from adbsat_ros.physics.setup import BodySpec, Setup, ShadingPolicy
from adbsat_ros.physics.surface import SurfaceProperties


class FrameIds(NamedTuple):
    """The names of each state frame (lower case)."""

    eci: tuple
    ecef: tuple


# one field per parameter, typed as its kind converts it
_Fields = make_dataclass(
    "_Fields",
    [(p.name, p.kind.__annotations__.get("return", object)) for p in PARAMETERS],
    frozen=True,
)


class WrenchSettings(_Fields):
    """Validated settings of the wrench computation: one field per parameter of :data:`PARAMETERS`,
    in SI units, as its kind converts it (``epoch_utc`` an aware UTC datetime, lists as tuples,
    an unused ``inertia`` or ``ap_history`` None). Frozen; made by :meth:`from_parameters`."""

    @classmethod
    def from_parameters(cls, values=None, **overrides) -> "WrenchSettings":
        """Validate parameter values and overrides by name (defaults for the rest).

        ValueError: ``"parameter NAME: reason"`` for the first bad value or an unknown name.
        """
        merged = dict(PARAMETER_DEFAULTS)
        for source in (values or {}), overrides:
            for key, value in source.items():
                if key not in merged:
                    raise ValueError(unknown_parameter(key))
                merged[key] = value
        settings = cls(**{p.name: p.kind(p.name, merged[p.name], p.bound) for p in PARAMETERS})
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
    def frame_ids(self) -> FrameIds:
        """The state frame names, lower case."""
        return FrameIds(self.eci_frame_ids, self.ecef_frame_ids)

    def as_parameters(self) -> dict:
        """The settings as ROS-parameter-compatible values (inverse of from_parameters)."""
        out = {}
        for p in PARAMETERS:
            value = getattr(self, p.name)
            if isinstance(value, _dt.datetime):
                value = value.isoformat()
            elif value is None or value == ():  # (unused: the default says so)
                value = list(p.default)
            elif isinstance(value, tuple):
                value = list(value)
            out[p.name] = value
        return out


def settings_from_file(path, node_name: str = "adbsat_node") -> WrenchSettings:
    """The settings a ROS 2 ``--params-file`` gives ``node_name`` (defaults for the rest).

    ValueError: ``"PATH: ..."``: the file cannot be read, an unknown name or a value out of range.
    """
    values = load_parameters_file(path, node_name)
    own = {key: value for key, value in values.items() if key not in ROS_PARAMETERS}
    try:
        return WrenchSettings.from_parameters(own)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None


#: The parts of a set-up the parameters give (:attr:`Parameter.use` ``"part.field"``).
_PARTS = {
    "body": BodySpec,
    "options": ModelOptions,
    "surface": SurfaceProperties,
    "reference": Reference,
    "shading": ShadingPolicy,
}
_LABELS = (
    ("materials", "parameter material_overrides"),
    ("moment_point", "parameter center_of_mass: center_of_mass"),
    ("samples", "parameter shading_samples: shading_samples"),
)


def setup_from_settings(settings: WrenchSettings) -> Setup:
    """The set-up the settings describe; ValueError naming ``material_overrides`` if unreadable."""
    parts, fields = {part: {} for part in _PARTS}, {}
    for p in PARAMETERS:
        part, _, field = p.use.partition(".")
        if part in _PARTS:
            parts[part][field] = getattr(settings, p.name)
        elif part in ("model", "overrides"):
            fields[part] = getattr(settings, p.name)
    made = {part: make(**parts[part]) for part, make in _PARTS.items()}
    return Setup(**made, **fields, labels=_LABELS)
