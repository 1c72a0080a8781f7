"""Panel-level checks of the gas-surface interaction models against closed forms.

Every reference below is written out here, independently of adbsat_ros.physics.gsi_models, from the
free-molecular flux integrals of a drifting Maxwellian gas on one side of a flat plate:

    x = s c (normal speed ratio), E = exp(-x^2), Phi = 1 + erf(x), s = V / sqrt(2 k T_inf / m)

    incident number flux      N_i / (n v_th)  = (E + sqrt(pi) x Phi) / (2 sqrt(pi))
    incident normal momentum  p_i / q         = (1/s^2) [x E / sqrt(pi) + (1/2 + x^2) Phi]
    incident tangential mom.  tau_i / q       = sin(delta) (E + sqrt(pi) x Phi) / (sqrt(pi) s)
    diffuse re-emission at T  p_w / q         = sqrt(T / T_inf) (E + sqrt(pi) x Phi) / (2 s^2)

(Schaaf & Chambre 1961, "Flow of Rarefied Gases", free-molecule plate p and tau; Bird 1994,
"Molecular Gas Dynamics and the DSMC of Gas Flows", Ch. 7 (collisionless flows); the re-emitted pressure is
N_i m sqrt(pi k T / (2 m)), the mean normal momentum of a half-range Maxwellian at T.)
q = rho V^2 / 2.  These closed forms are themselves checked against direct quadrature of the
Maxwellian below (test_flux_closed_forms_match_quadrature).
"""

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import erf

from adbsat_ros import FreeStream, MaterialTable, SurfaceProperties
from adbsat_ros.physics.constants import AMU, BOLTZMANN, species_mass_kg
from adbsat_ros.physics.gsi_models import (
    ModelOptions,
    cll,
    cook,
    dria,
    maxwell,
    newton,
    schaaf,
    sentman,
    storch,
)

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


# ------------------------------------------------------------------------- the flux integrals
@pytest.mark.parametrize("s", [0.3, 1.7, 7.0])
@pytest.mark.parametrize("delta_deg", [0.0, 30.0, 75.0, 90.0, 120.0, 180.0])
def test_flux_closed_forms_match_quadrature(s, delta_deg):
    """The erf closed forms above = direct integrals over the drifting Maxwellian.

    In units of v_th the inward normal velocity w has density exp(-(w - s c)^2)/sqrt(pi) and the
    tangential mean is s sin(delta), so N/(n v_th) = int_0^inf w f dw, p/(n m v_th^2) =
    int w^2 f dw, tau/(n m v_th^2) = s sin(delta) int w f dw, and q = n m v_th^2 s^2 / 2.
    Re-emission at T: p_w = N m sqrt(pi k T/(2m)) -> p_w/q = sqrt(pi T/T_inf) int w f dw / s^2.
    """
    c, sg = angles([delta_deg])
    x = s * c[0]
    f = lambda w: math.exp(-((w - x) ** 2)) / SQRT_PI  # noqa: E731
    I1 = quad(lambda w: w * f(w), 0.0, np.inf, epsabs=1e-14, epsrel=1e-13)[0]
    I2 = quad(lambda w: w * w * f(w), 0.0, np.inf, epsabs=1e-14, epsrel=1e-13)[0]
    n_flux, p_i, tau_i = incident_fluxes(c, sg, s)
    assert_close(n_flux, [I1], rtol=1e-9, atol=1e-14)
    assert_close(p_i, [2.0 * I2 / s**2], rtol=1e-9, atol=1e-14)
    assert_close(tau_i, [2.0 * s * sg[0] * I1 / s**2], rtol=1e-9, atol=1e-14)
    T_ratio = 0.37
    assert_close(
        reemitted_pressure(c, s, T_ratio),
        [math.sqrt(math.pi * T_ratio) * I1 / s**2],
        rtol=1e-9,
        atol=1e-14,
    )


# ------------------------------------------------------------------------------------- newton
def test_newton_plate():
    """Newtonian impact (Newton; e.g. Anderson 2006, Hypersonic and high-temperature gas
    dynamics, Ch. 3, Newtonian theory with C_p,max = 2): c_p = 2 cos^2 delta on faces seen by the flow, 0 behind;
    no shear."""
    c, sg = angles(DELTAS_DEG)
    cp, ctau = newton(c, sg, surface(), FLOWS["orbital"], ModelOptions())
    expected = np.where(
        np.radians(DELTAS_DEG) < math.pi / 2 - 1e-12, 2.0 * np.cos(np.radians(DELTAS_DEG)) ** 2, 0.0
    )
    assert_close(cp, expected, atol=1e-12)
    assert np.all(np.asarray(ctau) == 0.0)
    assert cp[0] == pytest.approx(2.0)


