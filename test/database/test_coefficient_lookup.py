"""The interpolating lookup: exact at the nodes, within its stated error between them (against the
panel method itself), wrap-around in aoa, the sideslip pole, range errors, and the error
estimator on functions with known interpolation errors."""

import math

import numpy as np
import pytest
import trimesh

from adbsat_ros import FreeStream, PanelMethod, panels_from_trimesh
from adbsat_ros.database.build import build_database
from adbsat_ros.database.format import AeroDatabase
from adbsat_ros.database.interpolation import bilinear, estimate_interpolation_error
from adbsat_ros.database.lookup import CoefficientLookup
from adbsat_ros.geometry import frames
from adbsat_ros.geometry.loading import resolve_mesh
from adbsat_ros.shading.shader import make_shader

FLOW = FreeStream(7500.0, 900.0, mean_mass_amu=16.0)


def box_mesh():
    box = trimesh.creation.box(extents=(1.0, 0.6, 0.4))
    box.apply_translation((0.1, 0.05, 0.0))
    return panels_from_trimesh(box, source="box")


@pytest.fixture(scope="module")
def satellite():
    """Example satellite (concave: real shadows), Sentman, ray-cast, 15 deg full-sphere grid."""
    method = PanelMethod(resolve_mesh("example"), "sentman")
    db = build_database(
        method,
        FLOW,
        np.arange(-180, 181, 15.0),
        np.arange(-90, 91, 15.0),
        shading="raycast",
        workers=2,
        progress=False,
    )
    return method, db


@pytest.fixture(scope="module")
def box():
    """Offset box, Newton (kinks where faces turn to grazing), 10 deg grid, no shading."""
    method = PanelMethod(box_mesh(), "newton")
    db = build_database(
        method,
        FLOW,
        np.arange(-180, 181, 10.0),
        np.arange(-90, 91, 10.0),
        shading="none",
        workers=1,
        progress=False,
        mesh_spec=None,
    )
    return method, db


def random_attitudes(n, seed):
    """Uniform over the sphere of flow directions (aoa uniform, sin(aos) uniform) [deg]."""
    rng = np.random.default_rng(seed)
    return rng.uniform(-180, 180, n), np.degrees(np.arcsin(rng.uniform(-1, 1, n)))


# ------------------------------------------------------------------------------ nodes
def test_exact_at_grid_nodes(satellite):
    _, db = satellite
    lookup = CoefficientLookup(db)
    for i in range(0, db.shape[0], 3):
        for j in range(db.shape[1]):
            r = lookup.coefficients(db.aoa_deg[i], db.aos_deg[j])
            np.testing.assert_array_equal(r.Cf_G, db.Cf_G[i, j])
            np.testing.assert_array_equal(r.Cm_G, db.Cm_G[i, j])
            assert (r.CD, r.CL, r.CY) == pytest.approx(
                (db.CD[i, j], db.CL[i, j], db.CY[i, j]), abs=1e-14
            )


# ------------------------------------------------------------------------------ stated error
@pytest.mark.parametrize("body,n,seed", [("satellite", 60, 3), ("box", 150, 4)])
def test_within_stated_error_between_nodes(satellite, box, body, n, seed):
    """Exact panel-method values (same shading) at random off-grid attitudes differ from the
    lookup by no more than the stated bound, for |dCf_G|, |dCm_G| and CD, CL, CY; the bound is
    not vacuous (below 20 % of the largest coefficient on these coarse grids) and the worst error
    uses a fair share of it."""
    method, db = satellite if body == "satellite" else box
    lookup = CoefficientLookup(db)
    bound = lookup.error_bound
    assert bound["force_coefficient"] < 0.2 * bound["max_force_coefficient"]
    shader = (
        make_shader(method.mesh, db.metadata["shading"]["mode"])
        if db.metadata["shading"]["mode"] != "none"
        else None
    )
    worst_f = worst_m = 0.0
    for a, b in zip(*random_attitudes(n, seed)):
        ar, br = math.radians(a), math.radians(b)
        lighting = shader.lighting(frames.flow_direction(ar, br)) if shader else None
        exact = method.coefficients(FLOW, ar, br, lighting=lighting)
        got = lookup.coefficients(a, b)
        df = np.linalg.norm(got.Cf_G - exact.Cf_G)
        worst_f = max(worst_f, df)
        worst_m = max(worst_m, np.linalg.norm(got.Cm_G - exact.Cm_G))
        for name, value in (("CD", exact.drag), ("CL", exact.lift), ("CY", exact.side_force)):
            assert abs(getattr(got, name) - value) <= bound["force_coefficient"], (name, a, b)
    assert worst_f <= bound["force_coefficient"]
    assert worst_m <= bound["moment_coefficient"]
    assert worst_f > 0.1 * bound["force_coefficient"]  # the bound is not absurdly loose


