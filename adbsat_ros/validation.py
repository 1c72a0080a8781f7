"""Checks of scalar inputs that raise ValueError naming the input."""

from __future__ import annotations

import math


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
