"""Maxwell's model (one-sided and ADBSat's two-sided plate) and the per-species models (dria,
cll) at panel level against closed forms and their mixing rules."""

import math

import numpy as np
import pytest
from model_references import (
    DELTAS_DEG,
    FLOWS,
    FRONT_DELTAS_DEG,
    SQRT_PI,
    angles,
    assert_close,
    incident_fluxes,
    reemission_temperature_ratio,
    schaaf_plate,
    sentman_plate,
    surface,
)
from scipy.special import erf

from adbsat_ros import FreeStream, MaterialTable, SurfaceProperties
from adbsat_ros.physics.constants import BOLTZMANN, species_mass_kg
from adbsat_ros.physics.gsi_models import (
    ModelOptions,
    cll,
    dria,
    maxwell,
    schaaf,
    sentman,
)


# ------------------------------------------------------------------------------------ maxwell
@pytest.mark.parametrize("flow_name", list(FLOWS))
def test_maxwell_specular_has_no_shear(flow_name):
    """Maxwell with alpha = 0 (pure specular reflection, Maxwell 1879): the tangential momentum
    is returned unchanged so c_tau = 0, and the normal momentum is reversed: c_p = 2 p_i/q."""
    flow = FLOWS[flow_name]
    c, sg = angles(DELTAS_DEG)
    cp, ctau = maxwell(c, sg, surface(alpha=0.0), flow, ModelOptions())
    assert np.all(np.abs(ctau) <= 1e-15)
    _, p_i, _ = incident_fluxes(c, sg, flow.speed_ratio)
    assert_close(cp, 2.0 * p_i)


@pytest.mark.parametrize("alpha", [0.0, 0.35, 1.0])
def test_maxwell_one_sided_is_schaaf(alpha):
    """Maxwell diffuse fraction alpha on one side: p = p_i + (1 - alpha) p_i + alpha p_w =
    (2 - alpha) p_i + alpha p_w and tau = alpha tau_i, i.e. Schaaf & Chambre with
    sigma_n = sigma_t = alpha."""
    flow = FLOWS["slow"]
    Tw = 310.0
    c, sg = angles(DELTAS_DEG)
    cp, ctau = maxwell(c, sg, surface(alpha=alpha, wall_temperature=Tw), flow, ModelOptions())
    cp_ref, ctau_ref = schaaf_plate(c, sg, flow.speed_ratio, alpha, alpha, Tw / flow.temperature)
    assert_close(cp, cp_ref)
    assert_close(ctau, ctau_ref)


@pytest.mark.parametrize("flow_name", list(FLOWS))
@pytest.mark.parametrize("alpha", [0.0, 0.4, 1.0])
def test_maxwell_compat_two_sided_plate(flow_name, alpha):
    """ADBSat's maxwell (compat) is the thin plate exposed on both faces: front minus back
    pressure, front plus back shear, both faces Maxwell/Schaaf with sigma_n = sigma_t = alpha
    (Bird 1994 Ch. 7 plate; derived from the one-sided forms above with c -> -c for the back):
        c_p = p(c) - p(-c),  c_tau = tau(c) + tau(-c)  for delta <= 90 deg, zero behind.
    At grazing incidence (c = 0): c_tau = 2 alpha / (sqrt(pi) s), c_p = 0."""
    flow = FLOWS[flow_name]
    Tw = 300.0
    s = flow.speed_ratio
    c, sg = angles(DELTAS_DEG)
    cp, ctau = maxwell(
        c, sg, surface(alpha=alpha, wall_temperature=Tw), flow, ModelOptions(adbsat_compat=True)
    )
    pf, tf = schaaf_plate(c, sg, s, alpha, alpha, Tw / flow.temperature)
    pb, tb = schaaf_plate(-c, sg, s, alpha, alpha, Tw / flow.temperature)
    front = c >= 0
    assert_close(cp, np.where(front, pf - pb, 0.0), atol=1e-12)
    assert_close(ctau, np.where(front, tf + tb, 0.0), atol=1e-12)
    i90 = DELTAS_DEG.index(90.0)
    assert ctau[i90] == pytest.approx(2 * alpha / (SQRT_PI * s), rel=1e-12, abs=1e-15)
    assert cp[i90] == pytest.approx(0.0, abs=1e-15)


