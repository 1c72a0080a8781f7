"""Evaluating coplanar panels once per facet gives what evaluating every panel gives.

The identity used (panel_method module docstring): panels with one normal and one material share
c, cp and ctau, so sum_i f_i A_i phi = W phi and sum_i f_i A_i r_i x phi = Q x phi. The reference
is the same PanelMethod with ``group_facets=False`` (the fast path against the reference path);
agreement is to rounding (1e-12 relative).
"""

import math

import numpy as np
import pytest
import trimesh

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.example_satellite import example_satellite
from adbsat_ros.geometry.loading import panels_from_trimesh
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.facets import blend_sums
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.gsi_models import ModelOptions
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.physics.surface import MaterialTable, PanelSurface, SurfaceProperties
from adbsat_ros.shading.lighting import LightingBlend, PanelLighting
from adbsat_ros.shading.shader import make_shader

SPECIES = {"He": 5e12, "O": 3e15, "N2": 1.5e15, "O2": 8e13, "Ar": 1e11, "H": 2e11, "N": 2e13}
FLOW = FreeStream(speed=7700.0, temperature=900.0, number_densities=SPECIES)


@pytest.fixture(scope="module")
def satellite():
    return example_satellite()


@pytest.fixture(scope="module")
def shader(satellite):
    return make_shader(satellite, mode="raycast")


def pair(mesh, model, **kwargs):
    arrays = {"solar_array": {"alpha": 0.8, "wall_temperature": 350.0}}
    materials = MaterialTable(
        SurfaceProperties(alpha=0.93, alpha_n=0.9, sigma_t=0.95, sigma_n=0.9),
        {name: v for name, v in arrays.items() if name in mesh.material_names},
    )
    ref = Reference(moment_point=(0.1, -0.05, 0.02))
    return (
        PanelMethod(mesh, model, materials, reference=ref, **kwargs),
        PanelMethod(mesh, model, materials, reference=ref, group_facets=False, **kwargs),
    )


def assert_same(a, b):
    scale_f = np.linalg.norm(b.Cf_G)
    scale_m = max(np.linalg.norm(b.Cm_G), 1e-3 * scale_f)
    np.testing.assert_allclose(a.Cf_G, b.Cf_G, rtol=0, atol=1e-12 * scale_f)
    np.testing.assert_allclose(a.Cm_G, b.Cm_G, rtol=0, atol=1e-12 * scale_m)
    assert a.area_projected == pytest.approx(b.area_projected, rel=1e-12)
    for name in ("cos_delta", "cp", "ctau"):
        np.testing.assert_allclose(getattr(a, name), getattr(b, name), rtol=1e-12, atol=1e-15)


def test_the_example_satellite_has_few_facets(satellite):
    grouped, panel_by_panel = pair(satellite, "sentman")
    assert grouped.facets is not None and panel_by_panel.facets is None
    assert grouped.facets.n < satellite.n_panels / 20
    # every facet is coplanar-facing and of one material
    f = grouped.facets
    assert np.abs(satellite.normals - f.normals[f.index]).max() < 1e-11
    assert np.all(satellite.material_index == satellite.material_index[f.first][f.index])


@pytest.mark.parametrize(
    "model", ["sentman", "newton", "cook", "schaaf", "storch", "maxwell", "cll", "dria"]
)
def test_facets_equal_panels_with_raycast_shading(satellite, shader, model):
    grouped, panel_by_panel = pair(satellite, model)
    for aoa, aos in ((0.0, 0.0), (10.0, 5.0), (-20.0, 30.0), (75.0, -40.0), (180.0, 0.0)):
        u = frames.flow_direction(math.radians(aoa), math.radians(aos))
        lighting = shader.lighting(u)
        a = grouped.coefficients(FLOW, math.radians(aoa), math.radians(aos), lighting=lighting)
        b = panel_by_panel.coefficients(
            FLOW, math.radians(aoa), math.radians(aos), lighting=lighting
        )
        assert_same(a, b)
        # the plates see c unclipped (|c| <= 1 to rounding); what is reported is a cosine, and a
        # face head-on (aoa 0 and 180: sin(delta) = 0, to the rounding of the direction made
        # from the angles, sin(pi) = 1.2e-16) carries no shear beyond that rounding
        assert np.all(np.abs(a.cos_delta) <= 1.0)
        assert np.all(np.abs(a.ctau[np.abs(a.cos_delta) == 1.0]) <= 1e-15)
    assert lighting.shift_index.size > 0 or model  # some attitudes above have partly lit panels


