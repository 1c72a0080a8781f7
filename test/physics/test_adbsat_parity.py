"""Parity with ADBSat's definitions, derived by hand (ADBSat itself cannot be run here).

For a box, every triangle of a face has the same normal and incidence, and the area-weighted
barycentres of the two triangles of a face give the face centroid, so ADBSat's sums over panels
reduce to sums over the six faces. The reference below evaluates those six faces with ADBSat's
formulas as written in docs/physics.md (Sec. 2 frames and totals, Sec. 3 models in their
c_d/c_l forms where physics.md gives them, Sec. 5 constants): it shares no code with adbsat_ros.

Frames (physics.md Sec. 2): L_gb = diag(1,-1,-1); L_wb = [[ca cb, sb, sa cb], [-ca sb, cb, -sa sb],
[-sa, 0, ca]]; gas direction u = L_gb L_wb^T (-1,0,0); delta = arccos(-u.n); shear direction
t = n x (u x n)/|...| (0 where undefined); panel force q A (c_tau t - c_p n);
Cf_w = L_gw^T C_F,G; Cf_f = L_fb L_gb^T C_F,G; Cm_B = L_gb^T C_M,G about the mesh origin;
Aref = half the wetted area; Lref = x extent; AreaProj = sum A cos(delta) over delta <= 90 deg.
"""

import math

import numpy as np
import pytest
import trimesh
from scipy.special import erf

from adbsat_ros import FreeStream, ModelOptions, PanelMethod, SurfaceProperties, panels_from_trimesh

# ------------------------------------------------------------------ ADBSat constants (Sec. 5)
R_GAS = 8.31446261815324
K_B = 1.3806503e-23
N_A = 6.02214076e23
M_G = {
    "He": 4.002602,
    "O": 15.9994,
    "N2": 28.0134,
    "O2": 31.9988,
    "Ar": 39.948,
    "H": 1.0079,
    "N": 14.0067,
}
SQ = math.sqrt(math.pi)

# NRLMSISE-like composition near 400 km [m^-3]
N_DENS = {
    "He": 2.5e12,
    "O": 3.5e14,
    "N2": 2.0e13,
    "O2": 6.0e11,
    "Ar": 1.0e10,
    "H": 1.5e11,
    "N": 4.0e12,
}
V_INF, T_INF = 7600.0, 1000.0
ALPHA, SIGMA_N, SIGMA_T, T_W = 0.85, 0.9, 0.8, 350.0


def adbsat_environment(n=N_DENS, V=V_INF, T=T_INF):
    """environment.m's derived quantities: mean molar mass (number weighted, g/mol), Rmean,
    speed ratio s, and massConc = n_k M_k/(1000 N_A)/rho_total."""
    n_tot = sum(n.values())
    m_bar = sum(M_G[k] * n[k] for k in n) / n_tot
    R_mean = 1000.0 * R_GAS / m_bar
    s = V / math.sqrt(2 * K_B * T / (m_bar / (1000 * N_A)))
    rho = sum(n[k] * M_G[k] / (1000 * N_A) for k in n)
    mass_conc = {k: n[k] * M_G[k] / (1000 * N_A) / rho for k in n}
    return m_bar, R_mean, s, rho, mass_conc


# ---------------------------------------------------------------- ADBSat model forms (Sec. 3)
def from_cd_cl(cd, cl, c, sg):
    """c_p = c_d c + c_l sigma, c_tau = c_d sigma - c_l c."""
    return cd * c + cl * sg, cd * sg - cl * c


def model_newton(c, sg, env):
    return (2 * c * c, 0.0) if c > 0 else (0.0, 0.0)


def model_sentman(c, sg, env):
    s = env["s"]
    K = math.sqrt(0.5 * (1 + ALPHA * (2 * T_W / (T_INF * s * s) - 1)))
    E, Phi = math.exp(-((s * c) ** 2)), 1 + erf(s * c)
    cp = (c * c + 1 / (2 * s * s)) * Phi + c * E / (SQ * s) + K / 2 * (SQ * c * Phi + E / s)
    ctau = sg * (c * Phi + E / (SQ * s))
    return cp, ctau


def model_cook(c, sg, env):
    if c <= 0:  # zeroed for delta >= 90 deg
        return 0.0, 0.0
    Tk = V_INF**2 / (3 * env["R_mean"])
    W = math.sqrt(1 + ALPHA * (T_W / Tk - 1))
    return from_cd_cl(2 * c * (1 + 2.0 / 3.0 * W * c), 4.0 / 3.0 * W * sg * c, c, sg)


