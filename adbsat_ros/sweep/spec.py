"""What a sweep computes: its YAML spec, checked into a :class:`SweepSpec`.

A spec names the body, the model and shading, the fixed inputs and the axes::

    mesh: example-articulated      # a mesh file, a URDF, or a bundled body
    model: sentman
    shading: raycast               # none | projection | raycast
    reference: {area: 1.0, length: 1.0, moment_point: [0, 0, 0]}   # optional
    materials: ["solar_array:alpha=0.8"]                           # optional overrides
    fixed: {speed: 7700, temperature: 900, mean_mass_amu: 16}
    axes:
      aoa: -180:10:180             # [deg]; a list, or start:step:stop
      aos: [-30, 0, 30]            # [deg]
      alpha: [0.8, 0.9, 1.0]
      joint.wing_left_hinge: 0:15:90   # [deg] (revolute), [m] (prismatic)
    chunk_points: 256              # points per task (optional)

Axes (:data:`AXES`, and ``joint.NAME`` for a URDF's moving joints) and fixed inputs take the
units and valid ranges of docs/physics.md section 11. ``aoa`` and ``aos`` are always axes
(a single value if they do not vary). An input that is neither fixed nor an axis takes its
default (:data:`DEFAULTS`; ``alpha`` and ``wall_temperature`` default to the materials'). Any
bad field is a :class:`SpecError` naming it.
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import json
import math
from dataclasses import dataclass

import numpy as np
import yaml

from adbsat_ros.bounds import BOUNDS, Bound
from adbsat_ros.environment.atmosphere import check_time
from adbsat_ros.physics.gsi_models import MODELS, canonical_model_name
from adbsat_ros.shading.shader import MODES as SHADING_MODES

_ACCOMMODATION = Bound(0.0, 1.0, "", "an accommodation coefficient: 0 specular, 1 diffuse")

#: The axes a sweep may have besides ``joint.NAME``: name -> (range, unit).
AXES = {
    "aoa": (Bound(-360.0, 360.0, "deg", "an angle of attack, once around and back"), "deg"),
    "aos": (Bound(-90.0, 90.0, "deg", "a sideslip angle (ADBSat's range)"), "deg"),
    "speed": (BOUNDS["speed"], "m/s"),
    "temperature": (BOUNDS["temperature"], "K"),
    "mean_mass_amu": (BOUNDS["mean_mass_amu"], "amu"),
    "alpha": (_ACCOMMODATION, ""),
    "wall_temperature": (BOUNDS["wall_temperature"], "K"),
    # the atmosphere (NRLMSISE-00) at a circular orbit's speed: any of these gives the gas
    "altitude": (
        Bound(100.0, 1000.0, "km", "NRLMSISE-00 up to 1,000 km; below 100 km no free flow"),
        "km",
    ),
    "latitude": (Bound(-90.0, 90.0, "deg", "a geodetic latitude"), "deg"),
    "longitude": (Bound(-360.0, 360.0, "deg", "an east longitude"), "deg"),
    "f107": (BOUNDS["f107"], "sfu"),
    "f107a": (BOUNDS["f107"], "sfu"),
    "ap": (BOUNDS["ap"], ""),
}
#: Inputs that make the gas that of the atmosphere (with ``time``, a fixed UTC).
ATMOSPHERE = ("altitude", "latitude", "longitude", "f107", "f107a", "ap")
#: The atmosphere's defaults, and the UTC of a sweep that gives none.
ATMOSPHERE_DEFAULTS = {"latitude": 0.0, "longitude": 0.0, "f107": 150.0, "f107a": 150.0, "ap": 4.0}
DEFAULT_TIME = "2026-01-01T00:00:00"
#: Inputs a spec may fix (any axis but the attitude).
FIXED = tuple(name for name in AXES if name not in ("aoa", "aos"))
#: Values of the inputs neither fixed nor swept (alpha and wall_temperature: the materials').
DEFAULTS = {"speed": 7700.0, "temperature": 900.0, "mean_mass_amu": 16.0}
#: Points per task unless the spec says: a few seconds of ray-cast panel method.
CHUNK_POINTS = 256
#: Fields of a spec.
FIELDS = (
    "mesh",
    "model",
    "shading",
    "reference",
    "materials",
    "time",
    "fixed",
    "axes",
    "chunk_points",
)
JOINT_PREFIX = "joint."


class SpecError(ValueError):
    """A spec that cannot be swept; the message names the field."""


@dataclass(frozen=True)
class SweepSpec:
    """A checked sweep spec (module docstring).

    Attributes
    ----------
    mesh : str
    model, shading : str
    reference : dict
        ``area``, ``length``, ``moment_point`` given (others from the mesh).
    materials : tuple of str
        ``NAME:key=value`` override texts.
    fixed : dict of str to float
    axes : dict of str to ndarray
        Axis name -> its values in the spec's units (deg for angles), in sweep order.
    chunk_points : int
    time : str
        UTC (ISO 8601) of the atmosphere.
    text : str
        The spec as YAML (recorded in the result).
    """

    mesh: str
    model: str
    shading: str
    reference: dict
    materials: tuple
    fixed: dict
    axes: dict
    chunk_points: int
    text: str
    time: str = DEFAULT_TIME

    @property
    def atmosphere(self) -> bool:
        """Whether the gas is the atmosphere's (an atmosphere input is fixed or swept)."""
        return any(name in self.fixed or name in self.axes for name in ATMOSPHERE)

    @property
    def shape(self) -> tuple:
        """Points along each axis."""
        return tuple(len(v) for v in self.axes.values())

    @property
    def fingerprint(self) -> str:
        """SHA-256 of the canonical spec: two specs that sweep the same are equal here."""
        canonical = {
            "mesh": self.mesh,
            "model": self.model,
            "shading": self.shading,
            "reference": self.reference,
            "materials": list(self.materials),
            "fixed": self.fixed,
            "axes": {k: [float(x) for x in v] for k, v in self.axes.items()},
            "chunk_points": self.chunk_points,
            "time": self.time,
        }
        return hashlib.sha256(json.dumps(canonical, sort_keys=True).encode()).hexdigest()

    def joint_axes(self) -> dict:
        """``{joint name: axis name}`` of the swept joints."""
        return {k[len(JOINT_PREFIX) :]: k for k in self.axes if k.startswith(JOINT_PREFIX)}