def test_partly_lit_panels_with_shifts_and_a_surface_override(satellite, shader):
    grouped, panel_by_panel = pair(satellite, "sentman")
    u = frames.flow_direction(math.radians(-20.0), math.radians(30.0))
    lighting = shader.lighting(u)
    assert lighting.shift_index.size > 0 and np.any(lighting.lit_fraction == 0.0)
    surface = grouped.surface_with(alpha=0.7, alpha_n=0.7)
    a = grouped.coefficients(FLOW, flow_direction=u, lighting=lighting, surface=surface)
    b = panel_by_panel.coefficients(FLOW, flow_direction=u, lighting=lighting, surface=surface)
    assert_same(a, b)
    # a surface that varies inside a facet falls back to panel-by-panel evaluation, still right
    alpha = np.full(satellite.n_panels, 0.9)
    alpha[::7] = 0.6
    values = {
        name: getattr(grouped.surface, name)
        for name in (
            "alpha_n",
            "sigma_n",
            "sigma_t",
            "wall_temperature",
            "specular_reflectivity",
            "diffuse_reflectivity",
        )
    }
    odd = PanelSurface(alpha=alpha, **values)
    assert grouped.facets.surface_of(odd) is None
    assert_same(
        grouped.coefficients(FLOW, flow_direction=u, lighting=lighting, surface=odd),
        panel_by_panel.coefficients(FLOW, flow_direction=u, lighting=lighting, surface=odd),
    )