# ------------------------------------------------------------------------------------ sentman
@pytest.mark.parametrize("flow_name", list(FLOWS))
@pytest.mark.parametrize("alpha", [1.0, 0.8, 0.3, 0.0])
def test_sentman_plate(flow_name, alpha):
    """Sentman (1961) one-sided plate with T_r = T_i + alpha (T_w - T_i), T_i = m V^2/(4k)
    (Koppenwallner energy-flux form, ADBSat's default). All incidences, back faces included
    (a back face still feels the thermal flux of the gas)."""
    flow = FLOWS[flow_name]
    Tw = 350.0
    c, sg = angles(DELTAS_DEG)
    cp, ctau = sentman(c, sg, surface(alpha=alpha, wall_temperature=Tw), flow, ModelOptions())
    Tr = reemission_temperature_ratio(flow, flow.mean_mass, alpha, Tw, "energy")
    cp_ref, ctau_ref = sentman_plate(c, sg, flow.speed_ratio, Tr)
    assert_close(cp, cp_ref)
    assert_close(ctau, ctau_ref)
    # back faces are not zeroed: thermal pressure on a face turned away (visible at low s;
    # at s ~ 7.7 it is ~e^{-60} and lost to cancellation in 1 + erf(-x))
    if flow_name == "slow":
        assert cp[-1] > 1e-5


def test_sentman_schamberg_form_head_on():
    """Head-on (delta = 0) Sentman plate written out directly: c_p = (1 + 1/(2 s^2))(1 + erf s)
    + e^{-s^2}/(sqrt(pi) s) + sqrt(T_r/T_inf) (e^{-s^2} + sqrt(pi) s (1 + erf s)) / (2 s^2)
    (Sentman 1961; with T_r/T_inf = s^2/2 + alpha (T_w/T_inf - s^2/2))."""
    flow = FLOWS["slow"]
    s, Tinf, Tw, alpha = flow.speed_ratio, flow.temperature, 400.0, 0.6
    Tr = (s * s / 2.0) * Tinf + alpha * (Tw - (s * s / 2.0) * Tinf)  # m V^2/(4k) = s^2 T_inf / 2
    E = math.exp(-s * s)
    expected = (
        (1 + 0.5 / s**2) * (1 + math.erf(s))
        + E / (SQRT_PI * s)
        + math.sqrt(Tr / Tinf) * (E + SQRT_PI * s * (1 + math.erf(s))) / (2 * s * s)
    )
    cp, ctau = sentman(
        np.array([1.0]),
        np.array([0.0]),
        surface(alpha=alpha, wall_temperature=Tw),
        flow,
        ModelOptions(),
    )
    assert cp[0] == pytest.approx(expected, rel=1e-12)
    assert ctau[0] == 0.0


@pytest.mark.parametrize("alpha", [1.0, 0.5])
def test_sentman_hyperthermal_limit_cold_gas(alpha):
    """s -> infinity at fixed V, m, T_w (T_inf -> 0): E -> 0, Phi -> 2 (c > 0) or 0 (c < 0), so
    c_p -> 2 c^2 + sqrt(pi) c sqrt(T_r/T_inf)/s = 2 c^2 + c sqrt(2 pi k T_r / m) / V and
    c_tau -> 2 c sin(delta) on front faces, both -> 0 on back faces. With alpha = 1, T_r = T_w.
    (Limit of Sentman 1961 derived here; it is Storch's 2002 hyperthermal form with
    sigma_n = sigma_t = 1 and T_w replaced by T_r.)"""
    m = 16.0 * AMU
    V, Tw = 7500.0, 300.0
    flow = FreeStream(V, 0.05, mean_mass_amu=16.0)  # s ~ 1040
    assert flow.speed_ratio > 1000
    Ti = m * V**2 / (4 * BOLTZMANN)
    Tr = Ti + alpha * (Tw - Ti)
    deg = [0.0, 20.0, 45.0, 70.0, 85.0, 100.0, 150.0, 180.0]
    c, sg = angles(deg)
    cp, ctau = sentman(c, sg, surface(alpha=alpha, wall_temperature=Tw), flow, ModelOptions())
    front = c > 0
    cp_lim = np.where(front, 2 * c * c + c * np.sqrt(2 * math.pi * BOLTZMANN * Tr / m) / V, 0.0)
    ctau_lim = np.where(front, 2 * c * sg, 0.0)
    # corrections are O(1/s^2) ~ 1e-6
    assert_close(cp, cp_lim, rtol=1e-5, atol=1e-6)
    assert_close(ctau, ctau_lim, rtol=1e-5, atol=1e-6)


