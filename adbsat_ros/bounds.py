"""The valid range of every physical input, in one table (:data:`BOUNDS`), each with its reason;
a value outside is refused with its name, the value and the range. docs/physics.md, section 11.
"""

from __future__ import annotations

import contextlib
import math
import os
from dataclasses import dataclass


@dataclass(frozen=True)
class Bound:
    """The range [low, high] of one input, its unit and why; ``*_open`` opens an end."""

    low: float
    high: float
    unit: str
    reason: str
    low_open: bool = False
    high_open: bool = False

    def text(self) -> str:
        """The range as shown in errors, e.g. ``(0, 20000] m/s``."""
        unit = f" {self.unit}" if self.unit else ""
        opening, closing = "(" if self.low_open else "[", ")" if self.high_open else "]"
        return f"{opening}{self.low:g}, {self.high:g}{closing}{unit}"

    def contains(self, value: float) -> bool:
        """Whether a float lies in the range (False for NaN)."""
        above = value > self.low if self.low_open else value >= self.low
        below = value < self.high if self.high_open else value <= self.high
        return above and below

    def check(self, name: str, value) -> float:
        """``value`` as a float in the range, else ValueError naming ``name`` (:func:`bounded`)."""
        try:
            if isinstance(value, bool):  # (True is 1.0 to float(): a flag is not a number)
                raise TypeError
            number = float(value)
        except (TypeError, ValueError):
            raise ValueError(f"{name} must be a number, got {value!r}") from None
        if not (math.isfinite(number) and self.contains(number)):
            raise ValueError(f"{name} must be in {self.text()} ({self.reason}), got {value!r}")
        return number


BOUNDS = {
    "speed": Bound(
        1.0,
        20_000.0,
        "m/s",
        "speed relative to the gas: Earth escape speed at the surface is 11.2 km/s, plus 0.5 km/s "
        "of co-rotating air and winds; 20 km/s leaves room for any Earth orbit, and below 1 m/s "
        "there is no flow to speak of",
    ),
    "temperature": Bound(
        50.0,
        5_000.0,
        "K",
        "gas temperature: NRLMSISE-00 gives 180-2,500 K from the ground to 1,000 km; 5,000 K "
        "leaves room for any storm",
    ),
    "wall_temperature": Bound(
        1.0,
        3_000.0,
        "K",
        "surface temperature: above 3,000 K nearly every spacecraft material has melted",
    ),
    "mean_mass_amu": Bound(
        1.0,
        100.0,
        "amu",
        "mean molecular mass of the gas: atomic hydrogen (1 amu) to beyond argon (40 amu)",
    ),
    "mass_density": Bound(
        0.0,
        2.0,
        "kg/m^3",
        "sea-level air is 1.2 kg/m^3; a free-molecular flow is many orders thinner",
        low_open=True,
    ),
    "number_density": Bound(
        0.0,
        1e26,
        "m^-3",
        "a species' number density: sea-level air holds 2.5e25 m^-3 in all",
    ),
    "f107": Bound(
        50.0,
        500.0,
        "sfu",
        "10.7 cm solar flux: the values observed since 1947 lie between about 60 and 460 sfu, the "
        "era of the data NRLMSISE-00 was fitted to; beyond, its density is an extrapolation",
    ),
    "ap": Bound(
        0.0,
        400.0,
        "",
        "geomagnetic ap index: its scale runs from 0 to 400 by definition",
    ),
    "orbital_speed": Bound(
        0.0,
        20_000.0,
        "m/s",
        "speed of a state: above Earth escape speed (11.2 km/s) with a margin",
    ),
    "length": Bound(
        1e-3,
        1_000.0,
        "m",
        "a reference length: from a millimetre to a kilometre, longer than any spacecraft",
    ),
    "offset": Bound(
        -1_000.0,
        1_000.0,
        "m",
        "a coordinate of a point of the satellite (the centre of mass) in the mesh frame: no "
        "spacecraft is a kilometre long",
    ),
    "wind": Bound(
        -2_000.0,
        2_000.0,
        "m/s",
        "a component of the wind relative to the rotating Earth: thermospheric winds reach "
        "several hundred m/s in storms (HWM14); 2 km/s leaves a wide margin",
    ),
    "mesh_extent": Bound(
        1e-3,
        200.0,
        "m",
        "the largest side of a mesh's bounding box: a satellite is between a millimetre and "
        "200 m across (the ISS is 109 m); outside, the file's units are likely not metres",
    ),
    "mesh_coordinate": Bound(
        -1e6,
        1e6,
        "m",
        "a coordinate of a mesh's vertex (after the scale to metres): a thousand kilometres "
        "from the mesh origin is beyond any body in orbit, even with its size accepted, and "
        "keeps the panels' areas, volumes and moments far within floating point",
    ),
    "area": Bound(
        1e-6,
        1e5,
        "m^2",
        "a reference area: from a square millimetre to a square of 316 m on a side",
    ),
    "altitude": Bound(
        0.0,
        1_000.0,
        "km",
        "a height above the WGS-84 ellipsoid: NRLMSISE-00 holds from the ground to 1,000 km",
    ),
    "latitude": Bound(-90.0, 90.0, "deg", "a geodetic latitude"),
    "longitude": Bound(-360.0, 360.0, "deg", "an east longitude, once around either way"),
    "position_radius": Bound(
        0.0,
        1e9,
        "m",
        "the distance of a position from the Earth's centre: the atmosphere ends 1,000 km up, "
        "the Moon is 3.8e8 m away",
    ),
    "sweep_axis_values": Bound(
        1.0,
        1e6,
        "",
        "the values along one axis of a sweep: a million is a step of 0.00036 deg around a circle",
    ),
    "sweep_points": Bound(
        1.0,
        1e9,
        "",
        "the points of a sweep (the product of its axes' lengths): its store keeps about 200 "
        "bytes a point, so 1e9 points fill 200 GB, and take days of CPU",
    ),
    "message_rate": Bound(
        0.0,
        1e6,
        "Hz",
        "a message rate: stamps are whole nanoseconds, and no attitude sensor or orbit "
        "estimator runs at a megahertz",
        low_open=True,
    ),
    "messages": Bound(
        1.0,
        1e8,
        "",
        "the messages of a simulated stream (duration x rate + 1): 1e8 is 116 days at 10 Hz, "
        "a bag of about 10 GB",
    ),
}

