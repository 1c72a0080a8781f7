"""What a sweep computes: its YAML spec, checked into a :class:`SweepSpec` (docs/sweeps.md).

Units and ranges of docs/physics.md section 11; ``aoa`` and ``aos`` are always axes; unset
inputs take :data:`DEFAULTS`. A bad field is a :class:`SpecError` naming it.
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import json
import math
import re
from dataclasses import dataclass, fields

import numpy as np
import yaml

from adbsat_ros.bounds import bounded, errors_as
from adbsat_ros.environment.atmosphere import ATMOSPHERE_MODELS, check_time
from adbsat_ros.environment.space_weather import SPACE_WEATHER_SOURCES, HistoricalWeather
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.gsi_models import MODELS, canonical_model_name
from adbsat_ros.physics.setup import BodySpec, Setup, ShadingPolicy, SolverSpec
from adbsat_ros.shading.shader import MODES as SHADING_MODES
from adbsat_ros.sweep.axes import (
    ATMOSPHERE,
    AXES,
    DEFAULT_TIME,
    FIXED,
    JOINT_PREFIX,
    SCALE_PREFIX,
    SpecError,
    axis_values,
    checked,
    joint_values_checked,
    mesh_variants,
    number,
    scale_rule,
    solver_settings,
)

#: Points per task unless the spec says: a few seconds of ray-cast panel method.
CHUNK_POINTS = 256


@dataclass(frozen=True)
class SweepSpec:
    """A checked sweep spec; ``axes``: name -> values in the spec's units (deg for angles).

    ``time``: the atmosphere's UTC (ISO 8601); ``meshes``: a ``mesh`` axis's variants, else empty.
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
    solver: tuple = (("method", "panel"),)
    meshes: tuple = ()
    atmosphere_model: str = "nrlmsise00"
    space_weather: str = "fixed"

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
        if self.tpmc is not None:  # (the panel method's specs keep their fingerprints)
            canonical["solver"] = dict(self.solver)
        if self.meshes:
            canonical["meshes"] = list(self.meshes)
        for name, default in (("atmosphere_model", "nrlmsise00"), ("space_weather", "fixed")):
            if getattr(self, name) != default:  # (the other specs keep their fingerprints)
                canonical[name] = getattr(self, name)
        return hashlib.sha256(json.dumps(canonical, sort_keys=True).encode()).hexdigest()

    @property
    def tpmc(self) -> dict | None:
        """The test-particle run (``particles``, ``tolerance``, ``seed``), or None (panel)."""
        solver = dict(self.solver)
        return None if solver["method"] == "panel" else solver

    def scales(self) -> dict:
        """``{species: factor}`` of the scaled species (fixed or swept names)."""
        names = [*self.fixed, *self.axes]
        return {k[len(SCALE_PREFIX) :]: k for k in names if k.startswith(SCALE_PREFIX)}

    def joint_axes(self) -> dict:
        """``{joint name: axis name}`` of the swept joints."""
        return {k[len(JOINT_PREFIX) :]: k for k in self.axes if k.startswith(JOINT_PREFIX)}


#: Fields of a spec: those of a SweepSpec but its text and a mesh axis's variants.
FIELDS = tuple(f.name for f in fields(SweepSpec) if f.name not in ("text", "meshes"))


