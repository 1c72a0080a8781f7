"""Incidence of the flow on panels: sin(delta) without cancellation near normal incidence."""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry.frames import cross

#: Below this sin(delta) [-] (within 0.06 deg of normal incidence) :func:`sine_of_incidence`
#: takes |u x n| instead of sqrt(1 - c^2).
NEAR_NORMAL_SINE = 1e-3


def sine_of_incidence(u, normals, c) -> np.ndarray:
    """sin(delta) of unit directions ``u`` and unit ``normals``: |u x n| near normal incidence."""
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