def axis_values(text, name: str) -> np.ndarray:
    """The values of an axis: a number, a list of numbers, or ``start:step:stop`` (inclusive of
    stop when the steps reach it)."""
    if isinstance(text, str) and ":" in text:
        parts = text.split(":")
        try:
            start, step, stop = (float(p) for p in parts)
        except ValueError:
            raise SpecError(f"axes.{name}: expected start:step:stop, got {text!r}") from None
        if len(parts) != 3 or step <= 0 or stop < start:
            raise SpecError(
                f"axes.{name}: start:step:stop needs a step > 0 and stop >= start, got {text!r}"
            )
        count = int(math.floor((stop - start) / step + 1e-9)) + 1
        return start + step * np.arange(count)
    values = text if isinstance(text, list) else [text]
    try:
        out = np.array([float(v) for v in values if not isinstance(v, bool)], dtype=float)
    except (TypeError, ValueError):
        raise SpecError(f"axes.{name}: expected numbers, got {text!r}") from None
    if len(out) != len(values):
        raise SpecError(f"axes.{name}: expected numbers, got {text!r}")
    if out.size == 0:
        raise SpecError(f"axes.{name}: empty; give at least one value")
    if len(set(out.tolist())) != out.size:
        raise SpecError(f"axes.{name}: a value appears twice")
    return out


def _checked(name: str, values: np.ndarray, rule: Bound, where: str) -> np.ndarray:
    for v in values.tolist():
        try:
            rule.check(f"{where}.{name}", v)
        except ValueError as exc:
            raise SpecError(str(exc)) from None
    return values


