"""Cercignani-Lampis-Lord model per species (docs/physics.md, section 3.7); results per q.

Sources: R. G. Lord, Physics of Fluids A 3 (1991) 706-710; A. Walker, P. Mehta and J. Koller,
J. Spacecraft and Rockets 51 (2014) 1544-1563 (the fits); as in ADBSat (Sinpetru et al., 2022).
"""

from __future__ import annotations

import numpy as np

from adbsat_ros.physics.models.diffuse import SQRT_PI, schaaf_plate
from adbsat_ros.physics.models.mixture import species_speed_ratio, species_weights
from adbsat_ros.physics.special import erfc

# Walker et al. (2014) fit of the CLL re-emitted normal momentum: (beta, gamma, delta, zeta).
_CLL_FIT = {
    "O": (5.85, 0.2, 0.48, 31.0),
    "N2": (6.6, 0.22, 0.48, 35.0),
    "O2": (6.3, 0.26, 0.42, 20.5),
    "N": (4.9, 0.32, 0.42, 8.0),
}
# He and H depend on the alpha_n band: (0.95, 1], (0.9, 0.95], (0.5, 0.9], [0, 0.5].
_CLL_FIT_BANDED = {
    "He": (
        (6.2, 0.38, 3.3, 0.74),
        (3.8, 0.52, 3.4, 1.12),
        (3.45, 0.52, 2.4, 0.93),
        (0.08, 0.52, 4.2, 1.1),
    ),
    "H": (
        (3.9, 0.195, 1.4, 0.3),
        (3.5, 0.42, 2.0, 0.72),
        (3.45, 0.52, 2.4, 0.93),
        (0.095, 0.465, 2.9, 0.92),
    ),
}
#: Species that the CLL fits cover (Ar and anomalous O are not fitted and are left out).
CLL_SPECIES = ("He", "O", "N2", "O2", "H", "N")


def _cll_fit(name, alpha_n):
    """(beta, gamma, delta, zeta) for species ``name``; arrays if ``alpha_n`` is an array."""
    if name in _CLL_FIT:
        return _CLL_FIT[name]
    bands = np.asarray(_CLL_FIT_BANDED[name])
    an = np.asarray(alpha_n)
    idx = np.select([an > 0.95, an > 0.9, an > 0.5], [0, 1, 2], default=3)
    params = bands[idx]
    return tuple(params[..., k] if params.ndim > 1 else params[k] for k in range(4))


def cll(c, sigma, surface, flow, options):
    """Cercignani-Lampis-Lord per species (He, O, N2, O2, H, N) with Walker et al. (2014) fits.

    Panels with alpha_n = 1 use Schaaf & Chambre with sigma_n = 1 (``adbsat_compat``: section 3.7).
    """
    if not flow.has_species:
        raise ValueError("the cll model needs the gas composition (number_densities / --species)")
    names = [n for n in CLL_SPECIES if n in flow.species and flow.number_densities[n] > 0]
    if not names:
        raise ValueError(
            f"the cll model needs at least one of the species {', '.join(CLL_SPECIES)}"
        )
    weights = species_weights(flow, names, options, "cll")
    alpha_n = surface.alpha_n
    Tw, Tinf = surface.wall_temperature, flow.temperature
    ratio = Tw / Tinf
    r = np.sqrt(ratio)
    use_fit = np.asarray(alpha_n) < 1.0
    if options.adbsat_compat:
        use_fit = np.full_like(use_fit, bool(np.all(use_fit)))
    one_minus = np.maximum(1.0 - np.asarray(alpha_n, dtype=float), 0.0)
    cp_total = 0.0
    ctau_total = 0.0
    for name, w in zip(names, weights):
        s = species_speed_ratio(flow, flow.species_masses[flow.species.index(name)])
        x = s * c
        E = np.exp(-x * x)
        Phi = erfc(-x)  # = 1 + erf(x), without cancellation for x << 0
        G1 = (x * E + 0.5 * SQRT_PI * (1.0 + 2.0 * x * x) * Phi) / SQRT_PI
        G2 = (E + SQRT_PI * x * Phi) / SQRT_PI
        beta, gamma, delta, zeta = _cll_fit(name, alpha_n)
        cp_fit = (
            (1.0 + np.sqrt(one_minus)) * G1
            + 0.5 * np.exp(-beta * one_minus**gamma) * ratio**delta * (zeta / s) * r * SQRT_PI * G2
        ) / (s * s)
        # Schaaf & Chambre with sigma_n = alpha_n: 1 on the panels that take it by default; every
        # panel's own alpha_n under ADBSat's compat rule (its fallback when not all are < 1)
        cp_schaaf, _ = schaaf_plate(c, s, alpha_n, surface.sigma_t, r)
        cp = np.where(use_fit, cp_fit, cp_schaaf)
        ctau = surface.sigma_t * sigma * G2 / s
        cp_total = cp_total + w * cp
        ctau_total = ctau_total + w * ctau
    return cp_total, ctau_total
