"""Gas-surface interaction models: local pressure and shear coefficients of a flat panel.

Every model maps the panel incidence to a pressure coefficient c_p (positive = compressive, along
-n) and a shear coefficient c_tau (along the tangential part of the flow), both normalised by the
free-stream dynamic pressure q = 0.5 rho V^2. The force on panel i is q A_i (c_tau t - c_p n).

Inputs are ``c = cos(delta)`` and ``sigma = sin(delta)``, where delta is the angle between the
inward normal -n and the flow direction (delta = 0: facing the flow; delta > 90 deg: facing away).
They may have any shape (e.g. (N,) panels or (M, N) attitudes x panels); surface parameters are
floats or (N,) arrays and broadcast against them.

Sources (formulas as written in docs/physics, from ADBSat's model set):

* newton: Newtonian impact, c_p = 2 cos^2 delta.
* sentman: Sentman (1961), diffuse re-emission at T_r = T_i + alpha (T_w - T_i), with
  Koppenwallner's incident temperature; Schamberg form.
* schaaf: Schaaf & Chambre (1961), normal/tangential momentum accommodation sigma_n, sigma_t.
* cook: Cook (1965), hyperthermal diffuse model with the kinetic temperature V^2 / (3 R).
* storch: Storch (2002), hyperthermal limit with sigma_n, sigma_t.
* maxwell: Maxwell specular/diffuse mixture (diffuse fraction alpha).
* cll: Cercignani-Lampis-Lord per species with the Walker et al. (2014) fits.
* dria: diffuse reflection with incomplete accommodation, per species (Sentman per species).

The temperature of the incident molecules T_i in sentman and dria (Sentman's energy accommodation)
is Koppenwallner's energy-flux form m V^2 / (4 k_B) by default (ADBSat's choice), or Moe's kinetic
form m V^2 / (3 k_B) with ``ModelOptions(incident_temperature="kinetic")``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import erf, erfc

from adbsat_ros.physics.constants import BOLTZMANN
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.surface import PanelSurface

SQRT_PI = math.sqrt(math.pi)

#: Valid values of :attr:`ModelOptions.incident_temperature`.
INCIDENT_TEMPERATURE_FORMS = ("energy", "kinetic")


@dataclass(frozen=True)
class ModelOptions:
    """Choices that change how models are evaluated (not per-material properties).

    Parameters
    ----------
    incident_temperature : {"energy", "kinetic"}
        Incident temperature used by sentman and dria for the re-emission temperature:
        "energy" is T_i = m V^2 / (4 k_B) (Koppenwallner, ADBSat's code), "kinetic" is
        T_i = m V^2 / (3 k_B) (Moe). They agree when alpha = 1.
    adbsat_compat : bool
        Reproduce ADBSat's coded behaviour where it differs from the physics: maxwell uses the
        two-sided flat-plate formula (zeroed for back faces) instead of a one-sided surface; cll
        weights species by M_j n_j^2 instead of mass fraction and uses its fit only if every
        panel has alpha_n < 1; dria divides by the given total density instead of normalising
        the mass fractions.
    """

    incident_temperature: str = "energy"
    adbsat_compat: bool = False

    def __post_init__(self):
        if self.incident_temperature not in INCIDENT_TEMPERATURE_FORMS:
            raise ValueError(
                f"incident_temperature must be one of {', '.join(INCIDENT_TEMPERATURE_FORMS)}, "
                f"got {self.incident_temperature!r}"
            )

    def incident_temperature_of(self, particle_mass, speed):
        """Incident temperature T_i [K] of particles of mass [kg] at speed [m/s]."""
        divisor = 4.0 if self.incident_temperature == "energy" else 3.0
        return particle_mass * speed**2 / (divisor * BOLTZMANN)


def _zero_backward(c, cp, ctau, strict=True):
    """Zero both coefficients where the panel faces away from the flow (c < 0, or c <= 0)."""
    back = c < 0.0 if strict else c <= 0.0
    return np.where(back, 0.0, cp), np.where(back, 0.0, ctau)


# ------------------------------------------------------------------------------------- models
def newton(c, sigma, surface: PanelSurface, flow: FreeStream, options: ModelOptions):
    """Newtonian impact: c_p = 2 c^2, c_tau = 0; zero on back faces (delta > 90 deg)."""
    cp = np.where(c > 0.0, 2.0 * c * c, 0.0)
    return cp, np.zeros_like(cp)


def _sentman_plate(c, s, K):
    """Sentman's plate for one gas: c_p and c_tau / sin(delta) for speed ratio s and
    K = sqrt(T_r / T_inf) / s (floats, or arrays like ``c``), elementwise in ``c``.

    With Phi = 1 + erf(s c) and e = exp(-s^2 c^2):
    c_tau / sin(delta) = c Phi + e / (sqrt(pi) s),
    c_p = c (c_tau / sin(delta)) + Phi / (2 s^2) + (K sqrt(pi) / 2) c Phi + (K / (2 s)) e,
    15 array operations for float s and K.
    """
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


def _sentman_single(c, sigma, s, K):
    """Sentman's plate for one gas: c_p and c_tau (:func:`_sentman_plate`)."""
    cp, shear = _sentman_plate(c, s, K)
    return cp, shear * sigma


def _re_emission_K(alpha, wall_temperature, incident_temperature, particle_mass, speed):
    """K = sqrt(T_r / T_inf) / s = sqrt(2 k_B T_r / (m V^2)), T_r = T_i + alpha (T_w - T_i).

    Diffusely re-emitted molecules at T_r carry the normal momentum flux N m sqrt(pi k_B T_r/(2m))
    (Schaaf & Chambre 1961), which is (K/2)(sqrt(pi) c Phi + E/s) in units of q. With the
    energy-flux T_i = m V^2/(4 k_B) this is ADBSat's sqrt(0.5 [1 + alpha (T_w/T_i - 1)]).
    """
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
    """Sentman (1961) diffuse model with energy accommodation ``alpha``; back faces kept.

    c_p = (c^2 + 1/(2 s^2)) (1 + erf(s c)) + c e^{-s^2 c^2} / (sqrt(pi) s)
          + (K/2) (sqrt(pi) c (1 + erf(s c)) + e^{-s^2 c^2} / s),
    c_tau = sin(delta) (c (1 + erf(s c)) + e^{-s^2 c^2} / (sqrt(pi) s)),
    K = sqrt(T_r / T_inf) / s with T_r = T_i + alpha (T_w - T_i) (for the energy-flux T_i this is
    ADBSat's sqrt(0.5 [1 + alpha (T_w / T_i - 1)])).
    """
    return _sentman_single(c, sigma, *sentman_parameters(surface, flow, options))


def sentman_parameters(surface, flow, options):
    """Sentman's (s, K) for :func:`_sentman_plate`: K per panel if alpha or T_w is an array."""
    Ti = options.incident_temperature_of(flow.mean_mass, flow.speed)
    return flow.speed_ratio, _re_emission_K(
        surface.alpha, surface.wall_temperature, Ti, flow.mean_mass, flow.speed
    )


def _schaaf_plate(c, s, sigma_n, sigma_t, r):
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


def _schaaf_single(c, sigma, s, sigma_n, sigma_t, r):
    """Schaaf & Chambre plate for one gas: c_p and c_tau (:func:`_schaaf_plate`)."""
    cp, shear = _schaaf_plate(c, s, sigma_n, sigma_t, r)
    return cp, shear * sigma


def schaaf(c, sigma, surface, flow, options):
    """Schaaf & Chambre (1961) with momentum accommodation sigma_n, sigma_t; back faces kept.

    c_p = (1/s^2) {[(2 - sigma_n) s c / sqrt(pi) + (sigma_n/2) r] e^{-s^2 c^2}
          + [(2 - sigma_n)(1/2 + s^2 c^2) + (sigma_n/2) r sqrt(pi) s c] (1 + erf(s c))},
    c_tau = sigma_t sin(delta) / (s sqrt(pi)) (e^{-s^2 c^2} + sqrt(pi) s c (1 + erf(s c))),
    r = sqrt(T_w / T_inf).
    """
    return _schaaf_single(c, sigma, *schaaf_parameters(surface, flow, options))


def schaaf_parameters(surface, flow, options):
    """Schaaf & Chambre's (s, sigma_n, sigma_t, r) for :func:`_schaaf_plate`."""
    r = np.sqrt(surface.wall_temperature / flow.temperature)
    return flow.speed_ratio, surface.sigma_n, surface.sigma_t, r


def cook(c, sigma, surface, flow, options):
    """Cook (1965) hyperthermal diffuse model; zero for delta >= 90 deg.

    c_p = 2 c^2 + (4/3) W c, c_tau = 2 c sin(delta), W = sqrt(1 + alpha (T_w / T_k - 1)),
    T_k = V^2 / (3 R) the kinetic temperature of the incident stream.
    """
    Tk = flow.speed**2 / (3.0 * flow.specific_gas_constant)
    W = np.sqrt(1.0 + surface.alpha * (surface.wall_temperature / Tk - 1.0))
    cp = 2.0 * c * c + (4.0 / 3.0) * W * c
    ctau = 2.0 * c * sigma
    return _zero_backward(c, cp, ctau, strict=False)


def storch(c, sigma, surface, flow, options):
    """Storch (2002) hyperthermal model; zero for delta > 90 deg.

    c_p = 2 c (sigma_n V_w / V + (2 - sigma_n) c), c_tau = 2 sigma_t c sin(delta),
    V_w = sqrt(pi R T_w / 2) the mean normal speed of molecules re-emitted at T_w.
    """
    Vw = np.sqrt(math.pi * flow.specific_gas_constant * surface.wall_temperature / 2.0)
    cp = 2.0 * c * (surface.sigma_n * Vw / flow.speed + (2.0 - surface.sigma_n) * c)
    ctau = 2.0 * surface.sigma_t * c * sigma
    return _zero_backward(c, cp, ctau)


def maxwell(c, sigma, surface, flow, options):
    """Maxwell model: a fraction alpha of molecules re-emitted diffusely at T_w, the rest specular.

    By default each panel is one side of a closed surface, which is exactly Schaaf & Chambre with
    sigma_n = sigma_t = alpha (specular reflection returns the incident normal momentum, diffuse
    re-emission none of the tangential), back faces kept. With ``adbsat_compat`` ADBSat's formula
    is used instead: the two-sided flat plate (both faces exposed), zeroed for back faces, which
    doubles the grazing shear (c_tau = 2 alpha / (sqrt(pi) s) at delta = 90 deg).
    """
    if not options.adbsat_compat:
        return _schaaf_single(c, sigma, *maxwell_parameters(surface, flow, options))
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
    return _zero_backward(c, cp, ctau)


def maxwell_parameters(surface, flow, options):
    """:func:`schaaf_parameters` with sigma_n = sigma_t = alpha, or None with ``adbsat_compat``
    (ADBSat's two-sided plate is not of that form)."""
    if options.adbsat_compat:
        return None
    r = np.sqrt(surface.wall_temperature / flow.temperature)
    return flow.speed_ratio, surface.alpha, surface.alpha, r


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


def _species_weights(flow: FreeStream, names, options: ModelOptions, adbsat_rule: str):
    """Mass fractions of ``names`` (renormalised over them), or ADBSat's weights in compat."""
    idx = [flow.species.index(n) for n in names]
    n = flow.species_number_densities[idx]
    m = flow.species_masses[idx]
    if options.adbsat_compat and adbsat_rule == "cll":
        w = m * n * n  # chi_j mu_j with chi = n_j / sum(n), mu = M_j n_j / N_A
        return w / w.sum()
    if options.adbsat_compat and adbsat_rule == "dria" and flow.density is not None:
        return n * m / flow.density  # not renormalised
    return n * m / np.dot(n, m)


def cll(c, sigma, surface, flow, options):
    """Cercignani-Lampis-Lord per species (He, O, N2, O2, H, N) with Walker et al. (2014) fits.

    For panels with alpha_n < 1, per species j (s_j its speed ratio, x = s_j c):
    c_p,j = (1/s_j^2) [(1 + sqrt(1 - alpha_n)) G1 + 1/2 exp(-beta_j (1 - alpha_n)^gamma_j)
            (T_w/T_inf)^delta_j (zeta_j / s_j) sqrt(T_w/T_inf) sqrt(pi) G2],
    c_tau,j = sigma_t sin(delta) G2 / s_j,
    G1 = [x e^{-x^2} + (sqrt(pi)/2)(1 + 2x^2)(1 + erf x)] / sqrt(pi),
    G2 = [e^{-x^2} + sqrt(pi) x (1 + erf x)] / sqrt(pi);
    panels with alpha_n = 1 use Schaaf & Chambre with sigma_n = 1. Species are mixed by mass
    fraction (the force is sum_j q_j C_j with q_j = rho_j V^2 / 2). Back faces are kept.
    """
    if not flow.has_species:
        raise ValueError("the cll model needs the gas composition (number_densities / --species)")
    names = [n for n in CLL_SPECIES if n in flow.species and flow.number_densities[n] > 0]
    if not names:
        raise ValueError(
            f"the cll model needs at least one of the species {', '.join(CLL_SPECIES)}"
        )
    weights = _species_weights(flow, names, options, "cll")
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
        s = flow.speed / math.sqrt(
            2.0 * BOLTZMANN * Tinf / flow.species_masses[flow.species.index(name)]
        )
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
        cp_schaaf, _ = _schaaf_plate(c, s, 1.0, surface.sigma_t, r)
        cp = np.where(use_fit, cp_fit, cp_schaaf)
        ctau = surface.sigma_t * sigma * G2 / s
        cp_total = cp_total + w * cp
        ctau_total = ctau_total + w * ctau
    return cp_total, ctau_total


def dria(c, sigma, surface, flow, options):
    """Diffuse reflection with incomplete accommodation: Sentman's plate per species, mixed.

    Per species j: c_d,j = P/sqrt(pi) + c Q Z + (c/2) K_j (c sqrt(pi) Z + P),
    c_l,j = sin(delta) G Z + (sin(delta)/2) K_j (c sqrt(pi) Z + P), with P = e^{-c^2 s_j^2}/s_j,
    G = 1/(2 s_j^2), Q = 1 + G, Z = 1 + erf(c s_j), K_j = sqrt(2 k_B T_r,j / (m_j V^2));
    c_p = c_d c + c_l sin(delta), c_tau = c_d sin(delta) - c_l c, which is Sentman's plate for
    species j. Species are mixed by mass fraction. Back faces are kept.
    """
    if not flow.has_species:
        raise ValueError("the dria model needs the gas composition (number_densities / --species)")
    names = [n for n in flow.species if flow.number_densities[n] > 0]
    weights = _species_weights(flow, names, options, "dria")
    cp_total = 0.0
    ctau_total = 0.0
    for name, w in zip(names, weights):
        m = flow.species_masses[flow.species.index(name)]
        s = flow.speed / math.sqrt(2.0 * BOLTZMANN * flow.temperature / m)
        Ti = options.incident_temperature_of(m, flow.speed)
        K = _re_emission_K(surface.alpha, surface.wall_temperature, Ti, m, flow.speed)
        cp, ctau = _sentman_single(c, sigma, s, K)
        cp_total = cp_total + w * cp
        ctau_total = ctau_total + w * ctau
    return cp_total, ctau_total


#: Model name -> function(c, sigma, surface, flow, options) -> (c_p, c_tau).
MODELS = {
    "newton": newton,
    "sentman": sentman,
    "cook": cook,
    "schaaf": schaaf,
    "cll": cll,
    "storch": storch,
    "dria": dria,
    "maxwell": maxwell,
}

#: Models whose (c_p, c_tau) are an elementwise function of c = cos(delta) and a few parameters of
#: the surface and the flow, with c_tau proportional to sin(delta):
#: name -> (parameters(surface, flow, options), plate(c, *parameters) -> (c_p, c_tau / sin(delta))).
#: The model itself is ``c_p, q = plate(c, *parameters(...)); c_tau = q sin(delta)``, so a caller
#: that evaluates several flows at once (parameters of each stacked along a leading axis, then one
#: ``plate`` call) gets every element bit for bit as the model's own call would
#: (PanelMethod.coefficients_many), and one that needs only c_tau / sin(delta) (the panel force
#: along u + c n) need not form sin(delta) at all. A ``parameters`` that returns None means the
#: split does not apply to these options.
SPLIT_MODELS = {
    "sentman": (sentman_parameters, _sentman_plate),
    "schaaf": (schaaf_parameters, _schaaf_plate),
    "maxwell": (maxwell_parameters, _schaaf_plate),
}

#: Which surface parameters each model reads (for documentation and parameter checks).
MODEL_PARAMETERS = {
    "newton": (),
    "sentman": ("alpha", "wall_temperature"),
    "cook": ("alpha", "wall_temperature"),
    "schaaf": ("sigma_n", "sigma_t", "wall_temperature"),
    "cll": ("alpha_n", "sigma_t", "wall_temperature"),
    "storch": ("sigma_n", "sigma_t", "wall_temperature"),
    "dria": ("alpha", "wall_temperature"),
    "maxwell": ("alpha", "wall_temperature"),
}

#: Models that need the species composition of the gas.
SPECIES_MODELS = ("cll", "dria")


def get_model(name: str):
    """The model function called ``name`` (case-insensitive; ``storchHyp`` = ``storch``).

    Raises
    ------
    ValueError
        For an unknown name, listing the known ones.
    """
    key = str(name).lower()
    if key == "storchhyp":
        key = "storch"
    if key == "schaaf_chambre":
        key = "schaaf"
    try:
        return MODELS[key]
    except KeyError:
        raise ValueError(
            f"unknown gas-surface model {name!r}; choose from {', '.join(MODELS)}"
        ) from None


def canonical_model_name(name: str) -> str:
    """The registry key for ``name`` (validates it)."""
    fn = get_model(name)
    return next(k for k, v in MODELS.items() if v is fn)