def test_sentman_hyperthermal_limit_fast_gas_is_newtonian_absorbing():
    """s -> infinity by V -> infinity with alpha = 1 and T_w fixed: the re-emission term
    c sqrt(2 pi k T_w/m)/V vanishes and the plate becomes a perfect absorber:
    c_p -> 2 c^2, c_tau -> 2 c sin(delta) (front), 0 behind. At V = 2e7 m/s the remaining
    re-emission term is below 5e-5 c and the O(1/s^2) terms below 1e-9."""
    m = 16.0 * AMU
    V, Tw = 2.0e7, 300.0
    flow = FreeStream(V, 300.0, mean_mass_amu=16.0)  # s ~ 3.5e4
    c, sg = angles([0.0, 30.0, 60.0, 80.0, 120.0])
    cp, ctau = sentman(c, sg, surface(alpha=1.0, wall_temperature=Tw), flow, ModelOptions())
    front = c > 0
    reemission = np.where(front, c * np.sqrt(2 * math.pi * BOLTZMANN * Tw / m) / V, 0.0)
    assert np.all(reemission <= 5e-5 * np.maximum(c, 0))
    assert_close(cp, np.where(front, 2 * c * c, 0.0) + reemission, rtol=1e-8, atol=1e-9)
    assert_close(cp, np.where(front, 2 * c * c, 0.0), rtol=1e-3, atol=1e-9)
    assert_close(ctau, np.where(front, 2 * c * sg, 0.0), rtol=1e-8, atol=1e-9)


# ------------------------------------------------------------------------------------- schaaf
@pytest.mark.parametrize("flow_name", list(FLOWS))
@pytest.mark.parametrize(
    "sigma_n,sigma_t", [(1.0, 1.0), (0.0, 0.0), (0.5, 0.6), (1.5, 0.9), (0.9, 0.0)]
)
def test_schaaf_plate(flow_name, sigma_n, sigma_t):
    """Schaaf & Chambre (1961) one-sided plate, p = (2 - sigma_n) p_i + sigma_n p_w(T_w),
    tau = sigma_t tau_i, all incidences."""
    flow = FLOWS[flow_name]
    Tw = 320.0
    c, sg = angles(DELTAS_DEG)
    cp, ctau = schaaf(
        c, sg, surface(sigma_n=sigma_n, sigma_t=sigma_t, wall_temperature=Tw), flow, ModelOptions()
    )
    cp_ref, ctau_ref = schaaf_plate(
        c, sg, flow.speed_ratio, sigma_n, sigma_t, Tw / flow.temperature
    )
    assert_close(cp, cp_ref)
    assert_close(ctau, ctau_ref)


@pytest.mark.parametrize("flow_name", list(FLOWS))
@pytest.mark.parametrize("form", ["energy", "kinetic"])
def test_sentman_alpha1_equals_schaaf_full_accommodation(flow_name, form):
    """alpha = 1 means T_r = T_w: Sentman's plate is then Schaaf & Chambre's with
    sigma_n = sigma_t = 1 (whatever T_i is, since T_i drops out of T_r)."""
    flow = FLOWS[flow_name]
    surf = surface(alpha=1.0, sigma_n=1.0, sigma_t=1.0, wall_temperature=280.0)
    c, sg = angles(DELTAS_DEG)
    a = sentman(c, sg, surf, flow, ModelOptions(incident_temperature="energy"))
    b = schaaf(c, sg, surf, flow, ModelOptions())
    assert_close(a[0], b[0], rtol=1e-13)
    assert_close(a[1], b[1], rtol=1e-13)


