"""The grid of an articulated body's joint configurations: keys, simplex vertices, positions. Steps
h_r (revolute, continuous) and h_p (prismatic); grid points clipped to the joints' limits; a
query blends the Kuhn simplex around it (docs/shading.md, "Articulated bodies")."""

from __future__ import annotations

import math
from typing import Mapping

#: Distance to a grid point, in grid steps, within which a joint is taken to be on it (a
#: position given as a multiple of the step, up to rounding, blends no second configuration);
#: also the smallest weight a grid configuration is blended with.
ON_GRID = 1e-9


def grid_steps(joints: Mapping, angle_step: float, length_step: float) -> tuple:
    """The grid step of each joint: ``length_step`` [m] if prismatic, else ``angle_step`` [rad].

    ValueError: a step is not positive.
    """
    if not (angle_step > 0.0 and length_step > 0.0):
        raise ValueError(
            f"the configuration grid's steps must be positive, got {angle_step!r} rad and "
            f"{length_step!r} m"
        )
    return tuple(
        length_step if joint.kind == "prismatic" else angle_step for joint in joints.values()
    )


def grid_key(joints: Mapping, steps: tuple, positions: Mapping[str, float]) -> tuple:
    """Grid indices of the grid configuration nearest checked joint ``positions``."""
    return tuple(math.floor(positions[name] / step + 0.5) for name, step in zip(joints, steps))


def grid_vertices(
    joints: Mapping, steps: tuple, positions: Mapping[str, float], interpolate: bool
) -> list:
    """``[(weight, key), ...]``: the Kuhn simplex around ``positions`` (or the nearest point)."""
    if not interpolate:
        return [(1.0, grid_key(joints, steps, positions))]
    base, fractions = [], []
    for (name, joint), step in zip(joints.items(), steps):
        q = positions[name]
        x = q / step
        nearest = round(x)
        if abs(x - nearest) <= ON_GRID:
            x = nearest
        index = math.floor(x)
        base.append(index)
        # the fraction between the cell's two grid positions as clipped to the limits, so
        # that the blend reproduces q in a cell a limit cuts (and is exact at the limit)
        low, high = clipped(joint, index * step), clipped(joint, (index + 1) * step)
        fraction = 0.0 if high <= low else min(max((q - low) / (high - low), 0.0), 1.0)
        fractions.append(fraction if fraction > ON_GRID else 0.0)
    order = sorted(range(len(base)), key=fractions.__getitem__, reverse=True)
    out, vertex, previous = [], list(base), 1.0
    for j in order:
        if previous - fractions[j] > ON_GRID:  # (a weight of rounding size: no vertex)
            out.append((previous - fractions[j], tuple(vertex)))
        vertex[j] += 1
        previous = fractions[j]
    if previous > ON_GRID:
        out.append((previous, tuple(vertex)))
    total = sum(w for w, _ in out)
    return [(w / total, key) for w, key in out]


def grid_configuration(joints: Mapping, steps: tuple, key: tuple) -> dict:
    """The joint positions of a grid key, clipped to the joints' limits."""
    return {
        name: clipped(joint, index * step)
        for (name, joint), index, step in zip(joints.items(), key, steps)
    }


def clipped(joint, position: float) -> float:
    """``position`` clipped to ``joint``'s limits."""
    return min(max(position, joint.lower), joint.upper)
