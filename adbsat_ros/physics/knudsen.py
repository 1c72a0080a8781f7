"""How rarefied the flow is: the mean free path and the body's Knudsen number (the panel method
assumes Kn >> 1). Mean free path of the U.S. Standard Atmosphere 1976 (NOAA-S/T 76-1562,
1.3.15); docs/physics.md, section 11."""

from __future__ import annotations

import math

#: The effective collision diameter of air of the U.S. Standard Atmosphere 1976 [m].
COLLISION_DIAMETER = 3.65e-10


def mean_free_path(number_density: float) -> float:
    """Mean free path [m] of a gas of ``number_density`` molecules per m^3 (> 0)."""
    if not number_density > 0.0:
        raise ValueError(f"number_density must be > 0, got {number_density!r}")
    return 1.0 / (math.sqrt(2.0) * math.pi * COLLISION_DIAMETER**2 * number_density)


def knudsen_number(number_density: float, length: float) -> float:
    """Knudsen number lambda / L of a body of characteristic length ``length`` [m] (> 0)."""
    if not length > 0.0:
        raise ValueError(f"length must be > 0, got {length!r}")
    return mean_free_path(number_density) / length