#: How far from its body a point of it (a moment reference point, a centre of mass) may lie, in
#: body sizes (the largest side of the mesh's bounding box): see :func:`body_point_bounds`.
BODY_REACH = 10.0
BODY_POINT_REASON = (
    "a moment reference point or centre of mass lies within the body's bounding box or near "
    f"it: at most {BODY_REACH:g} times the body's largest side beyond the box that holds the "
    "body and the mesh origin; farther, the lever arm is no part of the body (a unit or "
    "exponent mistyped) and the moment is that arm times the force"
)


def bounded(name: str, value, bound: str | Bound | None = None) -> float:
    """``value`` as a float within ``bound`` (a :class:`Bound` or a name in :data:`BOUNDS`).

    ValueError: ``"NAME must be in RANGE (REASON), got VALUE"`` (NaN, inf included), or
    ``"NAME must be a number, got VALUE"``.
    """
    rule = bound if isinstance(bound, Bound) else BOUNDS[bound or name]
    return rule.check(name, value)


@contextlib.contextmanager
def errors_as(kind, errors=ValueError, prefix: str = ""):
    """Raise ``kind(prefix + text)`` for an exception of the type(s) ``errors`` raised inside."""
    try:
        yield
    except errors as exc:
        raise kind(f"{prefix}{exc}") from None


def body_point_bounds(lower, upper) -> tuple:
    """The range [m] of each coordinate of a body point: the bounding box and the origin, widened by
    :data:`BODY_REACH` times its largest side.
    """
    size = max(float(high) - float(low) for low, high in zip(lower, upper))
    margin = BODY_REACH * size
    return tuple(
        Bound(min(float(low), 0.0) - margin, max(float(high), 0.0) + margin, "m", BODY_POINT_REASON)
        for low, high in zip(lower, upper)
    )


def body_point(name: str, point, lower, upper) -> tuple:
    """``point`` [m] as floats within :func:`body_point_bounds`, else ValueError."""
    rules = body_point_bounds(lower, upper)
    return tuple(rule.check(f"{name} {axis}", x) for axis, x, rule in zip("xyz", point, rules))


def available_memory() -> int | None:
    """Bytes of memory this machine can give a job now (MemAvailable, else free pages), or None."""
    with contextlib.suppress(OSError, ValueError, IndexError):
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    try:
        return int(os.sysconf("SC_AVPHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):
        return None


def check_memory(name: str, estimate: float, available: int | None = None) -> None:
    """ValueError naming ``name`` if ``estimate`` [bytes] exceeds the available memory."""
    available = available_memory() if available is None else available
    if available is not None and estimate > available:
        raise ValueError(
            f"{name} needs about {_bytes_text(estimate)} of memory, more than the "
            f"{_bytes_text(available)} this machine has available"
        )


def _bytes_text(count: float) -> str:
    for unit, size in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6)):
        if count >= size:
            return f"{count / size:.3g} {unit}"
    return f"{count / 1e3:.3g} kB"