@pytest.mark.parametrize("sigma_n,sigma_t", [(1.0, 1.0), (0.7, 0.4), (1.3, 1.0)])
def test_schaaf_hyperthermal_limit_is_storch(sigma_n, sigma_t):
    """s -> infinity at fixed V, T_w (T_inf -> 0): Schaaf & Chambre's c_p -> 2(2 - sigma_n) c^2
    + sigma_n sqrt(pi) c sqrt(T_w/T_inf)/s = 2 c (sigma_n V_w/V + (2 - sigma_n) c) with
    V_w = sqrt(pi R T_w / 2), c_tau -> 2 sigma_t c sin(delta): Storch's (2002) hyperthermal model,
    which must then agree with the package's storch."""
    flow = FreeStream(7800.0, 0.05, mean_mass_amu=16.0)
    surf = surface(sigma_n=sigma_n, sigma_t=sigma_t, wall_temperature=300.0)
    c, sg = angles([0.0, 25.0, 50.0, 75.0, 88.0, 95.0, 140.0, 180.0])
    a = schaaf(c, sg, surf, flow, ModelOptions())
    b = storch(c, sg, surf, flow, ModelOptions())
    assert_close(a[0], b[0], rtol=2e-5, atol=1e-6)
    assert_close(a[1], b[1], rtol=2e-5, atol=1e-6)


# --------------------------------------------------------------------------------------- cook
@pytest.mark.parametrize("alpha", [1.0, 0.7, 0.0])
def test_cook_plate(alpha):
    """Cook (1965): plate drag/lift per unit area c_d = 2 c (1 + (2/3) c sqrt(T_r/T_k)),
    c_l = (4/3) c sin(delta) sqrt(T_r/T_k), T_k = m V^2 / (3 k), T_r = T_k + alpha (T_w - T_k);
    then c_p = c_d c + c_l sin(delta), c_tau = c_d sin(delta) - c_l c. Zero for delta >= 90 deg."""
    flow = FLOWS["orbital"]
    Tw = 300.0
    Tk = flow.mean_mass * flow.speed**2 / (3 * BOLTZMANN)
    W = math.sqrt((Tk + alpha * (Tw - Tk)) / Tk)
    c, sg = angles(DELTAS_DEG)
    cd = 2 * c * (1 + (2.0 / 3.0) * c * W)
    cl = (4.0 / 3.0) * c * sg * W
    front = c > 0
    cp_ref = np.where(front, cd * c + cl * sg, 0.0)
    ctau_ref = np.where(front, cd * sg - cl * c, 0.0)
    cp, ctau = cook(c, sg, surface(alpha=alpha, wall_temperature=Tw), flow, ModelOptions())
    assert_close(cp, cp_ref, atol=1e-12)
    assert_close(ctau, ctau_ref, atol=1e-12)
    # head-on, alpha = 0: T_r = T_k, W = 1 -> c_p = 2 + 4/3
    if alpha == 0.0:
        assert cp[0] == pytest.approx(2.0 + 4.0 / 3.0, rel=1e-12)


# ------------------------------------------------------------------------------------- storch
@pytest.mark.parametrize("sigma_n,sigma_t", [(1.0, 1.0), (0.0, 0.0), (0.8, 0.5), (1.6, 1.0)])
def test_storch_plate(sigma_n, sigma_t):
    """Storch (2002) hyperthermal plate: p = (2 - sigma_n) rho V^2 c^2 + sigma_n rho V c V_w with
    V_w = sqrt(pi R T_w / 2) (mean normal momentum per unit mass of cosine-law re-emission at T_w),
    tau = sigma_t rho V^2 c sin(delta); divided by q = rho V^2 / 2. Zero behind."""
    flow = FLOWS["orbital"]
    Tw = 300.0
    R = BOLTZMANN / flow.mean_mass
    Vw = math.sqrt(math.pi * R * Tw / 2)
    c, sg = angles(DELTAS_DEG)
    front = c >= 0
    cp_ref = np.where(front, 2 * (2 - sigma_n) * c * c + 2 * sigma_n * c * Vw / flow.speed, 0.0)
    ctau_ref = np.where(front, 2 * sigma_t * c * sg, 0.0)
    cp, ctau = storch(
        c, sg, surface(sigma_n=sigma_n, sigma_t=sigma_t, wall_temperature=Tw), flow, ModelOptions()
    )
    assert_close(cp, cp_ref, atol=1e-12)
    assert_close(ctau, ctau_ref, atol=1e-12)


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
        C_D = 2 e^{-s^2 c^2}/(sqrt(pi) s) + (c/s^2)(1 + 2 s^2) erf(s c) + (sqrt(pi)/s) c^2 sqrt(T_r/T_inf)
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
    """DRIA for a one-species gas is Sentman's plate with that species' mass (s_j = s, T_i,j = T_i)."""
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


