"""The interpolating shading cache: the triangles over the cube-map cell centres cover the sphere
once, the weights reproduce the direction and vary continuously (across cube edges and corners
too), and a blend of lightings gives the weighted mean of the panel method's results."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh

from adbsat_ros.geometry.example_satellite import example_satellite
from adbsat_ros.geometry.mesh import panels_from_arrays
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.shading.cache import ShadingCache
from adbsat_ros.shading.cell_triangles import CellTriangulation
from adbsat_ros.shading.cube_map import key_centres
from adbsat_ros.shading.lighting import LightingBlend, PanelLighting
from adbsat_ros.shading.shader import make_shader

FLOW = FreeStream(speed=7600.0, temperature=900.0, mean_mass_amu=16.0)


def hard_directions(count: int = 3000) -> np.ndarray:
    """Random directions, half of them pressed against cube edges and corners."""
    rng = np.random.default_rng(7)
    u = rng.normal(size=(count, 3))
    edge = u[: count // 4].copy()
    edge[:, 1] = (
        np.sign(edge[:, 1]) * np.abs(edge[:, 0]) * (1.0 + 1e-4 * rng.normal(size=len(edge)))
    )
    corner = np.sign(u[count // 4 : count // 2]) * (1.0 + 1e-3 * rng.normal(size=(count // 4, 3)))
    return np.vstack([u, edge, corner])


@pytest.mark.parametrize("n", [1, 2, 3, 7, 91])
def test_the_triangles_close_the_sphere(n):
    """12 n^2 - 4 triangles over 6 n^2 centres (Euler: F = 2 V - 4), every edge in exactly two,
    and none repeated."""
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    k00 = (i * n + j).reshape(-1)  # a face's triangles, as CellTriangulation.locate takes them
    face = np.concatenate(
        [np.stack([k00, k00 + n, k00 + n + 1], 1), np.stack([k00, k00 + n + 1, k00 + 1], 1)]
    )
    border = CellTriangulation(n).border_triangles
    triangles = np.concatenate([*(face + f * n * n for f in range(6)), border])
    assert len(triangles) == 12 * n * n - 4
    assert set(np.unique(triangles).tolist()) == set(range(6 * n * n))
    edges = np.sort(
        np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1
    )
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert set(counts.tolist()) == {2}
    assert len(np.unique(np.sort(triangles, axis=1), axis=0)) == len(triangles)


@pytest.mark.parametrize("n", [1, 3, 9, 361])
def test_every_direction_is_a_convex_combination_of_its_three_centres(n):
    """Weights >= 0 summing to 1, and sum w_k c_k points along u (the barycentric coordinates
    in the right triangle), cube edges and corners included; the centres lie within 2 steps."""
    triangulation = CellTriangulation(n)
    step = 0.5 * math.pi / n
    for u in hard_directions(1500):
        keys, weights = triangulation.locate(*u.tolist())
        assert min(weights) >= 0.0 and sum(weights) == pytest.approx(1.0, abs=1e-12)
        centres = key_centres(np.array(keys), n)
        point = np.array(weights) @ centres
        unit = u / np.linalg.norm(u)
        assert np.linalg.norm(np.cross(point / np.linalg.norm(point), unit)) < 1e-9
        assert np.arccos(np.clip(centres @ unit, -1, 1)).max() <= 2.0 * step


def test_a_centre_is_its_own_answer_and_a_linear_function_is_reproduced():
    n = 9
    triangulation = CellTriangulation(n)
    for key in (0, 40, 6 * n * n - 1, 3 * n * n + 7):
        keys, weights = triangulation.locate(*key_centres(key, n).tolist())
        assert dict(zip(keys, weights, strict=True)).get(key) == pytest.approx(1.0, abs=1e-12)
    a = np.array([0.3, -1.2, 0.7])  # f(u) = a . u / s is linear in the triangle's plane
    for u in hard_directions(300):
        keys, weights = triangulation.locate(*u.tolist())
        centres = key_centres(np.array(keys), n)
        point = np.array(weights) @ centres
        assert np.array(weights) @ (centres @ a) == pytest.approx(point @ a, abs=1e-12)


def test_the_weights_are_continuous_across_cube_edges_and_corners():
    """Values at the cell centres, blended along great circles through a cube edge and close to
    a corner: between points 1e-5 rad apart the blend moves by at most a Lipschitz bound of the
    values (no jump where the triangle changes), while the nearest centre's value jumps."""
    n = 15
    triangulation = CellTriangulation(n)
    values = np.random.default_rng(3).uniform(0.0, 1.0, 6 * n * n)
    step = 0.5 * math.pi / n
    for start, end in (([1, 0.2, 0.1], [0.1, 1, 0.3]), ([1, 0.97, 0.95], [0.95, 1, 1.02])):
        a, b = np.array(start, float), np.array(end, float)
        blended, nearest = [], []
        for t in np.linspace(0.0, 1.0, 20001):
            keys, weights = triangulation.locate(*((1 - t) * a + t * b).tolist())
            blended.append(np.dot(weights, values[list(keys)]))
            nearest.append(values[keys[int(np.argmax(weights))]])
        angle = math.acos(a @ b / np.linalg.norm(a) / np.linalg.norm(b)) / 20000
        lipschitz = 4.0 / step  # values in [0, 1], triangles about one step across
        assert np.abs(np.diff(blended)).max() <= lipschitz * angle
        assert np.abs(np.diff(nearest)).max() > 10 * lipschitz * angle


