"""Diffuse models (sentman, schaaf, dria) at panel level against closed forms; the incident
temperature forms; broadcasting, positivity and the split plates of every such model.

Every reference is written out in model_references.py, independently of adbsat_ros.physics.models,
from the free-molecular flux integrals of a drifting Maxwellian gas on one side of a flat plate:

    x = s c (normal speed ratio), E = exp(-x^2), Phi = 1 + erf(x), s = V / sqrt(2 k T_inf / m)

    incident number flux      N_i / (n v_th)  = (E + sqrt(pi) x Phi) / (2 sqrt(pi))
    incident normal momentum  p_i / q         = (1/s^2) [x E / sqrt(pi) + (1/2 + x^2) Phi]
    incident tangential mom.  tau_i / q       = sin(delta) (E + sqrt(pi) x Phi) / (sqrt(pi) s)
    diffuse re-emission at T  p_w / q         = sqrt(T / T_inf) (E + sqrt(pi) x Phi) / (2 s^2)

(Schaaf & Chambre 1961, "Flow of Rarefied Gases", free-molecule plate p and tau; Bird 1994,
"Molecular Gas Dynamics and the DSMC of Gas Flows", Ch. 7 (collisionless flows); the re-emitted
pressure is N_i m sqrt(pi k T / (2 m)), the mean normal momentum of a half-range Maxwellian at T.)
q = rho V^2 / 2.  These closed forms are themselves checked against direct quadrature of the
Maxwellian below (test_flux_closed_forms_match_quadrature).
"""

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
    reemitted_pressure,
    schaaf_plate,
    sentman_plate,
    surface,
)
from scipy.integrate import quad

from adbsat_ros import FreeStream
from adbsat_ros.physics.constants import AMU, BOLTZMANN
from adbsat_ros.physics.gsi_models import (
    SPLIT_MODELS,
    ModelOptions,
    cook,
    dria,
    get_model,
    maxwell,
    newton,
    schaaf,
    sentman,
    storch,
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