def test_maxwell_compat_diffuse_is_bird_plate():
    """alpha = 1: the two-sided diffuse plate of Sentman (1961)/Bird (1994, Ch. 7), with
    c = sin(plate angle of attack) and T_r = T_w:
        C_D = 2 e^{-s^2 c^2}/(sqrt(pi) s) + (c/s^2)(1 + 2 s^2) erf(s c)
              + (sqrt(pi)/s) c^2 sqrt(T_r/T_inf)
        C_L = (sin(delta)/s^2) erf(s c) + (sqrt(pi)/s) c sin(delta) sqrt(T_r/T_inf)
    with c_p = C_D c + C_L sin(delta), c_tau = C_D sin(delta) - C_L c."""
    flow = FLOWS["slow"]
    s, Tw = flow.speed_ratio, 250.0
    r = math.sqrt(Tw / flow.temperature)
    c, sg = angles(FRONT_DELTAS_DEG + [90.0])
    CD = (
        2 * np.exp(-((s * c) ** 2)) / (SQRT_PI * s)
        + (c / s**2) * (1 + 2 * s * s) * erf(s * c)
        + (SQRT_PI / s) * c * c * r
    )
    CL = (sg / s**2) * erf(s * c) + (SQRT_PI / s) * c * sg * r
    cp, ctau = maxwell(
        c, sg, surface(alpha=1.0, wall_temperature=Tw), flow, ModelOptions(adbsat_compat=True)
    )
    assert_close(cp, CD * c + CL * sg, atol=1e-12)
    assert_close(ctau, CD * sg - CL * c, atol=1e-12)


# --------------------------------------------------------------------------------- dria / cll
ATMOSPHERE_400KM = {
    "He": 2.5e12,
    "O": 3.5e14,
    "N2": 2.0e13,
    "O2": 6.0e11,
    "Ar": 1.0e10,
    "H": 1.5e11,
    "N": 4.0e12,
}


@pytest.mark.parametrize("species", ["O", "N2", "He"])
@pytest.mark.parametrize("alpha", [1.0, 0.75])
def test_dria_single_species_is_sentman(species, alpha):
    """DRIA for a one-species gas is Sentman's plate with that species' mass (s_j = s,
    T_i,j = T_i)."""
    flow = FreeStream(7600.0, 1000.0, number_densities={species: 1.0e14})
    surf = surface(alpha=alpha, wall_temperature=330.0)
    c, sg = angles(DELTAS_DEG)
    a = dria(c, sg, surf, flow, ModelOptions())
    b = sentman(c, sg, surf, flow, ModelOptions())
    assert_close(a[0], b[0], rtol=1e-13)
    assert_close(a[1], b[1], rtol=1e-13)
    # and against the independent reference with m_j
    m = species_mass_kg(species)
    s = flow.speed / math.sqrt(2 * BOLTZMANN * flow.temperature / m)
    ref = sentman_plate(c, sg, s, reemission_temperature_ratio(flow, m, alpha, 330.0))
    assert_close(a[0], ref[0])
    assert_close(a[1], ref[1])