def parse_spec(data, text: str = "", joints=None) -> SweepSpec:
    """A :class:`SweepSpec` of a spec's mapping ``data`` and its YAML ``text``.

    SpecError: a field, its value and what it should be.
    """
    if not isinstance(data, dict):
        raise SpecError("the spec must be a mapping of fields (mesh, model, axes ...)")
    unknown = sorted(set(data) - set(FIELDS))
    if unknown:
        raise SpecError(f"{unknown[0]}: not a spec field; the fields are {', '.join(FIELDS)}")
    raw_axes = data.get("axes")
    if not isinstance(raw_axes, dict) or not raw_axes:
        raise SpecError("axes: missing; give at least aoa or aos")
    meshes = mesh_variants(data, raw_axes)
    mesh = meshes[0] if meshes else str(data.get("mesh", "")).strip()
    if not mesh:
        raise SpecError("mesh: missing; give a mesh file, a URDF or a bundled body")
    try:
        model = canonical_model_name(str(data.get("model", "sentman")))
    except ValueError:
        raise SpecError(f"model: {data.get('model')!r} is not one of {', '.join(MODELS)}") from None
    shading = str(data.get("shading", "raycast"))
    if shading not in SHADING_MODES:
        raise SpecError(f"shading: {shading!r} is not one of {', '.join(SHADING_MODES)}")
    reference = reference_checked(data.get("reference") or {})
    materials = data.get("materials") or []
    if isinstance(materials, str) or not all(isinstance(m, str) for m in materials):
        raise SpecError("materials: a list of NAME:key=value texts")
    fixed = {}
    for name, value in (data.get("fixed") or {}).items():
        rule = scale_rule(name, "fixed") if name.startswith(SCALE_PREFIX) else None
        if rule is None and name not in FIXED:
            known = ", ".join([*FIXED, "scale.SPECIES"])
            raise SpecError(f"fixed.{name}: not an input; the fixed inputs are {known}")
        rule = rule or AXES[name][0]
        fixed[name] = float(checked(name, np.array([number(value, name)]), rule, "fixed")[0])
    axes = {
        name: checked(name, axis_values(raw_axes.get(name, 0.0), name), AXES[name][0], "axes")
        for name in ("aoa", "aos")
    }
    for name, given in raw_axes.items():
        if name in ("aoa", "aos"):
            continue
        if name == "mesh":
            axes[name] = np.arange(len(meshes), dtype=float)
            continue
        if name in fixed:
            raise SpecError(f"axes.{name}: also fixed; an input is fixed or swept, not both")
        if name.startswith(SCALE_PREFIX):
            rule = scale_rule(name, "axes")
            axes[name] = checked(name, axis_values(given, name), rule, "axes")
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
            joint_values_checked(name, values, joints[joint])
            axes[name] = values
            continue
        if name not in AXES:
            known = ", ".join([*AXES, "joint.NAME"])
            raise SpecError(f"axes.{name}: not an axis; the axes are {known}")
        axes[name] = checked(name, axis_values(given, name), AXES[name][0], "axes")
    points_checked(axes)
    time = str(data.get("time", DEFAULT_TIME))
    try:
        epoch = _dt.datetime.fromisoformat(time)
        check_time(epoch)
    except ValueError as exc:
        raise SpecError(f"time: {time!r} is no UTC time in 1958..2100 ({exc})") from None
    for where, hours in (("fixed", fixed.get("time")), ("axes", axes.get("time"))):
        for value in np.atleast_1d(hours if hours is not None else []).tolist():
            try:
                check_time(epoch + _dt.timedelta(hours=value))
            except (ValueError, OverflowError):
                raise SpecError(
                    f"{where}.time: {value:g} h after {time} is outside 1958..2100"
                ) from None
    given = set(fixed) | set(axes)
    if given & set(ATMOSPHERE) and "altitude" not in given:
        raise SpecError(
            "altitude: the atmosphere's gas (asked for by "
            f"{', '.join(sorted(given & set(ATMOSPHERE)))}) needs an altitude, fixed or an axis"
        )
    if any(name.startswith(SCALE_PREFIX) for name in given) and not given & set(ATMOSPHERE):
        raise SpecError(
            "scale: species are scaled in the atmosphere's gas; fix or sweep altitude (or "
            "another atmosphere input) with it"
        )
    if meshes and any(name.startswith(JOINT_PREFIX) for name in axes):
        raise SpecError("axes.mesh: mesh variants are rigid meshes; no joint axis with them")
    if meshes and not {"area", "length"} <= set(reference):
        raise SpecError(
            "reference: mesh variants are compared at one reference area and length: give both"
        )
    solver = solver_settings(data.get("solver"))
    if given & set(ATMOSPHERE) and given & {"temperature", "mean_mass_amu"}:
        raise SpecError(
            "axes and fixed: the gas is the atmosphere's (altitude ...) or given (temperature, "
            "mean_mass_amu), not both"
        )
    atmosphere = _atmosphere_checked(data, epoch, fixed, axes)
    chunk = data.get("chunk_points", CHUNK_POINTS)
    if isinstance(chunk, bool) or not isinstance(chunk, int) or not 1 <= chunk <= 1_000_000:
        raise SpecError(f"chunk_points: a whole number in [1, 1000000], got {chunk!r}")
    return SweepSpec(
        mesh,
        model,
        shading,
        dict(reference),
        tuple(materials),
        fixed,
        axes,
        chunk,
        text,
        time,
        solver,
        meshes,
        *atmosphere,
    )