def test_the_sums_of_a_lighting_stay_right(satellite, shader):
    """The facet sums follow the lighting given: the same one gives the same numbers; another
    (even made from the caller's array changed in between) gives its own, panel by panel's."""
    grouped, panel_by_panel = pair(satellite, "sentman")
    u = frames.flow_direction(math.radians(10.0), math.radians(5.0))
    lighting = shader.lighting(u)
    first = grouped.coefficients(FLOW, flow_direction=u, lighting=lighting)
    again = grouped.coefficients(FLOW, flow_direction=u, lighting=lighting)
    np.testing.assert_array_equal(again.Cf_G, first.Cf_G)
    np.testing.assert_array_equal(again.Cm_G, first.Cm_G)
    assert_same(first, panel_by_panel.coefficients(FLOW, flow_direction=u, lighting=lighting))
    # a lighting cannot change under its holders: its arrays are read-only
    with pytest.raises(ValueError):
        lighting.shaded_fraction[:] = 0.0
    f = np.array(lighting.lit_fraction)
    f[: satellite.n_panels // 2] = 0.0
    darker = PanelLighting(f, lighting.shift_index, lighting.shift)
    second = grouped.coefficients(FLOW, flow_direction=u, lighting=darker)
    assert_same(second, panel_by_panel.coefficients(FLOW, flow_direction=u, lighting=darker))
    assert not np.allclose(first.Cf_G, second.Cf_G)


def test_lit_facet_sums_equal_panel_by_panel_sums_for_shaded_lightings(satellite, shader):
    """Facets.lit_sums against the sums written out per panel: W_g = sum f_i A_i,
    Q_g = sum f_i A_i (r_i + s_i), W_g n_g, Q_g x n_g, for ray-cast lightings and for random
    ones (lit fractions 0, 1 and between, shifts on the partly lit panels)."""
    grouped, _ = pair(satellite, "sentman")
    facets = grouped.facets
    rng = np.random.default_rng(12)
    n = satellite.n_panels
    lightings = [
        shader.lighting(frames.flow_direction(a, b)) for a, b in ((-0.5, -0.35), (0.3, 0.5))
    ]
    for _ in range(3):
        f = rng.choice([0.0, 1.0, 0.3], size=n, p=[0.2, 0.6, 0.2]) * rng.uniform(0.2, 1.0, n)
        f[f > 0.99] = 1.0
        part = np.flatnonzero((f > 0.0) & (f < 1.0))
        shift = 0.01 * rng.normal(size=(part.size, 3))
        lightings.append(PanelLighting(f, part, shift))
    for lighting in lightings:
        assert lighting.shaded_index.size > 0 and lighting.shift_index.size > 0
        f = lighting.lit_fraction
        points = satellite.barycentres.copy()
        points[lighting.shift_index] += lighting.shift
        w = f * satellite.areas
        W = np.zeros(facets.n)
        Q = np.zeros((facets.n, 3))
        np.add.at(W, facets.index, w)
        np.add.at(Q, facets.index, w[:, None] * points)
        expected = np.column_stack([W, W[:, None] * facets.normals, Q, np.cross(Q, facets.normals)])
        np.testing.assert_allclose(facets.lit_sums(lighting), expected, rtol=0, atol=1e-13)
        np.testing.assert_allclose(
            facets.lit_sums(None)[:, 0], np.bincount(facets.index, satellite.areas), rtol=1e-14
        )


def test_a_sphere_is_evaluated_panel_by_panel():
    sphere = panels_from_trimesh(trimesh.creation.icosphere(subdivisions=3, radius=0.5))
    grouped, _ = pair(sphere, "sentman")
    assert grouped.facets is None


@pytest.mark.parametrize(
    "model", ["sentman", "schaaf", "maxwell", "maxwell_adbsat", "newton", "cll", "dria"]
)
def test_facets_equal_panels_for_each_flow_lighting_and_surface(satellite, shader, model):
    """Directions each with its own free stream, lighting (or none) and surface (or the
    materials'), some not unit length and one along an axis (facets exactly grazing): the facet
    sums give what the panel-by-panel sums give, and the direction is normalised either way."""
    options = ModelOptions(adbsat_compat=model.endswith("_adbsat"))
    grouped, panel_by_panel = pair(satellite, model.removesuffix("_adbsat"), options=options)
    rng = np.random.default_rng(3)
    m = 7
    flows = [
        FreeStream(
            speed=float(rng.uniform(6500.0, 8000.0)),
            temperature=float(rng.uniform(600.0, 1400.0)),
            number_densities=SPECIES,
        )
        for _ in range(m)
    ]
    directions = [rng.standard_normal(3) * rng.uniform(0.5, 2.0) for _ in range(m)]
    directions[2] = np.array([-1.0, 0.0, 0.0])  # along an axis: some facets exactly grazing
    lightings = [
        shader.lighting(d / np.linalg.norm(d)) if k % 3 else None for k, d in enumerate(directions)
    ]
    surfaces = [grouped.surface_with(alpha=0.7 + 0.04 * k) if k % 2 else None for k in range(m)]
    results = []
    for flow, d, lighting, surface in zip(flows, directions, lightings, surfaces):
        got = grouped.coefficients(flow, flow_direction=d, lighting=lighting, surface=surface)
        ref = panel_by_panel.coefficients(
            flow, flow_direction=d, lighting=lighting, surface=surface
        )
        assert_same(got, ref)
        np.testing.assert_allclose(got.flow_direction, d / np.linalg.norm(d), rtol=0, atol=1e-16)
        results.append(got)
    assert len({tuple(c.Cf_G) for c in results}) == m  # the directions did differ
    with pytest.raises(ValueError, match="flow_direction must be a finite non-zero 3-vector"):
        grouped.coefficients(flows[0], flow_direction=[0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="lighting has 5 panels, the mesh has"):
        grouped.coefficients(
            flows[0], flow_direction=directions[0], lighting=PanelLighting.all_lit(5)
        )


def assert_identical(a, b):
    """Two results equal bit for bit (totals, per-panel values, flow, angles, lighting)."""
    for name in ("Cf_G", "Cm_G", "Cf_w", "Cm_w", "flow_direction", "cos_delta", "cp", "ctau"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert (a.area_projected, a.aoa, a.aos) == (b.area_projected, b.aoa, b.aos)
    assert a.lighting is b.lighting


@pytest.mark.parametrize("model", ["sentman", "cll", "maxwell"])
def test_coefficients_of_sums_are_coefficients_bit_for_bit(satellite, shader, model):
    """The entry from facet sums (lit_sums_of, a pure function of the lighting) gives what
    coefficients(lighting=...) gives, bit for bit, for angles and for directions, with and
    without a lighting and a surface override, and again once the sums are cached; a method
    without facets (group_facets=False) the same from its lighting alone."""
    grouped, panel_by_panel = pair(satellite, model)
    facets = grouped.facets
    for k, (aoa, aos) in enumerate(((0.0, 0.0), (-20.0, 30.0), (75.0, -40.0), (180.0, 0.0))):
        angles = (math.radians(aoa), math.radians(aos))
        u, _ = frames.attitude_flow(*angles)
        lighting = shader.lighting(u) if k else None
        surface = grouped.surface_with(alpha=0.7) if k % 2 else None
        sums = facets.lit_sums_of(lighting)
        assert not sums.flags.writeable
        np.testing.assert_array_equal(sums, facets.lit_sums_of(lighting))  # pure
        got = grouped.coefficients_of_sums(FLOW, u, angles, sums, lighting, surface)
        for _ in range(2):  # the second time through the facets' sums cache
            assert_identical(
                got, grouped.coefficients(FLOW, *angles, lighting=lighting, surface=surface)
            )
        d = 2.5 * u
        by_direction = grouped.coefficients(
            FLOW, flow_direction=d, lighting=lighting, surface=surface
        )
        u_d, _ = frames.attitude_flow(direction=d)
        assert_identical(
            by_direction, grouped.coefficients_of_sums(FLOW, u_d, None, sums, lighting, surface)
        )
        assert_identical(
            panel_by_panel.coefficients(FLOW, *angles, lighting=lighting, surface=surface),
            panel_by_panel.coefficients_of_sums(FLOW, u, angles, None, lighting, surface),
        )
        assert_same(
            got, panel_by_panel.coefficients(FLOW, *angles, lighting=lighting, surface=surface)
        )


def test_coefficients_of_sums_of_a_body_without_facets_use_the_lighting():
    """A sphere has no facets: its sums are None and the lighting is summed panel by panel."""
    sphere = panels_from_trimesh(trimesh.creation.icosphere(subdivisions=2, radius=0.5))
    method = PanelMethod(sphere, "sentman")
    assert method.facets is None
    d = [-1.0, 0.3, 0.2]
    u, _ = frames.attitude_flow(direction=d)
    f = np.linspace(0.0, 1.0, sphere.n_panels)
    lighting = PanelLighting(f, np.arange(1, 4), np.full((3, 3), 0.01))
    got = method.coefficients_of_sums(FLOW, u, None, None, lighting)
    assert_identical(got, method.coefficients(FLOW, flow_direction=d, lighting=lighting))
    unshaded = method.coefficients_of_sums(FLOW, u, None, None, None)
    assert unshaded.area_projected > got.area_projected


@pytest.mark.parametrize("weights", [(1.0,), (0.5, 0.3, 0.2)])
def test_a_blends_sums_are_its_parts_sums_in_part_order(satellite, shader, weights):
    """blend_sums of 1 and 3 parts: w_0 s_0 + w_1 s_1 + ... in part order, bit for bit; what the
    facets' lit_sums give for the blend; the sums of the blend's combined lighting to rounding
    (the sums are linear in the lit fractions and shifts); and through coefficients_of_sums what
    coefficients(lighting=blend) gives, bit for bit."""
    grouped, panel_by_panel = pair(satellite, "sentman")
    facets = grouped.facets
    directions = [(-0.35, 0.5), (-0.3, 0.55), (-0.4, 0.45)][: len(weights)]
    parts = [(w, shader.lighting(frames.flow_direction(*d))) for w, d in zip(weights, directions)]
    blend = LightingBlend(parts)
    part_sums = [(w, facets.lit_sums_of(p)) for w, p in parts]
    sums = blend_sums(part_sums)
    expected = part_sums[0][0] * part_sums[0][1]
    for w, s in part_sums[1:]:
        expected = expected + w * s
    np.testing.assert_array_equal(sums, expected)
    np.testing.assert_array_equal(sums, facets.lit_sums(blend))
    if len(parts) == 1:
        np.testing.assert_array_equal(sums, facets.lit_sums_of(parts[0][1]))
    else:
        combined = facets.lit_sums_of(blend.combined)
        np.testing.assert_allclose(sums, combined, rtol=0, atol=1e-13 * np.abs(combined).max())
        assert not np.array_equal(part_sums[0][1], part_sums[1][1])  # the parts did differ
    u, angles = frames.attitude_flow(-0.35, 0.5)
    got = grouped.coefficients_of_sums(FLOW, u, angles, sums, blend)
    assert_identical(got, grouped.coefficients(FLOW, -0.35, 0.5, lighting=blend))
    assert_same(got, panel_by_panel.coefficients(FLOW, -0.35, 0.5, lighting=blend))
