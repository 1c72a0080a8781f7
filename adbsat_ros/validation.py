"""Input checks raising ValueError naming the input, and what an output path holds."""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np


def finite(name: str, value) -> float:
    """``value`` as a finite float, or ValueError naming ``name``."""
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(value):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return value


def non_negative(name: str, value) -> float:
    """``value`` as a finite float >= 0, or ValueError naming ``name``."""
    value = finite(name, value)
    if value < 0.0:
        raise ValueError(f"{name} must be >= 0, got {value!r}")
    return value


def positive(name: str, value) -> float:
    """``value`` as a finite float > 0, or ValueError naming ``name``."""
    value = finite(name, value)
    if value <= 0.0:
        raise ValueError(f"{name} must be > 0, got {value!r}")
    return value


def all_finite(array: np.ndarray) -> bool:
    """True if every element of ``array`` is finite (Python floats for up to 3 elements)."""
    if array.size <= 3:
        return all(map(math.isfinite, array.ravel().tolist()))
    return bool(np.isfinite(array).all())


def vectors3(value, name: str) -> np.ndarray:
    """``value`` as a float array of shape (3,) or (N, 3), finite, or ValueError naming ``name``."""
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be numbers of shape (3,) or (N, 3), got {value!r}") from None
    if array.shape[-1:] != (3,) or array.ndim > 2:
        raise ValueError(f"{name} must have shape (3,) or (N, 3), got shape {array.shape}")
    if not all_finite(array):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return array


def foreign_entry(path, own) -> Path | None:
    """The first entry at ``path`` that ``own(parts)`` does not accept as an output, or None.

    An empty directory is accepted, a symbolic link or special file never.
    """
    path = Path(path)
    if path.is_symlink() or not path.is_dir():
        return None if path.is_file() and not path.is_symlink() and own(()) else path
    for root, dirs, files in os.walk(path):
        base = Path(root)
        rel = base.relative_to(path).parts
        dirs.sort()
        for name in dirs:
            if (base / name).is_symlink():
                return base / name
        for name in sorted(files):
            entry = base / name
            if entry.is_symlink() or not entry.is_file() or not own((*rel, name)):
                return entry
    return None


def foreign_file(path, own) -> Path | None:
    """``path`` unless it is a regular file (no link) that ``own(path)`` accepts as an output."""
    path = Path(path)
    return None if path.is_file() and not path.is_symlink() and own(path) else path


def not_an_output(entry, command: str, option: str) -> str:
    """The refusal of a command to replace ``entry``, which it did not write."""
    return (
        f"{entry} is not an output of adbsat-ros {command}; remove it yourself or choose another "
        f"{option}"
    )
