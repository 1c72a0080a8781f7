"""Hyperthermal models: the molecules' thermal speed neglected against the flow speed.

Back faces (delta > 90 deg) get no force. Inputs ``c = cos(delta)`` and ``sigma = sin(delta)``
of any shape; surface parameters floats or (N,) arrays; results normalised by q = rho V^2 / 2.

Sources:

* newton: Newtonian impact, every molecule giving up its normal momentum (e.g. Anderson,
  "Hypersonic and High-Temperature Gas Dynamics", 2006, ch. 3).
* cook: G. E. Cook, "Satellite drag coefficients", Planetary and Space Science 13 (1965),
  929-946: diffuse re-emission with energy accommodation alpha.
* storch: J. A. Storch, "Aerodynamic disturbances on spacecraft in free-molecular flow",
  The Aerospace Corporation (2002): normal and tangential momentum accommodation.

All three as in ADBSat (Sinpetru et al., "ADBSat: Methodology of a novel panel method tool for
aerodynamic analysis of satellites", Computer Physics Communications 275 (2022) 108326).
"""

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
    """Cook (1965) hyperthermal diffuse model; zero for delta >= 90 deg.

    c_p = 2 c^2 + (4/3) W c, c_tau = 2 c sin(delta), W = sqrt(1 + alpha (T_w / T_k - 1)),
    T_k = V^2 / (3 R) the kinetic temperature of the incident stream.
    """
    Tk = flow.speed**2 / (3.0 * flow.specific_gas_constant)
    W = np.sqrt(1.0 + surface.alpha * (surface.wall_temperature / Tk - 1.0))
    cp = 2.0 * c * c + (4.0 / 3.0) * W * c
    ctau = 2.0 * c * sigma
    return zero_backward(c, cp, ctau, strict=False)


def storch(c, sigma, surface, flow, options):
    """Storch (2002) hyperthermal model; zero for delta > 90 deg.

    c_p = 2 c (sigma_n V_w / V + (2 - sigma_n) c), c_tau = 2 sigma_t c sin(delta),
    V_w = sqrt(pi R T_w / 2) the mean normal speed of molecules re-emitted at T_w.
    """
    Vw = np.sqrt(math.pi * flow.specific_gas_constant * surface.wall_temperature / 2.0)
    cp = 2.0 * c * (surface.sigma_n * Vw / flow.speed + (2.0 - surface.sigma_n) * c)
    ctau = 2.0 * surface.sigma_t * c * sigma
    return zero_backward(c, cp, ctau)