def model_schaaf(c, sg, env):
    s, sn, st = env["s"], SIGMA_N, SIGMA_T
    r = math.sqrt(T_W / T_INF)
    E, Phi = math.exp(-((s * c) ** 2)), 1 + erf(s * c)
    cp = (
        ((2 - sn) * s * c / SQ + sn / 2 * r) * E
        + ((2 - sn) * (0.5 + s * s * c * c) + sn / 2 * r * SQ * s * c) * Phi
    ) / s**2
    ctau = st * sg / (s * SQ) * (E + SQ * s * c * Phi)
    return cp, ctau


def model_maxwell(c, sg, env):
    """ADBSat's maxwell (two-sided plate), theta = pi/2 - delta, zeroed for delta > 90 deg."""
    if c < 0:
        return 0.0, 0.0
    s, f = env["s"], 1 - ALPHA
    r = math.sqrt(T_W / T_INF)
    theta = math.pi / 2 - math.acos(c)
    cos2t = math.cos(2 * theta)
    E = math.exp(-((s * c) ** 2))
    cd = (
        2 * (1 - f * cos2t) * E / (SQ * s)
        + c / s**2 * (1 + 2 * s * s + f * (1 - 2 * s * s * cos2t)) * erf(s * c)
        + ALPHA * SQ / s * c * c * r
    )
    cl = (
        4 * f / (SQ * s) * c * sg * E
        + sg / s**2 * (1 + f * (1 + 4 * s * s * c * c)) * erf(s * c)
        + ALPHA * SQ / s * c * sg * r
    )
    return from_cd_cl(cd, cl, c, sg)


def model_storch(c, sg, env):
    if c < 0:
        return 0.0, 0.0
    Vw = math.sqrt(math.pi * env["R_mean"] * T_W / 2)
    return 2 * c * (SIGMA_N * Vw / V_INF + (2 - SIGMA_N) * c), 2 * SIGMA_T * c * sg


def model_dria(c, sg, env):
    """gamma = cos(delta), ell = sin(delta) (ADBSat's ell := 1 where n is parallel to u only
    matters through the shear, whose direction is 0 there). Weights massConc (or
    massConc * rho_sum/rho_given in compat with a given total density)."""
    gam, ell = c, (sg if sg > 0 else 1.0)
    cd_tot = cl_tot = 0.0
    for k, w in env["dria_weights"].items():
        m = M_G[k] / (1000 * N_A)
        s = V_INF / math.sqrt(2 * K_B * T_INF / m)
        Rj = 1000 * R_GAS / M_G[k]
        P = math.exp(-(gam**2) * s * s) / s
        G = 1 / (2 * s * s)
        Q = 1 + G
        Z = 1 + erf(gam * s)
        Kj = math.sqrt(0.5 * (1 + ALPHA * (4 * Rj * T_W / V_INF**2 - 1)))
        cd_tot += w * (P / SQ + gam * Q * Z + gam / 2 * Kj * (gam * SQ * Z + P))
        cl_tot += w * (ell * G * Z + ell / 2 * Kj * (gam * SQ * Z + P))
    return from_cd_cl(cd_tot, cl_tot, c, sg)


MODELS = {
    "newton": model_newton,
    "sentman": model_sentman,
    "cook": model_cook,
    "schaaf": model_schaaf,
    "maxwell": model_maxwell,
    "storch": model_storch,
    "dria": model_dria,
}


# ------------------------------------------------------------------------ frames and totals
def L_wb(a, b):
    ca, sa, cb, sb = math.cos(a), math.sin(a), math.cos(b), math.sin(b)
    return np.array([[ca * cb, sb, sa * cb], [-ca * sb, cb, -sa * sb], [-sa, 0.0, ca]])


L_GB = np.diag([1.0, -1.0, -1.0])
L_FB = np.diag([-1.0, 1.0, -1.0])


def box_faces(extents, centre):
    """(normal, area, centroid) of the six faces of an axis-aligned box."""
    ext = np.asarray(extents, float)
    ctr = np.asarray(centre, float)
    faces = []
    for k in range(3):
        for sgn in (1.0, -1.0):
            n = np.zeros(3)
            n[k] = sgn
            area = np.prod(np.delete(ext, k))
            faces.append((n, area, ctr + ext[k] / 2 * n))
    return faces