def test_estimator_on_known_functions():
    """Linear data: the bilinear interpolant is exact, stated error 0. Quadratic in aoa with step h:
    the coarse (2h) interpolant misses x^2 at its cell midpoints by exactly (2h)^2/4 = h^2."""
    aoa, aos = np.arange(-180, 181, 10.0), np.arange(-90, 91, 15.0)
    a, b = np.meshgrid(aoa, aos, indexing="ij")
    zero = np.zeros(a.shape)

    def database(fx):
        vec = np.stack([fx, zero, zero], axis=-1)
        return AeroDatabase(
            aoa,
            aos,
            zero,
            zero,
            zero,
            zero,
            vec,
            vec,
            vec,
            vec,
            0.5 * vec,
            metadata={"reference": {"area": 1.0, "length": 1.0}},
        )

    linear = estimate_interpolation_error(database(0.01 * a - 0.02 * b + 3.0))
    assert linear["force_coefficient"] == pytest.approx(0.0, abs=1e-13)
    quadratic = estimate_interpolation_error(database(1e-4 * a**2))
    assert quadratic["force_coefficient"] == pytest.approx(1e-4 * 10.0**2, rel=1e-12)
    assert quadratic["moment_coefficient"] == pytest.approx(0.5e-4 * 10.0**2, rel=1e-12)
    assert quadratic["points"] == a.size - 19 * 7


def test_too_small_grid_has_no_estimate():
    method = PanelMethod(box_mesh(), "newton")
    db = build_database(
        method, FLOW, [0, 10], [0, 5], shading="none", workers=1, progress=False, mesh_spec=None
    )
    assert db.metadata["interpolation_error"]["force_coefficient"] is None
    assert "unavailable" in CoefficientLookup(db).error_bound["method"]


# ------------------------------------------------------------------------------ geometry
def test_wrap_around_at_180(box):
    _, db = box
    lookup = CoefficientLookup(db)
    assert lookup.periodic
    for b in (-45.0, 0.0, 33.0):
        left = lookup.coefficients(179.9999, b).Cf_G
        right = lookup.coefficients(-179.9999, b).Cf_G
        np.testing.assert_allclose(left, right, atol=1e-4)
        np.testing.assert_array_equal(
            lookup.coefficients(190.0, b).Cf_G, lookup.coefficients(-170.0, b).Cf_G
        )
        np.testing.assert_allclose(
            lookup.coefficients(-545.0, b).Cf_G, lookup.coefficients(175.0, b).Cf_G, atol=1e-15
        )


def test_open_circle_grid_closes_with_the_first_node():
    """aoa -180:30:150 leaves a 30 deg gap: it wraps; 165 deg is halfway between 150 and -180."""
    method = PanelMethod(box_mesh(), "newton")
    db = build_database(
        method,
        FLOW,
        np.arange(-180, 151, 30.0),
        [0.0, 20.0],
        shading="none",
        workers=1,
        progress=False,
        mesh_spec=None,
    )
    lookup = CoefficientLookup(db)
    assert lookup.periodic and lookup.aoa_range == (-180.0, 180.0)
    np.testing.assert_allclose(
        lookup.coefficients(165.0, 0.0).Cf_G, 0.5 * (db.Cf_G[-1, 0] + db.Cf_G[0, 0]), atol=1e-15
    )