def two_spheres():
    """A sphere in the wake of another: shading, and no coplanar panels (the panel-by-panel
    path)."""
    front = trimesh.creation.icosphere(subdivisions=3, radius=0.5)
    back = front.copy()
    back.apply_translation([1.5, 0.2, 0.0])
    both = trimesh.util.concatenate([front, back])
    return panels_from_arrays(both.vertices, both.faces)


@pytest.mark.parametrize("mesh", [example_satellite(), two_spheres()], ids=["facets", "panels"])
def test_a_blend_gives_the_weighted_mean_of_its_parts_results(mesh):
    """On the facet path (a satellite of flat faces) and the panel-by-panel path (a sphere)."""
    method = PanelMethod(mesh, "sentman")
    shader = make_shader(mesh, mode="raycast", samples=16)
    u = np.array([-1.0, 0.3, 0.15]) / np.linalg.norm([-1.0, 0.3, 0.15])
    parts = [
        (0.5, shader.lighting(u)),
        (0.3, shader.lighting(u + [0.0, 0.02, 0.0])),
        (0.2, shader.lighting(u + [0.0, 0.0, 0.02])),
    ]
    assert parts[0][1].shaded_index.size > 0
    blend = LightingBlend.of(parts)
    result = method.coefficients(FLOW, flow_direction=u, lighting=blend)
    for name in ("Cf_G", "Cm_G"):
        mean = sum(
            w * getattr(method.coefficients(FLOW, flow_direction=u, lighting=p), name)
            for w, p in parts
        )
        np.testing.assert_allclose(getattr(result, name), mean, rtol=1e-12, atol=1e-15)
    assert np.all((blend.lit_fraction >= 0.0) & (blend.lit_fraction <= 1.0))
    combined = method.coefficients(FLOW, flow_direction=u, lighting=blend.combined)
    np.testing.assert_allclose(combined.Cm_G, result.Cm_G, rtol=1e-12, atol=1e-15)


def test_blends_refuse_bad_weights_and_mixed_meshes():
    one, two = PanelLighting(np.ones(4)), PanelLighting(np.ones(5))
    assert LightingBlend.of([(1.0, one)]) is one
    with pytest.raises(ValueError, match="sum to 1"):
        LightingBlend([(0.5, one), (0.4, one)])
    with pytest.raises(ValueError, match="positive"):
        LightingBlend([(1.5, one), (-0.5, one)])
    with pytest.raises(ValueError, match="panel count"):
        LightingBlend([(0.5, one), (0.5, two)])


def test_the_interpolating_cache_counts_the_cells_it_reads_and_bounds_its_error():
    mesh = example_satellite()
    shader = make_shader(mesh, mode="raycast", samples=16)
    cache = ShadingCache(shader, resolution_deg=1.0, interpolate=True)
    u = np.array([-1.0, 0.3, 0.15])
    lighting = cache.lighting(u)
    assert isinstance(lighting, LightingBlend) and len(cache.last_keys) == 3
    assert (cache.misses, cache.hits) == (3, 0)
    cache.lighting(u * 2.0)
    assert (cache.misses, cache.hits) == (3, 3)
    assert cache.lighting(cache.centre(cache.last_keys[0])) is not None
    exact = shader.lighting(u / np.linalg.norm(u))
    from_cache = np.abs(lighting.lit_fraction - exact.lit_fraction) @ (
        mesh.areas * np.maximum(-(mesh.normals @ (u / np.linalg.norm(u))), 0.0)
    )
    assert from_cache <= cache.area_error_bound(u, lighting)