def adbsat_by_hand(model, extents, centre, aoa, aos, env):
    faces = box_faces(extents, centre)
    L_gw = L_GB @ L_wb(aoa, aos).T
    u = L_gw @ np.array([-1.0, 0.0, 0.0])
    Aref = 0.5 * sum(A for _, A, _ in faces)
    Lref = float(extents[0])
    F = np.zeros(3)
    M = np.zeros(3)
    area_proj = 0.0
    for n, A, r in faces:
        delta = math.acos(max(-1.0, min(1.0, float(-u @ n))))
        c, sg = math.cos(delta), math.sin(delta)
        uxn = np.cross(u, n)
        t = np.cross(n, uxn)
        t = t / np.linalg.norm(t) if np.linalg.norm(uxn) > 1e-12 else np.zeros(3)
        cp, ctau = MODELS[model](c, sg, env)
        f = A * (ctau * t - cp * n)
        F += f
        M += np.cross(r, f)
        if delta <= math.pi / 2:
            area_proj += A * c
    Cf_G = F / Aref
    Cm_G = M / (Aref * Lref)
    return {
        "Cf_w": L_gw.T @ Cf_G,
        "Cf_f": L_FB @ L_GB.T @ Cf_G,
        "Cm_B": L_GB.T @ Cm_G,
        "Aref": Aref,
        "Lref": Lref,
        "AreaProj": area_proj,
    }


# ------------------------------------------------------------------------------------ cases
BODIES = {
    "unit_cube": ((1.0, 1.0, 1.0), (0.3, -0.2, 0.5)),
    "box_2x1x0.5": ((2.0, 1.0, 0.5), (-0.4, 0.7, 0.25)),
}
ATTITUDES = {
    "a0": (0.0, 0.0),
    "a45": (45.0, 0.0),
    "a30_b20": (30.0, 20.0),
    "a-110_b-35": (-110.0, -35.0),
}


def make_mesh(extents, centre):
    tm = trimesh.creation.box(extents=extents)
    tm.apply_translation(centre)
    return panels_from_trimesh(tm)


def env_dict(compat_density_factor=None):
    m_bar, R_mean, s, rho, mass_conc = adbsat_environment()
    weights = dict(mass_conc)
    if compat_density_factor is not None:
        weights = {k: w / compat_density_factor for k, w in mass_conc.items()}
    return {"m_bar": m_bar, "R_mean": R_mean, "s": s, "rho": rho, "dria_weights": weights}


