"""Hyperthermal models (newton, cook, storch) at panel level against closed forms; the
hyperthermal limits of the diffuse models (Sentman 1961, Schaaf & Chambre 1961)."""

import math

import numpy as np
import pytest
from model_references import (
    DELTAS_DEG,
    FLOWS,
    angles,
    assert_close,
    surface,
)

from adbsat_ros.physics.constants import BOLTZMANN
from adbsat_ros.physics.gsi_models import (
    ModelOptions,
    cook,
    newton,
    storch,
)


# ------------------------------------------------------------------------------------- newton
def test_newton_plate():
    """Newtonian impact (Newton; e.g. Anderson 2006, Hypersonic and high-temperature gas
    dynamics, Ch. 3, Newtonian theory with C_p,max = 2): c_p = 2 cos^2 delta on faces seen by
    the flow, 0 behind; no shear."""
    c, sg = angles(DELTAS_DEG)
    cp, ctau = newton(c, sg, surface(), FLOWS["orbital"], ModelOptions())
    expected = np.where(
        np.radians(DELTAS_DEG) < math.pi / 2 - 1e-12, 2.0 * np.cos(np.radians(DELTAS_DEG)) ** 2, 0.0
    )
    assert_close(cp, expected, atol=1e-12)
    assert np.all(np.asarray(ctau) == 0.0)
    assert cp[0] == pytest.approx(2.0)


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
