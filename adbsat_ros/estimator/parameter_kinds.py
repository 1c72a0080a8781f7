"""The kinds of the node's parameters: ``kind(name, value, bound) -> setting`` checks a value
against its range (or None) and converts it, else ValueError ``"parameter NAME: ..."``.
"""

from __future__ import annotations

import datetime as _dt

import numpy as np

from adbsat_ros.bounds import Bound, bounded
from adbsat_ros.environment.atmosphere import FIRST_YEAR, LAST_YEAR
from adbsat_ros.physics.gsi_models import canonical_model_name

#: The valid range of ``epoch_utc``, in words.
EPOCH_UTC_RANGE = f"from {FIRST_YEAR}-01-01T00:00:00 to {LAST_YEAR}-12-31T23:59:59 UTC"
#: Why ``epoch_utc`` has that range.
EPOCH_UTC_REASON = "the years the time scales and the atmosphere model's space weather cover"


def number(name: str, value, bound: Bound) -> float:
    """A number within its range (an element of a list named ``name[label]``)."""
    try:
        return bounded(name, value, bound)
    except ValueError as exc:
        raise ValueError(f"parameter {name.split('[')[0]}: {exc}") from None


def _numbers(name: str, value, bound: Bound, count: int | None, labels, expected: str) -> tuple:
    """``count`` numbers (any if None), each within ``bound``, named ``name[label]`` in errors."""
    if isinstance(value, str) or not hasattr(value, "__len__"):
        raise ValueError(f"parameter {name}: expected {expected}, got {value!r}")
    if count is not None and len(value) != count:
        raise ValueError(f"parameter {name}: expected {expected}, got {value!r}")
    return tuple(number(f"{name}[{label}]", x, bound) for label, x in zip(labels, value))


def whole(name: str, value, bound: Bound) -> int:
    """A whole number within its range."""
    result = number(name, value, bound)
    if not result.is_integer():
        raise ValueError(f"parameter {name}: {name} must be a whole number, got {value!r}")
    return int(result)


def flag(name: str, value, bound=None) -> bool:
    """True or false (a string such as "false" is not taken for True)."""
    if not isinstance(value, bool):
        raise ValueError(f"parameter {name}: expected true or false, got {value!r}")
    return value


def text(name: str, value, bound=None) -> str:
    """Any text."""
    return str(value)


def stripped(name: str, value, bound=None) -> str:
    """Text without surrounding blanks."""
    return str(value).strip()


def mesh_name(name: str, value, bound=None) -> str:
    """A mesh file or bundled body's name: text, not empty."""
    value = str(value).strip()
    if not value:
        raise ValueError(f"parameter {name}: empty")
    return value


def frame_id(name: str, value, bound=None) -> str:
    """A frame name without a leading "/" (``base_link`` if empty)."""
    return str(value).lstrip("/") or "base_link"


def texts(name: str, value, bound=None) -> tuple:
    """A list of texts, each stripped, the empty ones left out."""
    return tuple(s for s in (str(x).strip() for x in value) if s)


def frame_ids(name: str, value, bound=None) -> tuple:
    """Frame names as a tuple of lower-case strings without a leading "/"."""
    if isinstance(value, str) or not all(isinstance(x, str) for x in value):
        raise ValueError(f"parameter {name}: expected a list of frame names, got {value!r}")
    names = tuple(x.strip().lstrip("/").lower() for x in value)
    if not names:
        raise ValueError(f"parameter {name}: {name} must name at least one frame")
    if not all(names):
        raise ValueError(f"parameter {name}: {name}: names must be non-empty, got {value!r}")
    return names


def vector3(name: str, value, bound: Bound) -> tuple:
    """Three numbers (x, y, z), each within the range."""
    return _numbers(name, value, bound, 3, "xyz", "three numbers")


def inertia(name: str, value, bound: Bound) -> tuple | None:
    """An inertia tensor, 9 numbers row-major, symmetric and positive definite; None when all are
    0."""
    tensor = _numbers(name, value, bound, 9, range(9), "9 numbers (3 x 3, row-major)")
    if not any(tensor):
        return None
    matrix = np.array(tensor).reshape(3, 3)
    if np.max(np.abs(matrix - matrix.T)) > 1e-9 * np.max(np.abs(matrix)):
        raise ValueError(f"parameter {name}: the tensor must be symmetric, got {value!r}")
    if np.linalg.eigvalsh(matrix).min() <= 0.0:
        raise ValueError(
            f"parameter {name}: the tensor must be positive definite (every principal moment "
            f"> 0), got {value!r}"
        )
    return tensor


def ap_history(name: str, value, bound: Bound) -> tuple | None:
    """NRLMSISE-00's 7 Ap values, each in the range; None for a single value (unused)."""
    if isinstance(value, str) or not hasattr(value, "__len__"):
        raise ValueError(f"parameter {name}: expected a list of numbers, got {value!r}")
    if len(value) <= 1:
        return None
    history = _numbers(name, value, bound, None, range(len(value)), "a list of numbers")
    if len(history) != 7:
        raise ValueError(
            f"parameter {name}: needs 7 values (or one to leave it unused), got {len(history)}"
        )
    return history


def model(name: str, value, bound=None) -> str:
    """A gas-surface model's canonical name."""
    try:
        return canonical_model_name(value)
    except ValueError as exc:
        raise ValueError(f"parameter {name}: {exc}") from None


def choice(allowed: tuple, lower: bool = False):
    """The kind of a parameter that is one of ``allowed`` (in lower case if ``lower``)."""

    def check(name: str, value, bound=None) -> str:
        value = str(value).lower() if lower else str(value)
        if value not in allowed:
            raise ValueError(f"parameter {name}: {value!r} is not one of {', '.join(allowed)}")
        return value

    return check


def parse_utc(name: str, value, bound=None) -> _dt.datetime:
    """An ISO 8601 UTC time (a trailing Z or +00:00 allowed) as an aware datetime, within
    :data:`EPOCH_UTC_RANGE`."""
    try:
        t = _dt.datetime.fromisoformat(str(value).replace("Z", "+00:00"))
        if t.tzinfo is None:
            t = t.replace(tzinfo=_dt.timezone.utc)
        t = t.astimezone(_dt.timezone.utc)
    except ValueError:
        raise ValueError(f"parameter {name}: not an ISO 8601 time: {value!r}") from None
    except OverflowError:  # (an offset that takes it outside the years datetime has)
        t = None
    if t is None or not FIRST_YEAR <= t.year <= LAST_YEAR:
        raise ValueError(
            f"parameter {name}: {name} must be {EPOCH_UTC_RANGE} ({EPOCH_UTC_REASON}), "
            f"got {value!r}"
        )
    return t