def test_partial_grid_range_errors_and_reduction():
    method = PanelMethod(box_mesh(), "newton")
    db = build_database(
        method,
        FLOW,
        np.arange(0, 91, 10.0),
        np.arange(-30, 31, 10.0),
        shading="none",
        workers=1,
        progress=False,
        mesh_spec=None,
    )
    lookup = CoefficientLookup(db)
    assert not lookup.periodic
    np.testing.assert_array_equal(
        lookup.coefficients(370.0, 10.0).Cf_G, db.Cf_G[1, 4]
    )  # 370 = 10 deg
    with pytest.raises(ValueError, match=r"angle of attack 100 deg .*\[0, 90\]"):
        lookup.coefficients(100.0, 0.0)
    with pytest.raises(ValueError, match=r"sideslip 40 deg .*\[-30, 30\]"):
        lookup.coefficients(45.0, 40.0)
    with pytest.raises(ValueError, match=r"sideslip 95 deg is outside \[-90, 90\]"):
        lookup.coefficients(45.0, 95.0)
    with pytest.raises(ValueError, match="finite"):
        lookup.coefficients(float("nan"), 0.0)


def test_sideslip_pole_and_flow_direction(box):
    """At aos = +/-90 deg every aoa is the flow u_G = (0, +/-1, 0): one Cf_G; a flow direction
    gives the same result as its angles; CD is the drag along that flow."""
    method, db = box
    lookup = CoefficientLookup(db)
    at_pole = [lookup.coefficients(a, 90.0).Cf_G for a in (-180.0, -37.0, 0.0, 121.0)]
    for v in at_pole[1:]:
        np.testing.assert_allclose(v, at_pole[0], atol=1e-12)
    np.testing.assert_allclose(
        lookup.coefficients(flow_direction=[0.0, 2.0, 0.0]).Cf_G, at_pole[0], atol=1e-12
    )
    exact = method.coefficients(FLOW, flow_direction=[0.0, 1.0, 0.0])
    np.testing.assert_allclose(at_pole[0], exact.Cf_G, atol=1e-12)
    u = np.array([-0.3, 0.5, 0.7])
    a, b = (math.degrees(x) for x in frames.angles_of_flow(u))
    r1, r2 = lookup.coefficients(flow_direction=u), lookup.coefficients(a, b)
    np.testing.assert_array_equal(r1.Cf_G, r2.Cf_G)
    assert r1.CD == pytest.approx(float(r1.Cf_G @ (u / np.linalg.norm(u))), abs=1e-14)
    with pytest.raises(ValueError, match="flow_direction"):
        lookup.coefficients(flow_direction=[0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="not both"):
        lookup.coefficients(1.0, 2.0, flow_direction=u)


def test_vectorised_lookup_matches_scalar_and_bilinear(box):
    _, db = box
    lookup = CoefficientLookup(db)
    a, b = random_attitudes(50, 9)
    Cf, Cm = lookup.body_coefficients_many(a, b)
    for k in range(a.size):
        f, m = lookup.body_coefficients(a[k], b[k])
        np.testing.assert_allclose(Cf[k], f, atol=1e-15)
        np.testing.assert_allclose(Cm[k], m, atol=1e-15)
    # bilinear() against a direct weighted sum at one point
    i, j, t, s = 4, 5, 0.3, 0.8
    qa = db.aoa_deg[i] + t * 10.0
    qb = db.aos_deg[j] + s * 10.0
    expected = (
        (1 - t) * (1 - s) * db.Cf_G[i, j]
        + (1 - t) * s * db.Cf_G[i, j + 1]
        + t * (1 - s) * db.Cf_G[i + 1, j]
        + t * s * db.Cf_G[i + 1, j + 1]
    )
    np.testing.assert_allclose(
        bilinear(db.aoa_deg, db.aos_deg, db.Cf_G, [qa], [qb])[0], expected, atol=1e-15
    )


def test_load_and_forces(box, tmp_path):
    _, db = box
    lookup = CoefficientLookup.load(db.save(tmp_path / "box.npz"))
    r = lookup.coefficients(12.5, -7.5)
    q = 0.5 * 1e-11 * 7500.0**2
    np.testing.assert_allclose(r.force(q), q * db.reference_area * r.Cf_G)
    np.testing.assert_allclose(r.torque(q), q * db.reference_area * db.reference_length * r.Cm_G)
    assert lookup.error_bound == db.metadata["interpolation_error"]