def _atmosphere_checked(data, epoch, fixed: dict, axes: dict) -> tuple:
    """``(atmosphere_model, space_weather)`` of a spec; ``historical`` takes the indices of each
    time from the record, which must hold them (SpecError naming the field otherwise)."""
    model = str(data.get("atmosphere_model", "nrlmsise00"))
    if model not in ATMOSPHERE_MODELS:
        raise SpecError(f"atmosphere_model: {model!r} is not one of {', '.join(ATMOSPHERE_MODELS)}")
    source = str(data.get("space_weather", "fixed"))
    if source not in SPACE_WEATHER_SOURCES:
        raise SpecError(
            f"space_weather: {source!r} is not one of {', '.join(SPACE_WEATHER_SOURCES)}"
        )
    if source == "historical":
        given = sorted({"f107", "f107a", "ap"} & (set(fixed) | set(axes)))
        if given:
            raise SpecError(f"space_weather: historical takes {given[0]} from the record")
        record = HistoricalWeather()
        for hours in np.atleast_1d(axes.get("time", fixed.get("time", 0.0))).tolist():
            with errors_as(SpecError, ValueError, "space_weather: "):
                record.at(epoch + _dt.timedelta(hours=hours))
    return model, source


def body_setup(spec: SweepSpec, mesh: str) -> Setup:
    """The set-up of one body (mesh variant) of a sweep."""
    ref, run = spec.reference, spec.tpmc
    return Setup(
        body=BodySpec(mesh),
        model=spec.model,
        overrides=spec.materials,
        reference=Reference(
            ref.get("area"), ref.get("length"), tuple(ref.get("moment_point", (0.0, 0.0, 0.0)))
        ),
        shading=ShadingPolicy(spec.shading),
        solver=SolverSpec() if run is None else SolverSpec(**run),
        labels=(("materials", ""), ("moment_point", "reference.moment_point"), ("solver", "")),
    )


def reference_checked(reference) -> dict:
    """The ``reference`` field, checked: ``area``, ``length``, ``moment_point`` in range."""
    if not isinstance(reference, dict) or set(reference) - {"area", "length", "moment_point"}:
        raise SpecError("reference: a mapping of area, length and moment_point")
    point = reference.get("moment_point", (0.0, 0.0, 0.0))
    if not isinstance(point, (list, tuple)) or len(point) != 3:
        raise SpecError(f"reference.moment_point: three numbers [x, y, z], got {point!r}")
    with errors_as(SpecError):
        for name in ("area", "length"):
            if name in reference:
                bounded(f"reference.{name}", reference[name], name)
        for axis, x in zip("xyz", point):
            bounded(f"reference.moment_point {axis}", x, "offset")
    return dict(reference)


def points_checked(axes: dict) -> None:
    """The sweep's points within ``sweep_points``; SpecError naming the axes' lengths."""
    lengths = [len(v) for v in axes.values()]
    with errors_as(SpecError):
        text = " x ".join(map(str, lengths))
        bounded(f"axes: the points ({text})", math.prod(lengths), "sweep_points")


class SpecLoader(yaml.SafeLoader):
    """``yaml.safe_load``'s YAML 1.1, but ``10:5:30`` is a range's text, not a base-60 number:
    safe_load's int and float rules without their base-60 forms."""


SpecLoader.yaml_implicit_resolvers = {
    first: [(tag, rx) for tag, rx in rules if not rx.match("10:5:30") and not rx.match("1:5:3.5")]
    for first, rules in yaml.SafeLoader.yaml_implicit_resolvers.items()
}

for _tag, _pattern in (
    ("int", r"[-+]?(?:0b[0-1_]+|0[0-7_]+|0|[1-9][0-9_]*|0x[0-9a-fA-F_]+)"),
    ("float", r"[-+]?[0-9][0-9_]*\.[0-9_]*(?:[eE][-+][0-9]+)?|\.[0-9][0-9_]*(?:[eE][-+][0-9]+)?"),
    ("float", r"[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN)"),
):
    SpecLoader.add_implicit_resolver(
        f"tag:yaml.org,2002:{_tag}", re.compile(f"^(?:{_pattern})$"), list("-+0123456789.")
    )


def load_spec(path) -> tuple:
    """The text and mapping of a spec file; SpecError for a file that cannot be read."""
    try:
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
    except OSError as exc:
        raise SpecError(f"spec {path}: cannot be read ({exc.strerror})") from None
    try:
        return text, yaml.load(text, Loader=SpecLoader)
    except yaml.YAMLError as exc:
        where = getattr(exc, "problem_mark", None)
        at = f" at line {where.line + 1}, column {where.column + 1}" if where else ""
        problem = getattr(exc, "problem", None) or type(exc).__name__
        raise SpecError(f"spec {path}: not YAML{at}: {problem}") from None