# ------------------------------------------------------------------- incident temperature form
@pytest.mark.parametrize("flow_name", list(FLOWS))
@pytest.mark.parametrize("alpha", [0.0, 0.5, 0.9])
def test_energy_form_matches_reference(flow_name, alpha):
    """Energy-flux incident temperature T_i = m V^2/(4k) (Koppenwallner): reference Sentman
    plate with T_r = T_i + alpha (T_w - T_i)."""
    flow = FLOWS[flow_name]
    c, sg = angles(DELTAS_DEG)
    cp, _ = sentman(
        c,
        sg,
        surface(alpha=alpha, wall_temperature=300.0),
        flow,
        ModelOptions(incident_temperature="energy"),
    )
    ref = sentman_plate(
        c,
        sg,
        flow.speed_ratio,
        reemission_temperature_ratio(flow, flow.mean_mass, alpha, 300.0, "energy"),
    )
    assert_close(cp, ref[0])


@pytest.mark.parametrize("model", [sentman, dria])
@pytest.mark.parametrize("flow_name", list(FLOWS))
def test_energy_and_kinetic_agree_at_full_accommodation(model, flow_name):
    """alpha = 1 -> T_r = T_w whatever T_i is: both incident-temperature forms must give the
    same coefficients (physics.md; the package's own ModelOptions docstring says so too)."""
    base = FLOWS[flow_name]
    flow = FreeStream(base.speed, base.temperature, number_densities={"O": 1e14})
    surf = surface(alpha=1.0, wall_temperature=300.0)
    c, sg = angles(DELTAS_DEG)
    a = model(c, sg, surf, flow, ModelOptions(incident_temperature="energy"))
    b = model(c, sg, surf, flow, ModelOptions(incident_temperature="kinetic"))
    assert_close(a[0], b[0], rtol=1e-12)


@pytest.mark.parametrize("alpha", [0.0, 0.5, 0.9, 1.0])
def test_kinetic_form_matches_reference(alpha):
    """Kinetic incident temperature T_i = m V^2/(3k) (Moe): Sentman plate with
    T_r = T_i + alpha (T_w - T_i), p_r/q = sqrt(T_r/T_inf)(E + sqrt(pi) x Phi)/(2 s^2)."""
    flow = FLOWS["orbital"]
    c, sg = angles(DELTAS_DEG)
    cp, _ = sentman(
        c,
        sg,
        surface(alpha=alpha, wall_temperature=300.0),
        flow,
        ModelOptions(incident_temperature="kinetic"),
    )
    ref = sentman_plate(
        c,
        sg,
        flow.speed_ratio,
        reemission_temperature_ratio(flow, flow.mean_mass, alpha, 300.0, "kinetic"),
    )
    assert_close(cp, ref[0], rtol=1e-9)


@pytest.mark.parametrize("alpha", [0.0, 0.5, 0.9])
def test_kinetic_form_raises_pressure_when_alpha_below_one(alpha):
    """For alpha < 1, T_r,kin - T_r,energy = (1 - alpha) m V^2 (1/3 - 1/4)/k > 0, so the
    re-emitted pressure and c_p must be strictly larger with the kinetic form on every face
    that receives molecules."""
    flow = FLOWS["orbital"]
    c, sg = angles(DELTAS_DEG[:-1])
    surf = surface(alpha=alpha, wall_temperature=300.0)
    a, _ = sentman(c, sg, surf, flow, ModelOptions(incident_temperature="energy"))
    b, _ = sentman(c, sg, surf, flow, ModelOptions(incident_temperature="kinetic"))
    front = c > 0
    assert np.all(b[front] > a[front] * (1 + 1e-4))


@pytest.mark.parametrize("alpha", [0.5, 0.9])
def test_energy_and_kinetic_differ_when_alpha_below_one(alpha):
    """With partial accommodation the two forms must give different drag (about a percent)."""
    flow = FLOWS["orbital"]
    c, sg = angles(FRONT_DELTAS_DEG)
    surf = surface(alpha=alpha, wall_temperature=300.0)
    a, _ = sentman(c, sg, surf, flow, ModelOptions(incident_temperature="energy"))
    b, _ = sentman(c, sg, surf, flow, ModelOptions(incident_temperature="kinetic"))
    assert np.all(np.abs(b - a) > 1e-4 * np.abs(a))