def test_dria_mixture_is_mass_fraction_sum():
    """Force = sum_j q_j A C_j with q_j = rho_j V^2/2, so the mixture coefficient (per total q)
    is sum_j (rho_j/rho) C_j with C_j Sentman's plate for species j alone."""
    flow = FreeStream(7600.0, 1000.0, number_densities=ATMOSPHERE_400KM)
    alpha, Tw = 0.85, 300.0
    c, sg = angles(DELTAS_DEG)
    cp, ctau = dria(c, sg, surface(alpha=alpha, wall_temperature=Tw), flow, ModelOptions())
    rho = {k: n * species_mass_kg(k) for k, n in ATMOSPHERE_400KM.items()}
    rho_tot = sum(rho.values())
    cp_ref = 0.0
    ctau_ref = 0.0
    for k in ATMOSPHERE_400KM:
        m = species_mass_kg(k)
        s = flow.speed / math.sqrt(2 * BOLTZMANN * flow.temperature / m)
        p, t = sentman_plate(c, sg, s, reemission_temperature_ratio(flow, m, alpha, Tw))
        cp_ref = cp_ref + rho[k] / rho_tot * p
        ctau_ref = ctau_ref + rho[k] / rho_tot * t
    assert_close(cp, cp_ref)
    assert_close(ctau, ctau_ref)


