"""Models of a drifting Maxwellian gas with diffuse or partly accommodated re-emission: each a
*plate* (c_p and c_tau / sin(delta) in c); docs/physics.md, 3.2, 3.3, 3.8; results per q.
Sources: Sentman, LMSC-448514 (1961); Schaaf and Chambre, "Flow of Rarefied Gases" (1961); dria:
Walker, Mehta and Koller, JSR 51 (2014) 1544-1563; as in ADBSat (Sinpetru et al., CPC 275, 2022)."""

from __future__ import annotations

import math

import numpy as np

from adbsat_ros.physics.constants import BOLTZMANN
from adbsat_ros.physics.models.mixture import species_speed_ratio, species_weights
from adbsat_ros.physics.special import erfc

SQRT_PI = math.sqrt(math.pi)


def sentman_plate(c, s, K):
    """Sentman's plate: c_p, c_tau / sin(delta) of speed ratio ``s``; K = sqrt(T_r / T_inf) / s."""
    minus_x = c * -s
    Phi = erfc(minus_x)  # = 1 + erf(x), without cancellation for x << 0
    e = np.exp(-(minus_x * minus_x))
    c_phi = c * Phi
    shear = e * (1.0 / (SQRT_PI * s))
    shear += c_phi
    cp = c * shear
    Phi *= 0.5 / (s * s)
    cp += Phi
    c_phi *= (0.5 * SQRT_PI) * K
    cp += c_phi
    e *= 0.5 * K / s
    cp += e
    return cp, shear


def sentman_coefficients(c, sigma, s, K):
    """Sentman's plate for one gas: c_p and c_tau (:func:`sentman_plate`)."""
    cp, shear = sentman_plate(c, s, K)
    return cp, shear * sigma


def re_emission_k(alpha, wall_temperature, incident_temperature, particle_mass, speed):
    """K = sqrt(2 k_B T_r / (m V^2)), T_r = T_i + alpha (T_w - T_i) (docs/physics.md, 3.10)."""
    t_r = incident_temperature + alpha * (wall_temperature - incident_temperature)
    k_squared = 2.0 * BOLTZMANN * t_r / (particle_mass * speed * speed)
    # one value for all panels: math.sqrt (the same correctly rounded root) keeps K a Python float,
    # so the plate's scalar factors of K are float arithmetic, not numpy scalars'
    return (
        math.sqrt(k_squared)
        if type(k_squared) is float and k_squared >= 0.0
        else np.sqrt(k_squared)
    )


def sentman(c, sigma, surface, flow, options):
    """Sentman (1961) diffuse model with energy accommodation ``alpha``; back faces kept."""
    return sentman_coefficients(c, sigma, *sentman_parameters(surface, flow, options))


def sentman_parameters(surface, flow, options):
    """Sentman's (s, K) for :func:`sentman_plate`: K per panel if alpha or T_w is an array."""
    Ti = options.incident_temperature_of(flow.mean_mass, flow.speed)
    return flow.speed_ratio, re_emission_k(
        surface.alpha, surface.wall_temperature, Ti, flow.mean_mass, flow.speed
    )


def schaaf_plate(c, s, sigma_n, sigma_t, r):
    """Schaaf & Chambre plate for one gas: c_p and c_tau / sin(delta); r = sqrt(T_w / T_inf)."""
    x = s * c
    E = np.exp(-x * x)
    Phi = erfc(-x)  # = 1 + erf(x), without cancellation for x << 0
    cp = (
        ((2.0 - sigma_n) * x / SQRT_PI + 0.5 * sigma_n * r) * E
        + ((2.0 - sigma_n) * (0.5 + x * x) + 0.5 * sigma_n * r * SQRT_PI * x) * Phi
    ) / (s * s)
    shear = sigma_t / (s * SQRT_PI) * (E + SQRT_PI * x * Phi)
    return cp, shear


def schaaf_coefficients(c, sigma, s, sigma_n, sigma_t, r):
    """Schaaf & Chambre plate for one gas: c_p and c_tau (:func:`schaaf_plate`)."""
    cp, shear = schaaf_plate(c, s, sigma_n, sigma_t, r)
    return cp, shear * sigma


def schaaf(c, sigma, surface, flow, options):
    """Schaaf & Chambre (1961) with momentum accommodation sigma_n, sigma_t; back faces kept."""
    return schaaf_coefficients(c, sigma, *schaaf_parameters(surface, flow, options))


def schaaf_parameters(surface, flow, options):
    """Schaaf & Chambre's (s, sigma_n, sigma_t, r) for :func:`schaaf_plate`."""
    r = np.sqrt(surface.wall_temperature / flow.temperature)
    return flow.speed_ratio, surface.sigma_n, surface.sigma_t, r


def dria(c, sigma, surface, flow, options):
    """Diffuse reflection with incomplete accommodation: Sentman per species, mixed by mass
    fraction."""
    if not flow.has_species:
        raise ValueError("the dria model needs the gas composition (number_densities / --species)")
    names = [n for n in flow.species if flow.number_densities[n] > 0]
    weights = species_weights(flow, names, options, "dria")
    cp_total = 0.0
    ctau_total = 0.0
    for name, w in zip(names, weights):
        m = flow.species_masses[flow.species.index(name)]
        s = species_speed_ratio(flow, m)
        Ti = options.incident_temperature_of(m, flow.speed)
        K = re_emission_k(surface.alpha, surface.wall_temperature, Ti, m, flow.speed)
        cp, ctau = sentman_coefficients(c, sigma, s, K)
        cp_total = cp_total + w * cp
        ctau_total = ctau_total + w * ctau
    return cp_total, ctau_total
