"""The inputs a sweep varies or fixes: names, units, ranges (docs/physics.md section 11), defaults,
and the checks of a spec's values (a :class:`SpecError` naming field, value and range).
"""

from __future__ import annotations

import math

import numpy as np

from adbsat_ros.bounds import BOUNDS, Bound, errors_as
from adbsat_ros.physics.constants import SPECIES
from adbsat_ros.physics.tpmc.method import run_settings


class SpecError(ValueError):
    """A spec that cannot be swept; the message names the field."""


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
    "latitude": (BOUNDS["latitude"], "deg"),
    "longitude": (BOUNDS["longitude"], "deg"),
    "f107": (BOUNDS["f107"], "sfu"),
    "f107a": (BOUNDS["f107"], "sfu"),
    "ap": (BOUNDS["ap"], ""),
    "time": (Bound(-1e6, 1e6, "h", "hours after the spec's time, within 1958..2100"), "h"),
}
#: A factor on one species' number density of NRLMSISE-00 (``scale.O``: atomic oxygen ...).
SCALE = Bound(0.0, 100.0, "", "a factor on one species' number density")
SCALE_PREFIX = "scale."
#: Inputs that make the gas that of the atmosphere (with ``time``, a fixed UTC).
ATMOSPHERE = ("altitude", "latitude", "longitude", "f107", "f107a", "ap", "time")
#: The atmosphere's defaults, and the UTC of a sweep that gives none.
ATMOSPHERE_DEFAULTS = {
    "latitude": 0.0,
    "longitude": 0.0,
    "f107": 150.0,
    "f107a": 150.0,
    "ap": 4.0,
    "time": 0.0,
}
DEFAULT_TIME = "2026-01-01T00:00:00"
#: Inputs a spec may fix (any axis but the attitude).
FIXED = tuple(name for name in AXES if name not in ("aoa", "aos"))
#: Values of the inputs neither fixed nor swept (alpha and wall_temperature: the materials').
DEFAULTS = {"speed": 7700.0, "temperature": 900.0, "mean_mass_amu": 16.0}
#: Fields of ``solver``: the panel method (default) or test particles (every reflection).
SOLVER_FIELDS = ("method", "particles", "tolerance", "seed")
JOINT_PREFIX = "joint."


def axis_values(text, name: str) -> np.ndarray:
    """An axis's values: a number, a list, or ``start:step:stop`` (stop included if reached)."""
    if isinstance(text, str) and ":" in text:
        parts = text.split(":")
        try:
            start, step, stop = (float(p) for p in parts)
        except ValueError:
            raise SpecError(f"axes.{name}: expected start:step:stop, got {text!r}") from None
        if len(parts) != 3 or not all(map(math.isfinite, (start, step, stop))):
            raise SpecError(f"axes.{name}: start:step:stop of finite numbers, got {text!r}")
        if step <= 0 or stop < start:
            raise SpecError(
                f"axes.{name}: start:step:stop needs a step > 0 and stop >= start, got {text!r}"
            )
        steps = (stop - start) / step + 1e-9
        count = math.floor(steps) + 1 if math.isfinite(steps) else math.inf
        with errors_as(SpecError):  # (counted before the values are made)
            BOUNDS["sweep_axis_values"].check(f"axes.{name}: the values of {text!r}", count)
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
    with errors_as(SpecError):
        BOUNDS["sweep_axis_values"].check(f"axes.{name}: the values", out.size)
    if len(set(out.tolist())) != out.size:
        raise SpecError(f"axes.{name}: a value appears twice")
    return out


def checked(name: str, values: np.ndarray, rule: Bound, where: str) -> np.ndarray:
    """``values`` of input ``name`` (given under ``where``), each within ``rule``."""
    with errors_as(SpecError):
        for v in values.tolist():
            rule.check(f"{where}.{name}", v)
    return values


def mesh_variants(data: dict, raw_axes: dict) -> tuple:
    """The mesh files of a ``mesh`` axis (none without one)."""
    if "mesh" not in raw_axes:
        return ()
    variants = raw_axes["mesh"]
    if "mesh" in data:
        raise SpecError("axes.mesh: also the field mesh; give the variants on the axis only")
    if not isinstance(variants, list) or not variants:
        raise SpecError("axes.mesh: a list of mesh files (the design variants)")
    if not all(isinstance(v, str) and v.strip() for v in variants):
        raise SpecError(f"axes.mesh: mesh files are names, got {variants!r}")
    if len(set(variants)) != len(variants):
        raise SpecError("axes.mesh: a mesh appears twice")
    if any(v.lower().endswith(".urdf") for v in variants):
        raise SpecError("axes.mesh: mesh variants are rigid meshes (.obj, .stl ...), not URDFs")
    return tuple(v.strip() for v in variants)


def scale_rule(name: str, where: str) -> Bound:
    """The range of a ``scale.SPECIES`` input, for a species of NRLMSISE-00."""
    species = name[len(SCALE_PREFIX) :]
    if species not in SPECIES:
        raise SpecError(
            f"{where}.{name}: {species!r} is not a species of NRLMSISE-00; they are "
            f"{', '.join(SPECIES)}"
        )
    return SCALE


def solver_settings(given) -> tuple:
    """The checked ``solver`` field, as sorted pairs."""
    if given is None:
        return (("method", "panel"),)
    if not isinstance(given, dict) or set(given) - set(SOLVER_FIELDS):
        raise SpecError(f"solver: a mapping of {', '.join(SOLVER_FIELDS)}")
    method = given.get("method", "panel")
    if method == "panel":
        if len(given) > 1:
            raise SpecError("solver: particles, tolerance and seed are for method tpmc")
        return (("method", "panel"),)
    if method != "tpmc":
        raise SpecError(f"solver.method: {method!r} is not panel or tpmc")
    particles, tolerance = given.get("particles"), given.get("tolerance")
    seed = given.get("seed", 0)
    with errors_as(SpecError, (TypeError, ValueError), "solver: "):
        run_settings(particles, tolerance, seed)
    return tuple(
        sorted(
            {"method": "tpmc", "particles": particles, "tolerance": tolerance, "seed": seed}.items()
        )
    )


def number(value, name: str) -> float:
    """The fixed input ``name`` as a float."""
    try:
        if isinstance(value, bool):
            raise TypeError
        return float(value)
    except (TypeError, ValueError):
        raise SpecError(f"fixed.{name}: expected a number, got {value!r}") from None


def joint_values_checked(name: str, values: np.ndarray, joint) -> None:
    """Joint axis values (deg, or m for a prismatic joint) within the joint's limits."""
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