def test_dria_compat_divides_by_given_density():
    """ADBSat's DRIA weights are massConc_j = rho_j / rho_total(NRLMSISE), not renormalised: a
    given total density 5 % above sum(rho_j) scales both coefficients by 1/1.05."""
    base = FreeStream(7600.0, 1000.0, number_densities=ATMOSPHERE_400KM)
    rho_sum = base.mass_density
    flow = FreeStream(7600.0, 1000.0, number_densities=ATMOSPHERE_400KM, density=1.05 * rho_sum)
    surf = surface(alpha=0.9)
    c, sg = angles(DELTAS_DEG)
    a = dria(c, sg, surf, flow, ModelOptions(adbsat_compat=True))
    b = dria(c, sg, surf, base, ModelOptions())
    assert_close(np.asarray(a[0]) * 1.05, b[0], rtol=1e-12)
    assert_close(np.asarray(a[1]) * 1.05, b[1], rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("sigma_t", [1.0, 0.6])
def test_cll_full_normal_accommodation_is_schaaf(sigma_t):
    """CLL with alpha_n = 1 falls back to Schaaf & Chambre with sigma_n = 1 (ADBSat's branch);
    for one species (O) this is schaaf with the O mass, c_tau = sigma_t tau_i."""
    flow = FreeStream(7600.0, 1000.0, number_densities={"O": 1.0e14})
    Tw = 300.0
    surf = surface(alpha_n=1.0, sigma_n=1.0, sigma_t=sigma_t, wall_temperature=Tw)
    c, sg = angles(DELTAS_DEG)
    cp, ctau = cll(c, sg, surf, flow, ModelOptions())
    ref = schaaf_plate(c, sg, flow.speed_ratio, 1.0, sigma_t, Tw / flow.temperature)
    assert_close(cp, ref[0])
    assert_close(ctau, ref[1])
    b = schaaf(c, sg, surf, flow, ModelOptions())
    assert_close(cp, b[0], rtol=1e-13)


def test_cll_mixture_weights():
    """alpha_n = 1, six CLL species (Ar excluded): default mixing by mass fraction renormalised
    over the six; ADBSat compat weights w_j proportional to M_j n_j^2 (physics.md Sec. 3)."""
    flow = FreeStream(7600.0, 1000.0, number_densities=ATMOSPHERE_400KM)
    Tw = 300.0
    surf = surface(alpha_n=1.0, sigma_t=1.0, wall_temperature=Tw)
    c, sg = angles(DELTAS_DEG)
    six = ["He", "O", "N2", "O2", "H", "N"]
    per = {}
    for k in six:
        m = species_mass_kg(k)
        s = flow.speed / math.sqrt(2 * BOLTZMANN * flow.temperature / m)
        per[k] = schaaf_plate(c, sg, s, 1.0, 1.0, Tw / flow.temperature)
    for compat, wfun in [
        (False, lambda k: ATMOSPHERE_400KM[k] * species_mass_kg(k)),
        (True, lambda k: ATMOSPHERE_400KM[k] ** 2 * species_mass_kg(k)),
    ]:
        w = {k: wfun(k) for k in six}
        W = sum(w.values())
        cp_ref = sum(w[k] / W * per[k][0] for k in six)
        ctau_ref = sum(w[k] / W * per[k][1] for k in six)
        cp, ctau = cll(c, sg, surf, flow, ModelOptions(adbsat_compat=compat))
        assert_close(cp, cp_ref)
        assert_close(ctau, ctau_ref)


def test_cll_partial_accommodation_as_coded():
    """alpha_n < 1, atomic oxygen only (Walker et al. 2014 fit beta, gamma, delta, zeta =
    5.85, 0.2, 0.48, 31, as coded in ADBSat, physics.md Sec. 3):
    c_p = (1/s^2)[(1 + sqrt(1 - a_n)) G1 + 1/2 e^{-beta (1-a_n)^gamma} (T_w/T)^delta (zeta/s)
          sqrt(T_w/T) sqrt(pi) G2],  c_tau = sigma_t sin(delta) G2 / s."""
    flow = FreeStream(7600.0, 1000.0, number_densities={"O": 1.0e14})
    an, st, Tw = 0.7, 0.8, 300.0
    s = flow.speed_ratio
    c, sg = angles(DELTAS_DEG)
    x = s * c
    E = np.exp(-x * x)
    Z = 1 + erf(x)
    G1 = (x * E + SQRT_PI / 2 * (1 + 2 * x * x) * Z) / SQRT_PI
    G2 = (E + SQRT_PI * x * Z) / SQRT_PI
    tr = Tw / flow.temperature
    cp_ref = (
        (1 + math.sqrt(1 - an)) * G1
        + 0.5
        * math.exp(-5.85 * (1 - an) ** 0.2)
        * tr**0.48
        * (31.0 / s)
        * math.sqrt(tr)
        * SQRT_PI
        * G2
    ) / s**2
    cp, ctau = cll(
        c, sg, surface(alpha_n=an, sigma_t=st, wall_temperature=Tw), flow, ModelOptions()
    )
    assert_close(cp, cp_ref)
    assert_close(ctau, st * sg * G2 / s)


def test_cll_compat_on_a_mesh_of_mixed_alpha_n_is_schaaf_with_sigma_n_alpha_n():
    """Two materials, alpha_n = 0.7 and 1, atomic oxygen only. By default the fit applies where
    alpha_n < 1 and Schaaf & Chambre (sigma_n = 1) where alpha_n = 1; with ADBSat's compat the fit
    applies only if every panel has alpha_n < 1, and otherwise every panel is Schaaf & Chambre
    with sigma_n = alpha_n of its own (physics.md Sec. 3.7)."""
    flow = FreeStream(7600.0, 1000.0, number_densities={"O": 1.0e14})
    Tw, st = 300.0, 0.8
    alpha_n = np.array([0.7, 1.0])
    mixed = MaterialTable(
        SurfaceProperties(alpha_n=1.0, sigma_t=st, wall_temperature=Tw),
        {"coated": {"alpha_n": 0.7}},
    ).expand(("coated", "bare"), np.array([0, 1]))
    c, sg = angles([30.0, 60.0])
    s, tr = flow.speed_ratio, Tw / flow.temperature
    compat = cll(c, sg, mixed, flow, ModelOptions(adbsat_compat=True))
    ref = schaaf_plate(c, sg, s, alpha_n, st, tr)
    assert_close(compat[0], ref[0])
    assert_close(compat[1], ref[1])
    default = cll(c, sg, mixed, flow, ModelOptions())
    fit = cll(
        c[:1], sg[:1], surface(alpha_n=0.7, sigma_t=st, wall_temperature=Tw), flow, ModelOptions()
    )
    assert_close(default[0][:1], fit[0])
    assert_close(default[0][1:], schaaf_plate(c[1:], sg[1:], s, 1.0, st, tr)[0])
    assert not np.allclose(default[0][0], compat[0][0])
