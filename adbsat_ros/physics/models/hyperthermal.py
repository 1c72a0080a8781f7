"""Hyperthermal models (thermal speed neglected); back faces get no force; results per q
(docs/physics.md, 3.1, 3.5, 3.6). Sources: Anderson, "Hypersonic and High-Temperature Gas
Dynamics" (2006), ch. 3; G. E. Cook, Planet. Space Sci. 13 (1965) 929-946; J. A. Storch, The
Aerospace Corporation (2002); as in ADBSat (Sinpetru et al., CPC 275 (2022) 108326)."""

from __future__ import annotations

import math

import numpy as np


def zero_backward(c, cp, ctau, strict=True):
    """Zero both coefficients where the panel faces away from the flow (c < 0, or c <= 0)."""
    back = c < 0.0 if strict else c <= 0.0
    return np.where(back, 0.0, cp), np.where(back, 0.0, ctau)


def newton(c, sigma, surface, flow, options):
    """Newtonian impact: c_p = 2 c^2, c_tau = 0; zero on back faces (delta > 90 deg)."""
    cp = np.where(c > 0.0, 2.0 * c * c, 0.0)
    return cp, np.zeros_like(cp)


def cook(c, sigma, surface, flow, options):
    """Cook (1965) hyperthermal diffuse model (T_k = V^2 / (3 R)); zero for delta >= 90 deg."""
    Tk = flow.speed**2 / (3.0 * flow.specific_gas_constant)
    W = np.sqrt(1.0 + surface.alpha * (surface.wall_temperature / Tk - 1.0))
    cp = 2.0 * c * c + (4.0 / 3.0) * W * c
    ctau = 2.0 * c * sigma
    return zero_backward(c, cp, ctau, strict=False)


def storch(c, sigma, surface, flow, options):
    """Storch (2002) hyperthermal model; zero for delta > 90 deg."""
    Vw = np.sqrt(math.pi * flow.specific_gas_constant * surface.wall_temperature / 2.0)
    cp = 2.0 * c * (surface.sigma_n * Vw / flow.speed + (2.0 - surface.sigma_n) * c)
    ctau = 2.0 * surface.sigma_t * c * sigma
    return zero_backward(c, cp, ctau)
