"""Incidence of the flow on panels: sin(delta) without cancellation near normal incidence."""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry.frames import cross

#: Below this sin(delta) [-] (within 0.06 deg of normal incidence) :func:`sine_of_incidence`
#: takes |u x n| instead of sqrt(1 - c^2).
NEAR_NORMAL_SINE = 1e-3


def sine_of_incidence(u, normals, c) -> np.ndarray:
    """sin(delta) of every panel, given c = cos(delta) = -u . n.

    sqrt(1 - c^2), except within NEAR_NORMAL_SINE of normal incidence, where 1 - c^2 cancels and
    |u x n| is taken instead (the shear's direction divides by sin(delta)).

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
