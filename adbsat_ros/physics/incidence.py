"""Incidence of the flow on panels: sin(delta) without cancellation near normal incidence.

Also the cross product over the last axis used by the panel sums (vectors in the mesh frame G).
"""

from __future__ import annotations

import numpy as np


def cross(a, b) -> np.ndarray:
    """Cross product a x b over the last axis (shapes (3,) or (..., 3), broadcast).

    The same numbers as ``np.cross`` (the three component formulas), without its checks and
    axis moves, which cost more than the product itself for the panel method's (3,) vectors.
    """
    if a.ndim == 1 and b.ndim == 1:
        a0, a1, a2 = (float(v) for v in a)
        b0, b1, b2 = (float(v) for v in b)
        return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


#: Below this sin(delta) [-] (within 0.06 deg of normal incidence) :func:`sine_of_incidence`
#: takes |u x n| instead of sqrt(1 - c^2).
NEAR_NORMAL_SINE = 1e-3


def sine_of_incidence(u, normals, c) -> np.ndarray:
    """sin(delta) of every panel, given c = cos(delta) = -u . n.

    sqrt(1 - c^2), except within NEAR_NORMAL_SINE of normal incidence, where 1 - c^2 cancels (c
    rounds to +-1 below delta ~ 1.5e-8 rad, and a panel's shear, along (u + c n) / sin(delta),
    would be lost with its sine) and |u x n| is taken instead, which has no cancellation.

    Parameters
    ----------
    u : ndarray, shape (3,) or (M, 3)
        Unit flow direction(s).
    normals : ndarray, shape (N, 3)
        Unit panel normals (either orientation).
    c : ndarray, shape (N,) or (M, N)
        cos(delta) of every panel for every direction, within [-1, 1].

    Returns
    -------
    ndarray, shape of ``c``
    """
    sigma = np.sqrt(1.0 - c * c)
    near = sigma < NEAR_NORMAL_SINE
    if near.any():
        if c.ndim == 1:
            u_x_n = cross(u, normals[near])
        else:
            rows, panels = np.nonzero(near)
            u_x_n = cross(u[rows], normals[panels])
        sigma[near] = np.sqrt((u_x_n * u_x_n).sum(axis=-1))
    return sigma