def compare(result, expected):
    for key in ("Cf_w", "Cf_f", "Cm_B"):
        np.testing.assert_allclose(
            getattr(result, key), expected[key], rtol=1e-6, atol=1e-12, err_msg=key
        )
    assert result.reference.area == pytest.approx(expected["Aref"], rel=1e-12)
    assert result.reference.length == pytest.approx(expected["Lref"], rel=1e-12)
    assert result.area_projected == pytest.approx(expected["AreaProj"], rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("att", list(ATTITUDES))
@pytest.mark.parametrize("body", list(BODIES))
@pytest.mark.parametrize("model", list(MODELS))
def test_parity_with_hand_derived_adbsat(model, body, att):
    extents, centre = BODIES[body]
    aoa_deg, aos_deg = ATTITUDES[att]
    flow = FreeStream(V_INF, T_INF, number_densities=N_DENS)
    env = env_dict()
    assert flow.speed_ratio == pytest.approx(env["s"], rel=1e-9)  # same s as environment.m
    pm = PanelMethod(
        make_mesh(extents, centre),
        model,
        SurfaceProperties(alpha=ALPHA, sigma_n=SIGMA_N, sigma_t=SIGMA_T, wall_temperature=T_W),
        options=ModelOptions(adbsat_compat=True),
    )
    res = pm.coefficients(flow, math.radians(aoa_deg), math.radians(aos_deg))
    expected = adbsat_by_hand(
        model, extents, centre, math.radians(aoa_deg), math.radians(aos_deg), env
    )
    compare(res, expected)
    # moments about the mesh origin are non-trivial for the shifted bodies
    assert np.linalg.norm(expected["Cm_B"]) > 1e-3


@pytest.mark.parametrize("att", ["a0", "a30_b20"])
def test_dria_compat_with_given_total_density(att):
    """ADBSat's DRIA weights are n_j m_j / rho_total(NRLMSISE), not renormalised; with a given
    total density 3 % above sum(n_j m_j) every coefficient is 1/1.03 of the mass-fraction one."""
    extents, centre = BODIES["box_2x1x0.5"]
    aoa_deg, aos_deg = ATTITUDES[att]
    rho = adbsat_environment()[3]
    flow = FreeStream(V_INF, T_INF, number_densities=N_DENS, density=1.03 * rho)
    pm = PanelMethod(
        make_mesh(extents, centre),
        "dria",
        SurfaceProperties(alpha=ALPHA, wall_temperature=T_W),
        options=ModelOptions(adbsat_compat=True),
    )
    res = pm.coefficients(flow, math.radians(aoa_deg), math.radians(aos_deg))
    expected = adbsat_by_hand(
        "dria", extents, centre, math.radians(aoa_deg), math.radians(aos_deg), env_dict(1.03)
    )
    compare(res, expected)


@pytest.mark.parametrize("model", ["sentman", "dria", "schaaf", "newton", "cook", "storch"])
def test_non_compat_matches_adbsat_for_models_without_quirks(model):
    """Models without an ADBSat quirk must give the same numbers with and without compat
    (dria without a given total density: mass fractions either way)."""
    extents, centre = BODIES["box_2x1x0.5"]
    flow = FreeStream(V_INF, T_INF, number_densities=N_DENS)
    props = SurfaceProperties(alpha=ALPHA, sigma_n=SIGMA_N, sigma_t=SIGMA_T, wall_temperature=T_W)
    mesh = make_mesh(extents, centre)
    a = PanelMethod(mesh, model, props).coefficients(flow, 0.5, -0.3)
    b = PanelMethod(mesh, model, props, options=ModelOptions(adbsat_compat=True)).coefficients(
        flow, 0.5, -0.3
    )
    np.testing.assert_allclose(a.Cf_w, b.Cf_w, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(a.Cm_B, b.Cm_B, rtol=1e-13, atol=1e-15)


def test_maxwell_default_differs_from_adbsat_compat():
    """The default maxwell is one-sided (Schaaf with sigma_n = sigma_t = alpha, back faces kept);
    ADBSat's is the two-sided plate: for the cube at aoa 0 the four grazing faces give
    c_tau = 2 alpha/(sqrt(pi) s) (compat) vs alpha/(sqrt(pi) s) (one-sided), a drag difference
    of 4 * alpha/(sqrt(pi) s) / Aref plus the back-face terms."""
    extents, centre = BODIES["unit_cube"]
    flow = FreeStream(V_INF, T_INF, number_densities=N_DENS)
    mesh = make_mesh(extents, centre)
    props = SurfaceProperties(alpha=ALPHA, wall_temperature=T_W)
    one = PanelMethod(mesh, "maxwell", props).coefficients(flow, 0.0, 0.0)
    two = PanelMethod(
        mesh, "maxwell", props, options=ModelOptions(adbsat_compat=True)
    ).coefficients(flow, 0.0, 0.0)
    s = flow.speed_ratio
    # one-sided: equals schaaf with sigma_n = sigma_t = alpha on every face
    sch = PanelMethod(
        mesh, "schaaf", SurfaceProperties(sigma_n=ALPHA, sigma_t=ALPHA, wall_temperature=T_W)
    ).coefficients(flow, 0.0, 0.0)
    np.testing.assert_allclose(one.Cf_w, sch.Cf_w, rtol=1e-13, atol=1e-15)
    # grazing-face shear: 4 faces x 1 m^2 x alpha/(sqrt(pi) s) more in compat, over Aref = 3.
    # Front/rear: compat gives the front plate p(1) - p(-1) and zeroes the rear face; one-sided
    # gives p(1) on the front and the rear face's p(-1) pushing forward: the same net.
    grazing_extra = 4 * ALPHA / (SQ * s) / 3.0
    assert two.drag - one.drag == pytest.approx(grazing_extra, rel=1e-9)


# -------------------------------------------------------------------------- hand-worked numbers
def test_newton_offset_cube_aoa0_by_hand():
    """Unit cube centred at (0.3,-0.2,0.5), aoa = aos = 0: only the +x face (c = 1, c_p = 2):
    F_G = (-2, 0, 0) q m^2 at r = (0.8,-0.2,0.5); M_G = r x F = (0, -1, -0.4).
    Aref = 3, Lref = 1: Cf_w = (-2/3, 0, 0) (drag = +2/3 = -Cf_w[0]), Cf_f = (2/3, 0, 0),
    Cm_B = diag(1,-1,-1) (0,-1,-0.4)/3 = (0, 1/3, 0.4/3); AreaProj = 1."""
    pm = PanelMethod(make_mesh(*BODIES["unit_cube"]), "newton")
    r = pm.coefficients(FreeStream(V_INF, T_INF, mean_mass_amu=16.0), 0.0, 0.0)
    np.testing.assert_allclose(r.Cf_w, [-2 / 3, 0, 0], atol=1e-15)
    np.testing.assert_allclose(r.Cf_f, [2 / 3, 0, 0], atol=1e-15)
    np.testing.assert_allclose(r.Cm_B, [0, 1 / 3, 0.4 / 3], atol=1e-15)
    assert r.drag == pytest.approx(2 / 3) and r.Cf_f[0] == pytest.approx(r.drag)
    assert (r.reference.area, r.reference.length, r.area_projected) == pytest.approx(
        (3.0, 1.0, 1.0)
    )


def test_newton_offset_cube_aoa45_by_hand():
    """aoa = 45 deg: u = (-1/sqrt2, 0, 1/sqrt2); faces +x (r = (0.8,-0.2,0.5)) and -z
    (r = (0.3,-0.2,0)) at c = 1/sqrt2, c_p = 1: F = (-1,0,0) + (0,0,1); M = (0,-0.5,-0.2) +
    (-0.2,-0.3,0) = (-0.2,-0.8,-0.2). Cf_B = (-1,0,-1)/3 -> Cf_w = L_wb Cf_B = (-sqrt2/3, 0, 0),
    Cf_f = (1/3, 0, 1/3), Cm_B = (-0.2, 0.8, 0.2)/3, AreaProj = sqrt2."""
    pm = PanelMethod(make_mesh(*BODIES["unit_cube"]), "newton")
    r = pm.coefficients(FreeStream(V_INF, T_INF, mean_mass_amu=16.0), math.radians(45), 0.0)
    np.testing.assert_allclose(r.Cf_w, [-math.sqrt(2) / 3, 0, 0], atol=1e-15)
    np.testing.assert_allclose(r.Cf_f, [1 / 3, 0, 1 / 3], atol=1e-15)
    np.testing.assert_allclose(r.Cm_B, [-0.2 / 3, 0.8 / 3, 0.2 / 3], atol=1e-15)
    assert r.area_projected == pytest.approx(math.sqrt(2))
    assert r.lift == pytest.approx(0.0, abs=1e-15)


@pytest.mark.parametrize("model", list(MODELS))
def test_sign_conventions_at_zero_angles(model):
    """At aoa = aos = 0 the gas moves along -x_G: drag = -Cf_w[0] > 0 and Cf_f[0] = +C_D
    (physics.md Sec. 2), and a positive angle of attack puts the flow on the -z_G (= +z_B) face."""
    flow = FreeStream(V_INF, T_INF, number_densities=N_DENS)
    pm = PanelMethod(
        make_mesh(*BODIES["box_2x1x0.5"]),
        model,
        SurfaceProperties(alpha=ALPHA, sigma_n=SIGMA_N, sigma_t=SIGMA_T, wall_temperature=T_W),
        options=ModelOptions(adbsat_compat=True),
    )
    r = pm.coefficients(flow, 0.0, 0.0)
    np.testing.assert_allclose(r.flow_direction, [-1, 0, 0], atol=1e-15)
    assert r.drag > 0 and r.Cf_w[0] < 0
    assert r.Cf_f[0] == pytest.approx(r.drag, rel=1e-14)
    assert r.Cf_G[0] == pytest.approx(-r.drag, rel=1e-14)
    r10 = pm.coefficients(flow, math.radians(10.0), 0.0)
    assert r10.flow_direction[2] > 0  # gas moves towards +z_G: the -z_G face is windward
    # at aoa, the box's windward -z_G face pushes it towards +z_G: Cf_G[2] > 0, Cf_f[2] = Cf_G[2]
    assert r10.Cf_G[2] > 0 and r10.Cf_f[2] == pytest.approx(r10.Cf_G[2], rel=1e-14)