# ------------------------------------------------------------------------------- broadcasting
@pytest.mark.parametrize(
    "name,model",
    [
        ("sentman", sentman),
        ("schaaf", schaaf),
        ("cook", cook),
        ("storch", storch),
        ("maxwell", maxwell),
        ("newton", newton),
    ],
)
def test_models_broadcast_attitudes_by_panels(name, model):
    """(M attitudes, N panels) input gives, row by row, the same as (N,) input."""
    flow = FLOWS["slow"]
    surf = surface(alpha=0.8, sigma_n=0.9, sigma_t=0.7)
    rng = np.random.default_rng(1)
    c = rng.uniform(-1, 1, size=(4, 7))
    sg = np.sqrt(1 - c * c)
    cp, ctau = model(c, sg, surf, flow, ModelOptions())
    assert np.shape(cp) == (4, 7)
    for i in range(4):
        cp_i, ctau_i = model(c[i], sg[i], surf, flow, ModelOptions())
        assert_close(np.asarray(cp)[i], cp_i, rtol=1e-15)
        assert_close(np.broadcast_to(ctau, (4, 7))[i], np.broadcast_to(ctau_i, (7,)), rtol=1e-15)


# ------------------------------------------------------------------------- numerical positivity
@pytest.mark.parametrize("name,model", [("sentman", sentman), ("schaaf", schaaf), ("dria", dria)])
def test_back_face_pressure_is_never_negative(name, model):
    """Every term of p = (2 - sigma_n) p_i + sigma_n p_w is a momentum flux of molecules hitting
    the wall, so c_p >= 0 at every incidence (Schaaf & Chambre 1961), even where it is tiny."""
    flow = FreeStream(7500.0, 900.0, number_densities={"O": 1e14})
    c, sg = angles([100.0, 120.0, 143.0, 160.0, 180.0])
    cp, _ = model(c, sg, surface(alpha=1.0, sigma_n=1.0, sigma_t=1.0), flow, ModelOptions())
    assert np.all(np.asarray(cp) >= 0.0)


# ------------------------------------------------------------------------------- split models
@pytest.mark.parametrize("name", ["sentman", "schaaf", "maxwell"])
@pytest.mark.parametrize("flow_name", ["orbital", "slow"])
def test_split_plate_is_the_model(name, flow_name):
    """SPLIT_MODELS[name] = (parameters, plate): plate(c, *parameters) gives the model's c_p and
    c_tau / sin(delta), against the closed forms above (Sentman's, and Schaaf & Chambre's, whose
    c_tau is sin(delta) times a function of c alone), also at grazing and head-on incidence where
    sin(delta) = 0 and the ratio cannot be read off c_tau."""
    from adbsat_ros.physics.gsi_models import SPLIT_MODELS, get_model

    flow = FLOWS[flow_name]
    surf = surface(alpha=0.8, sigma_n=0.9, sigma_t=0.7, wall_temperature=350.0)
    parameters_of, plate = SPLIT_MODELS[name]
    c, sg = angles(DELTAS_DEG)
    cp, shear = plate(c, *parameters_of(surf, flow, ModelOptions()))
    cp_model, ctau_model = get_model(name)(c, sg, surf, flow, ModelOptions())
    assert_close(cp, cp_model, rtol=1e-14)
    assert_close(shear * sg, ctau_model, rtol=1e-14)
    m = flow.mean_mass
    if name == "sentman":
        cp_ref, tau_ref = sentman_plate(
            c, 1.0, flow.speed_ratio, reemission_temperature_ratio(flow, m, 0.8, 350.0)
        )
    else:
        sigma_n, sigma_t = (0.9, 0.7) if name == "schaaf" else (0.8, 0.8)
        cp_ref, tau_ref = schaaf_plate(
            c, 1.0, flow.speed_ratio, sigma_n, sigma_t, 350.0 / flow.temperature
        )
    assert_close(cp, cp_ref)
    assert_close(shear, tau_ref)  # (tau_i with sin(delta) = 1: c_tau / sin(delta))
    assert (
        np.all(np.isfinite(shear)) and shear[0] > 0.0
    )  # head-on: a ratio c_tau / sin(delta) of 0/0
