"""Maxwell's model: a fraction alpha of the molecules re-emitted diffusely, the rest specularly.

Docs/physics.md, section 3.4 (ADBSat's two-sided plate, Bird 1994 ch. 7, with ``adbsat_compat``).
Sources: J. C. Maxwell, Phil. Trans. R. Soc. 170 (1879) 231-256; Sinpetru et al., CPC 275 (2022).
"""

from __future__ import annotations

import numpy as np

from adbsat_ros.physics.models.diffuse import SQRT_PI, schaaf_coefficients
from adbsat_ros.physics.models.hyperthermal import zero_backward
from adbsat_ros.physics.special import erf


def maxwell(c, sigma, surface, flow, options):
    """Maxwell: Schaaf & Chambre with sigma_n = sigma_t = alpha (``adbsat_compat``: ADBSat's)."""
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
    """Schaaf & Chambre's parameters with sigma_n = sigma_t = alpha (or None: ``adbsat_compat``)."""
    if options.adbsat_compat:
        return None
    r = np.sqrt(surface.wall_temperature / flow.temperature)
    return flow.speed_ratio, surface.alpha, surface.alpha, r
