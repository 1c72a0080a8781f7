"""How the per-species models (cll, dria) weight the species of the gas: by mass fraction
(docs/physics.md, section 3.9; ``adbsat_compat``: ADBSat's rules)."""

from __future__ import annotations

import math

import numpy as np

from adbsat_ros.physics.constants import BOLTZMANN
from adbsat_ros.physics.freestream import FreeStream


def species_weights(flow: FreeStream, names, options, adbsat_rule: str) -> np.ndarray:
    """Weights of the species ``names`` of ``flow``: mass fractions, or ADBSat's rule."""
    idx = [flow.species.index(n) for n in names]
    n = flow.species_number_densities[idx]
    m = flow.species_masses[idx]
    if options.adbsat_compat and adbsat_rule == "cll":
        w = m * n * n  # chi_j mu_j with chi = n_j / sum(n), mu = M_j n_j / N_A
        return w / w.sum()
    if options.adbsat_compat and adbsat_rule == "dria" and flow.density is not None:
        return n * m / flow.density  # not renormalised
    return n * m / np.dot(n, m)


def species_speed_ratio(flow: FreeStream, mass: float) -> float:
    """Speed ratio s_j = V / sqrt(2 k_B T_inf / m_j) of particles of mass [kg] in ``flow``."""
    return flow.speed / math.sqrt(2.0 * BOLTZMANN * flow.temperature / mass)