def parse_spec(data, text: str = "", joints=None) -> SweepSpec:
    """A :class:`SweepSpec` of a spec's mapping.

    Parameters
    ----------
    data : mapping
        The YAML's content.
    text : str
        The YAML text (recorded).
    joints : mapping of str to Joint, optional
        The body's moving joints (a URDF's), to check ``joint.NAME`` axes against; None for a
        rigid mesh (no joint axis allowed).

    Raises
    ------
    SpecError
        Naming the field, its value and what it should be.
    """
    if not isinstance(data, dict):
        raise SpecError("the spec must be a mapping of fields (mesh, model, axes ...)")
    unknown = sorted(set(data) - set(FIELDS))
    if unknown:
        raise SpecError(f"{unknown[0]}: not a spec field; the fields are {', '.join(FIELDS)}")
    mesh = str(data.get("mesh", "")).strip()
    if not mesh:
        raise SpecError("mesh: missing; give a mesh file, a URDF or a bundled body")
    try:
        model = canonical_model_name(str(data.get("model", "sentman")))
    except ValueError:
        raise SpecError(f"model: {data.get('model')!r} is not one of {', '.join(MODELS)}") from None
    shading = str(data.get("shading", "raycast"))
    if shading not in SHADING_MODES:
        raise SpecError(f"shading: {shading!r} is not one of {', '.join(SHADING_MODES)}")
    reference = data.get("reference") or {}
    if not isinstance(reference, dict) or set(reference) - {"area", "length", "moment_point"}:
        raise SpecError("reference: a mapping of area, length and moment_point")
    materials = data.get("materials") or []
    if isinstance(materials, str) or not all(isinstance(m, str) for m in materials):
        raise SpecError("materials: a list of NAME:key=value texts")
    fixed = {}
    for name, value in (data.get("fixed") or {}).items():
        if name not in FIXED:
            raise SpecError(f"fixed.{name}: not an input; the fixed inputs are {', '.join(FIXED)}")
        fixed[name] = float(
            _checked(name, np.array([_number(value, name)]), AXES[name][0], "fixed")[0]
        )
    raw_axes = data.get("axes")
    if not isinstance(raw_axes, dict) or not raw_axes:
        raise SpecError("axes: missing; give at least aoa or aos")
    axes = {}
    for name in ("aoa", "aos"):
        axes[name] = _checked(
            name, axis_values(raw_axes.get(name, 0.0), name), AXES[name][0], "axes"
        )
    for name, given in raw_axes.items():
        if name in ("aoa", "aos"):
            continue
        if name.startswith(JOINT_PREFIX):
            joint = name[len(JOINT_PREFIX) :]
            if joints is None:
                raise SpecError(f"axes.{name}: the mesh {mesh} is no URDF: it has no joints")
            if joint not in joints:
                raise SpecError(
                    f"axes.{name}: {joint!r} is not a moving joint of {mesh}; its joints are "
                    f"{', '.join(joints) or 'none'}"
                )
            values = axis_values(given, name)
            _joint_values_checked(name, values, joints[joint])
            axes[name] = values
            continue
        if name not in AXES:
            known = ", ".join([*AXES, "joint.NAME"])
            raise SpecError(f"axes.{name}: not an axis; the axes are {known}")
        if name in fixed:
            raise SpecError(f"axes.{name}: also fixed; an input is fixed or swept, not both")
        axes[name] = _checked(name, axis_values(given, name), AXES[name][0], "axes")
    time = str(data.get("time", DEFAULT_TIME))
    try:
        check_time(_dt.datetime.fromisoformat(time))
    except ValueError as exc:
        raise SpecError(f"time: {time!r} is no UTC time in 1958..2100 ({exc})") from None
    given = set(fixed) | set(axes)
    if given & set(ATMOSPHERE) and given & {"temperature", "mean_mass_amu"}:
        raise SpecError(
            "axes and fixed: the gas is the atmosphere's (altitude ...) or given (temperature, "
            "mean_mass_amu), not both"
        )
    chunk = data.get("chunk_points", CHUNK_POINTS)
    if isinstance(chunk, bool) or not isinstance(chunk, int) or not 1 <= chunk <= 1_000_000:
        raise SpecError(f"chunk_points: a whole number in [1, 1000000], got {chunk!r}")
    return SweepSpec(
        mesh, model, shading, dict(reference), tuple(materials), fixed, axes, chunk, text, time
    )


def _number(value, name: str) -> float:
    try:
        if isinstance(value, bool):
            raise TypeError
        return float(value)
    except (TypeError, ValueError):
        raise SpecError(f"fixed.{name}: expected a number, got {value!r}") from None


def _joint_values_checked(name: str, values: np.ndarray, joint) -> None:
    """Joint axis values (deg for revolute and continuous joints, m for prismatic) within the
    joint's limits."""
    positions = values if joint.kind == "prismatic" else np.radians(values)
    unit = "m" if joint.kind == "prismatic" else "deg"
    for value, position in zip(values.tolist(), positions.tolist()):
        if not joint.lower <= position <= joint.upper:
            low, high = joint.lower, joint.upper
            if unit == "deg":
                low, high = math.degrees(low), math.degrees(high)
            raise SpecError(
                f"axes.{name}: {value:g} {unit} is outside the joint's limits [{low:g}, {high:g}] "
                f"{unit}"
            )


def load_spec(path) -> tuple:
    """The text and mapping of a spec file; SpecError for a file that cannot be read."""
    try:
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
    except OSError as exc:
        raise SpecError(f"spec {path}: cannot be read ({exc.strerror})") from None
    try:
        return text, yaml.safe_load(text)
    except yaml.YAMLError as exc:
        where = getattr(exc, "problem_mark", None)
        at = f" at line {where.line + 1}, column {where.column + 1}" if where else ""
        problem = getattr(exc, "problem", None) or type(exc).__name__
        raise SpecError(f"spec {path}: not YAML{at}: {problem}") from None
