"""Solar radiation pressure against the Luthcke flat-plate closed forms (Montenbruck & Gill,
eq. 3.75)."""

import math

import numpy as np
import pytest

from adbsat_ros import (
    MaterialTable,
    PanelMethod,
    Reference,
    SurfaceProperties,
    example_satellite,
    panels_from_arrays,
)
from adbsat_ros.physics.facets import blend_sums
from adbsat_ros.physics.solar import solar_coefficients
from adbsat_ros.shading.lighting import LightingBlend
from adbsat_ros.shading.shader import make_shader

# One square plate (two triangles) of area 1 m^2 in the y-z plane with normal +x.
PLATE_V = np.array([[0, -0.5, -0.5], [0, 0.5, -0.5], [0, 0.5, 0.5], [0, -0.5, 0.5]], float)
PLATE_F = np.array([[0, 1, 2], [0, 2, 3]])


def plate_method(rho_s, rho_d):
    mesh = panels_from_arrays(PLATE_V, PLATE_F)
    surf = SurfaceProperties(specular_reflectivity=rho_s, diffuse_reflectivity=rho_d)
    return PanelMethod(mesh, "newton", surf, reference=Reference(area=1.0, length=1.0))


@pytest.mark.parametrize("theta_deg", [0.0, 30.0, 60.0])
@pytest.mark.parametrize("rho_s,rho_d", [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (0.3, 0.4)])
def test_plate_matches_luthcke(theta_deg, rho_s, rho_d):
    th = math.radians(theta_deg)
    to_sun = np.array([math.cos(th), math.sin(th), 0.0])
    n = np.array([1.0, 0.0, 0.0])
    c = math.cos(th)
    # F/(P A) = -cos(th) [(1 - rho_s) s + 2 (rho_s cos(th) + rho_d/3) n], s towards the sun
    expected = -c * ((1 - rho_s) * to_sun + 2 * (rho_s * c + rho_d / 3) * n)
    got = solar_coefficients(plate_method(rho_s, rho_d), to_sun)
    assert np.allclose(got.Cf_G, expected, atol=1e-12)
    assert got.area_lit == pytest.approx(c)


@pytest.mark.parametrize("theta", [1e-9, -1e-11])
def test_the_photons_sideways_push_is_kept_near_normal_incidence(theta):
    """Luthcke's plate a hair off the normal: the absorbed photons push along s, and the part of
    that across the normal, -(1 - rho_s) cos(th) sin(th), is kept where cos(th) rounds to 1 (a
    sine taken as sqrt(1 - cos^2) there would be 0)."""
    rho_s, rho_d = 0.3, 0.4
    to_sun = np.array([math.cos(theta), math.sin(theta), 0.0])
    got = solar_coefficients(plate_method(rho_s, rho_d), to_sun)
    assert got.Cf_G[1] == pytest.approx(-(1 - rho_s) * math.cos(theta) * math.sin(theta), rel=1e-6)
    assert got.Cf_G[0] == pytest.approx(-((1 - rho_s) + 2 * (rho_s + rho_d / 3)), rel=1e-12)


def test_plate_facing_away_from_the_sun_feels_nothing():
    got = solar_coefficients(plate_method(0.5, 0.3), np.array([-1.0, 0.2, 0.0]))
    assert np.allclose(got.Cf_G, 0.0) and got.area_lit == 0.0


def test_absorbing_plate_force_is_along_the_photons():
    got = solar_coefficients(plate_method(0.0, 0.0), np.array([1.0, 1.0, 0.0]))
    direction = got.Cf_G / np.linalg.norm(got.Cf_G)
    assert np.allclose(direction, -np.array([1.0, 1.0, 0.0]) / math.sqrt(2))


def test_bad_sun_direction():
    with pytest.raises(ValueError, match="sun_direction"):
        solar_coefficients(plate_method(0, 0), [0.0, 0.0, 0.0])


def test_facets_and_panels_give_the_same_solar_force():
    """The example satellite, its arrays reflecting differently from its body, the Sun oblique
    and the body's shadow on the arrays: summed per facet of coplanar panels or panel by panel,
    the same coefficients (to rounding)."""
    mesh = example_satellite()
    materials = MaterialTable(
        SurfaceProperties(specular_reflectivity=0.1, diffuse_reflectivity=0.2),
        {"solar_array": {"specular_reflectivity": 0.05, "diffuse_reflectivity": 0.02}},
    )
    sun = np.array([0.3, -0.9, 0.4])
    lighting = make_shader(mesh).lighting(-sun / np.linalg.norm(sun))
    assert lighting.shaded_index.size > 0
    results = []
    for grouped in (True, False):
        method = PanelMethod(mesh, "newton", materials, group_facets=grouped)
        assert (method.facets is not None) == grouped
        results.append(solar_coefficients(method, sun, lighting=lighting))
    facet, panel = results
    np.testing.assert_allclose(facet.Cf_G, panel.Cf_G, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(facet.Cm_G, panel.Cm_G, rtol=1e-12, atol=1e-15)
    assert facet.area_lit == pytest.approx(panel.area_lit, rel=1e-12)


def test_solar_pressure_from_facet_sums_is_that_of_their_lighting_bit_for_bit():
    """Given the facet sums of a lighting (one, or a blend of three by blend_sums), the solar
    coefficients are those given the lighting, bit for bit; the sums are what counts (those of
    no shadow give the unshaded result), and the result agrees with the panel-by-panel sums."""
    mesh = example_satellite()
    materials = MaterialTable(
        SurfaceProperties(specular_reflectivity=0.1, diffuse_reflectivity=0.2),
        {"solar_array": {"specular_reflectivity": 0.05, "diffuse_reflectivity": 0.02}},
    )
    method = PanelMethod(mesh, "newton", materials)
    panel_by_panel = PanelMethod(mesh, "newton", materials, group_facets=False)
    facets = method.facets
    shader = make_shader(mesh)
    sun = np.array([0.3, -0.9, 0.4])
    suns = [sun, sun + [0.02, 0.0, 0.01], sun - [0.0, 0.03, 0.02]]
    parts = [(w, shader.lighting(-s / np.linalg.norm(s))) for w, s in zip((0.5, 0.3, 0.2), suns)]
    blend = LightingBlend(parts)
    for lighting, sums in (
        (parts[0][1], facets.lit_sums_of(parts[0][1])),
        (blend, blend_sums([(w, facets.lit_sums_of(p)) for w, p in parts])),
    ):
        by_lighting = solar_coefficients(method, sun, aoa=0.1, lighting=lighting)
        for got in (
            solar_coefficients(method, sun, aoa=0.1, sums=sums),
            solar_coefficients(method, sun, aoa=0.1, lighting=lighting, sums=sums),
        ):
            for name in ("Cf_G", "Cm_G", "Cf_s", "Cm_S"):
                np.testing.assert_array_equal(getattr(got, name), getattr(by_lighting, name))
            assert got.area_lit == by_lighting.area_lit
        panel = solar_coefficients(panel_by_panel, sun, aoa=0.1, lighting=lighting)
        np.testing.assert_allclose(by_lighting.Cf_G, panel.Cf_G, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(by_lighting.Cm_G, panel.Cm_G, rtol=1e-12, atol=1e-15)
    unshaded = solar_coefficients(method, sun, lighting=parts[0][1], sums=facets.all_lit)
    np.testing.assert_array_equal(unshaded.Cf_G, solar_coefficients(method, sun).Cf_G)
    assert unshaded.area_lit > by_lighting.area_lit
