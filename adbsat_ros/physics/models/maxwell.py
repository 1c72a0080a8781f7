"""Maxwell's model: a fraction alpha of the molecules re-emitted diffusely, the rest specularly.

Inputs and units as in :mod:`adbsat_ros.physics.models.diffuse`; ADBSat's two-sided plate
(Bird, "Molecular Gas Dynamics and the Direct Simulation of Gas Flows", Oxford 1994, ch. 7)
with ``ModelOptions(adbsat_compat=True)``.

Sources: J. C. Maxwell, "On stresses in rarified gases arising from inequalities of
temperature", Philosophical Transactions of the Royal Society 170 (1879) 231-256; Sinpetru et
al., Computer Physics Communications 275 (2022) 108326 (ADBSat).
"""

from __future__ import annotations

import numpy as np
from scipy.special import erf

from adbsat_ros.physics.models.diffuse import SQRT_PI, schaaf_coefficients
from adbsat_ros.physics.models.hyperthermal import zero_backward


def maxwell(c, sigma, surface, flow, options):
    """Maxwell model: a fraction alpha of molecules re-emitted diffusely at T_w, the rest specular.

    By default each panel is one side of a closed surface, which is exactly Schaaf & Chambre with
    sigma_n = sigma_t = alpha (specular reflection returns the incident normal momentum, diffuse
    re-emission none of the tangential), back faces kept. With ``adbsat_compat`` ADBSat's formula
    is used instead: the two-sided flat plate (both faces exposed), zeroed for back faces, which
    doubles the grazing shear (c_tau = 2 alpha / (sqrt(pi) s) at delta = 90 deg).
    """
    if not options.adbsat_compat:
        return schaaf_coefficients(c, sigma, *maxwell_parameters(surface, flow, options))
    alpha = surface.alpha
    r = np.sqrt(surface.wall_temperature / flow.temperature)
    s = flow.speed_ratio
    f = 1.0 - alpha
    cos2theta = 1.0 - 2.0 * c * c  # theta = 90 deg - delta
    x = s * c
    E = np.exp(-x * x)
    erfx = erf(x)
    cd = (
        2.0 * (1.0 - f * cos2theta) * E / (SQRT_PI * s)
        + (c / (s * s)) * (1.0 + 2.0 * s * s + f * (1.0 - 2.0 * s * s * cos2theta)) * erfx
        + alpha * (SQRT_PI / s) * c * c * r
    )
    cl = (
        (4.0 * f / (SQRT_PI * s)) * c * sigma * E
        + (sigma / (s * s)) * (1.0 + f * (1.0 + 4.0 * x * x)) * erfx
        + alpha * (SQRT_PI / s) * c * sigma * r
    )
    cp = cd * c + cl * sigma
    ctau = cd * sigma - cl * c
    return zero_backward(c, cp, ctau)


def maxwell_parameters(surface, flow, options):
    """:func:`~adbsat_ros.physics.models.diffuse.schaaf_parameters` with sigma_n = sigma_t = alpha.

    None with ``adbsat_compat`` (ADBSat's two-sided plate is not of that form).
    """
    if options.adbsat_compat:
        return None
    r = np.sqrt(surface.wall_temperature / flow.temperature)
    return flow.speed_ratio, surface.alpha, surface.alpha, r
