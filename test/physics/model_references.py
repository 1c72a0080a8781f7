"""Closed-form references of the gas-surface model tests, written out independently of
adbsat_ros.physics.models (see test_models_diffuse.py for their derivation and sources)."""

import math

import numpy as np
from scipy.special import erf

from adbsat_ros import FreeStream, MaterialTable, SurfaceProperties
from adbsat_ros.physics.constants import BOLTZMANN

SQRT_PI = math.sqrt(math.pi)

DELTAS_DEG = [0.0, 10.0, 30.0, 45.0, 60.0, 80.0, 89.9, 90.0, 100.0, 135.0, 170.0, 180.0]
FRONT_DELTAS_DEG = [d for d in DELTAS_DEG if d < 90.0]

# Two free streams: orbital (s ~ 7.7) and a slow, hot one (s ~ 1.9) where thermal terms matter.
FLOWS = {
    "orbital": FreeStream(7500.0, 900.0, mean_mass_amu=16.0),
    "slow": FreeStream(1500.0, 1200.0, mean_mass_amu=28.0),
}


def surface(**kw):
    """Uniform per-panel surface parameters (scalars) for one material."""
    return MaterialTable(SurfaceProperties(**kw)).expand(("default",), np.array([0]))


def angles(deg_list):
    d = np.radians(np.asarray(deg_list, dtype=float))
    c = np.cos(d)
    sg = np.sin(d)
    # exact values at the special angles, as the panel method computes them (sigma = sqrt(1-c^2))
    sg = np.sqrt(np.clip(1.0 - c * c, 0.0, None))
    return c, sg


# ------------------------------------------------------------------------- reference formulas
def incident_fluxes(c, sg, s):
    """(N_i/(n v_th), p_i/q, tau_i/q): Schaaf & Chambre (1961) one-sided plate, incident part."""
    x = s * c
    E = np.exp(-x * x)
    Phi = 1.0 + erf(x)
    n_flux = (E + SQRT_PI * x * Phi) / (2.0 * SQRT_PI)
    p_i = (x * E / SQRT_PI + (0.5 + x * x) * Phi) / s**2
    tau_i = sg * (E + SQRT_PI * x * Phi) / (SQRT_PI * s)
    return n_flux, p_i, tau_i


def reemitted_pressure(c, s, T_over_Tinf):
    """p_w/q of diffuse (cosine-law) re-emission at temperature T (Schaaf & Chambre 1961)."""
    x = s * c
    return np.sqrt(T_over_Tinf) * (np.exp(-x * x) + SQRT_PI * x * (1.0 + erf(x))) / (2.0 * s**2)


def sentman_plate(c, sg, s, Tr_over_Tinf):
    """Sentman (1961) one-sided plate: incident momentum fully absorbed, diffuse re-emission at
    T_r (tangential momentum fully accommodated): c_p = p_i + p_r, c_tau = tau_i."""
    _, p_i, tau_i = incident_fluxes(c, sg, s)
    return p_i + reemitted_pressure(c, s, Tr_over_Tinf), tau_i


def schaaf_plate(c, sg, s, sigma_n, sigma_t, Tw_over_Tinf):
    """Schaaf & Chambre (1961): p = (2 - sigma_n) p_i + sigma_n p_w, tau = sigma_t tau_i."""
    _, p_i, tau_i = incident_fluxes(c, sg, s)
    return (2.0 - sigma_n) * p_i + sigma_n * reemitted_pressure(c, s, Tw_over_Tinf), sigma_t * tau_i


def reemission_temperature_ratio(flow, m, alpha, Tw, form="energy"):
    """T_r / T_inf with T_r = T_i + alpha (T_w - T_i) (Sentman 1961's energy accommodation);
    T_i = m V^2 / (4 k) (Koppenwallner, energy flux) or m V^2 / (3 k) (Moe, kinetic)."""
    Ti = m * flow.speed**2 / ((4.0 if form == "energy" else 3.0) * BOLTZMANN)
    return (Ti + alpha * (Tw - Ti)) / flow.temperature


def assert_close(actual, expected, rtol=1e-10, atol=1e-13):
    np.testing.assert_allclose(
        np.asarray(actual, float), np.asarray(expected, float), rtol=rtol, atol=atol
    )
