"""Shading cache: quantisation bound on the whole sphere, LRU behaviour, counters, precompute,
and the stated error bound of a cached answer on the cube-before-plate scene."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.mesh import panels_from_arrays
from adbsat_ros.geometry.shapes import grid_box
from adbsat_ros.shading.cache import ShadingCache, moved_lit_area
from adbsat_ros.shading.cube_map import cells_per_edge, direction_keys, key_centres
from adbsat_ros.shading.lighting import lit_projected_area
from adbsat_ros.shading.shader import make_shader


@pytest.fixture(scope="module")
def scene():
    """Cube 1 m at x = +2, plate 3 x 3 x 0.1 m at x = 0 (front face at x = +0.05)."""
    v1, f1 = grid_box((2.0, 0.0, 0.0), (1.0, 1.0, 1.0), (2, 2, 2))
    v2, f2 = grid_box((0.0, 0.0, 0.0), (0.1, 3.0, 3.0), (1, 25, 25))
    return panels_from_arrays(
        np.vstack([v1, v2]), np.vstack([f1, f2 + len(v1)]), source="cube+plate"
    )


@pytest.fixture(scope="module")
def shader(scene):
    return make_shader(scene)


def _angles_deg(u, c):
    return np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", u, c), -1.0, 1.0)))


@pytest.mark.parametrize("resolution_deg", [0.5, 1.0, 2.0, 7.3, 45.0])
def test_quantisation_error_bounded_everywhere(resolution_deg):
    n = cells_per_edge(resolution_deg)
    step = 90.0 / n
    assert step <= resolution_deg + 1e-12
    rng = np.random.default_rng(0)
    u = rng.normal(size=(100_000, 3))
    # poles, axis directions, cube-map edges and corners, near-pole directions
    special = [
        [0, 0, 1],
        [0, 0, -1],
        [1, 0, 0],
        [-1, 0, 0],
        [0, 1, 0],
        [0, -1, 0],
        [1, 1, 0],
        [1, 0, -1],
        [0, 1, 1],
        [1, 1, 1],
        [-1, -1, -1],
        [1, 1, -1],
        [1e-9, 0, 1],
        [0, 1e-12, -1],
        [1, 1 - 1e-12, 0],
    ]
    u = np.vstack([u, special])
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    c = key_centres(direction_keys(u, n), n)
    ang = _angles_deg(u, c)
    assert ang.max() <= step * (1 + 1e-9)
    # the proof's bound is not far from tight (measured ~0.79 step)
    assert ang.max() > 0.6 * step
    # near the poles the cells are as small as elsewhere
    polar = np.abs(u[:, 2]) > 0.99
    assert ang[polar].max() <= step


@pytest.mark.parametrize("resolution_deg", [0.25, 1.0, 2.0, 30.0, 45.0, 90.0])
def test_axis_directions_are_cell_centres(resolution_deg):
    """n is odd, so a flow along a body axis (plus rounding-level noise) stays in the cell
    centred on that axis and is shaded exactly for it."""
    n = cells_per_edge(resolution_deg)
    assert n % 2 == 1 and 90.0 / n <= resolution_deg
    axes = np.vstack([np.eye(3), -np.eye(3)])
    np.testing.assert_allclose(key_centres(direction_keys(axes, n), n), axes, atol=1e-15)
    rng = np.random.default_rng(7)
    for axis in axes:
        noisy = axis + 1e-9 * rng.normal(size=(200, 3))
        assert len(np.unique(direction_keys(noisy, n))) == 1


def test_keys_and_centres_round_trip():
    n = cells_per_edge(10.0)
    keys = np.arange(6 * n * n)
    centres = key_centres(keys, n)
    assert np.allclose(np.linalg.norm(centres, axis=1), 1.0)
    np.testing.assert_array_equal(direction_keys(centres, n), keys)
    # scalar forms agree with the vector ones
    assert int(direction_keys(centres[17], n)) == 17
    np.testing.assert_allclose(key_centres(17, n), centres[17])
    with pytest.raises(ValueError):
        key_centres(6 * n * n, n)
    with pytest.raises(ValueError):
        cells_per_edge(0.0)


def test_per_query_key_equals_vectorised_keys(shader):
    """ShadingCache.key (plain floats, the node's per-message path) equals direction_keys, also on
    cell edges, cube edges and corners where ties between axes decide the face."""
    rng = np.random.default_rng(3)
    u = rng.normal(size=(2000, 3))
    edges = np.array(
        [[1, 1, 0], [1, -1, 1], [-1, -1, -1], [0, 0, -1], [1, 0, 0], [0.5, 0.5, -0.5]], float
    )
    u = np.vstack([u, edges, key_centres(np.arange(24), 2)])
    for resolution in (0.25, 1.0, 7.5):
        cache = ShadingCache(shader, resolution_deg=resolution)
        np.testing.assert_array_equal([cache.key(v) for v in u], direction_keys(u, cache.n))


def test_hits_misses_and_lru(shader):
    cache = ShadingCache(shader, resolution_deg=2.0, max_entries=2)
    ua = frames.flow_direction(math.radians(10.0), 0.0)
    ua2 = frames.flow_direction(math.radians(10.3), math.radians(0.2))  # same 2 deg cell?
    ub = frames.flow_direction(math.radians(-20.0), math.radians(5.0))
    uc = frames.flow_direction(math.radians(30.0), math.radians(-15.0))
    assert cache.key(ua) != cache.key(ub) != cache.key(uc) != cache.key(ua)
    same_cell = cache.key(ua) == cache.key(ua2)
    cache.lighting(ua)
    assert (cache.hits, cache.misses) == (0, 1)
    cache.lighting(ua)
    assert (cache.hits, cache.misses) == (1, 1)
    cache.lighting(ua2)
    assert cache.hits == (2 if same_cell else 1)
    cache.lighting(ub)  # store: a, b
    cache.lighting(ua)  # a most recent
    cache.lighting(uc)  # evicts b (least recently used), not a
    assert len(cache) == 2 and cache.evictions >= 1
    assert cache.key(ua) in cache and cache.key(uc) in cache and cache.key(ub) not in cache
    misses = cache.misses
    cache.lighting(ua)
    assert cache.misses == misses
    cache.lighting(ub)
    assert cache.misses == misses + 1
    info = cache.info()
    assert info["size"] == 2 and info["max_entries"] == 2 and info["hits"] == cache.hits
    cache.clear()
    assert len(cache) == 0 and cache.hits == cache.misses == cache.evictions == 0
    with pytest.raises(ValueError):
        ShadingCache(shader, max_entries=0)


def test_cached_answer_is_the_cell_centre_shading(shader, scene):
    cache = ShadingCache(shader, resolution_deg=1.0, max_entries=3)
    u = frames.flow_direction(math.radians(8.4), math.radians(-3.3))
    got = cache.lighting(u)
    assert cache.last_keys == (cache.key(u),)
    ref = shader.lighting(cache.centre(cache.key(u)))
    np.testing.assert_array_equal(got.lit_fraction, ref.lit_fraction)
    np.testing.assert_array_equal(got.shift_index, ref.shift_index)
    np.testing.assert_allclose(got.shift, ref.shift)
    assert got.shaded_index.size > 0  # the direction does throw a shadow on the plate
    # every query in a stored cell gets the stored lighting itself, also after other cells
    assert cache.lighting(u) is got
    back = cache.lighting(-u)
    assert cache.last_keys == (cache.key(-u),) != (cache.key(u),)
    assert cache.lighting(u) is got and cache.lighting(-u) is back
    assert (cache.hits, cache.misses, cache.evictions) == (3, 2, 0)
    # three other cells later (max_entries = 3), u's cell was evicted: shaded again, same answer
    others = [
        frames.flow_direction(math.radians(8.4 + 3.0 * k), math.radians(20.0)) for k in range(3)
    ]
    for v in others:
        cache.lighting(v)
    assert cache.key(u) not in cache and cache.evictions == 2
    again = cache.lighting(u)
    assert again is not got
    np.testing.assert_array_equal(again.lit_fraction, ref.lit_fraction)
    np.testing.assert_array_equal(again.shift_index, ref.shift_index)
    np.testing.assert_allclose(again.shift, ref.shift)
    assert (cache.hits, cache.misses, cache.evictions) == (3, 6, 3)
    # what callers get is read-only, so nobody can corrupt the cache through it
    for lighting in (got, again):
        for array in (lighting.shaded_fraction, lighting.shaded_index, lighting.shift):
            with pytest.raises(ValueError):
                array[...] = 0
        with pytest.raises(ValueError):
            lighting.lit_fraction[:] = 0.0
    np.testing.assert_array_equal(cache.lighting(u).lit_fraction, ref.lit_fraction)


def test_counters_and_the_bound(shader):
    """hits + misses = queries; the store never exceeds max_entries; evictions = cells computed
    beyond the bound; info() reports them; clear() resets them."""
    cache = ShadingCache(shader, resolution_deg=5.0, max_entries=4)
    rng = np.random.default_rng(8)
    u = rng.normal(size=(300, 3))
    queries = np.vstack([np.repeat(u[:30], 2, axis=0), u])  # 30 cells asked twice in a row
    keys = []
    for k, v in enumerate(queries):
        cache.lighting(v)
        keys.append(cache.key(v))
        assert len(cache) <= 4
        assert cache.hits + cache.misses == k + 1
    info = cache.info()
    assert info == {
        "hits": cache.hits,
        "misses": cache.misses,
        "evictions": cache.misses - 4,
        "size": 4,
        "max_entries": 4,
        "n": cache.n,
        "step_deg": pytest.approx(90.0 / cache.n),
    }
    assert cache.hits >= 30 and cache.misses > 4
    assert all(key in cache for key in keys[-1:])  # the latest cell is stored
    unbounded = ShadingCache(shader, resolution_deg=5.0, max_entries=None)
    for v in queries:
        unbounded.lighting(v)
    assert unbounded.evictions == 0 and len(unbounded) == len(set(keys)) == unbounded.misses
    cache.clear()
    assert (len(cache), cache.hits, cache.misses, cache.evictions, cache.last_keys) == (
        0,
        0,
        0,
        0,
        (),
    )
    with pytest.raises(ValueError, match="flow direction must be a finite non-zero 3-vector"):
        cache.lighting([0.0, np.nan, 1.0])


def test_precompute_grid(shader):
    cache = ShadingCache(shader, resolution_deg=2.0)
    aoa, aos = np.meshgrid(
        np.radians(np.arange(-10.0, 10.1, 2.0)), np.radians(np.arange(-4.0, 4.1, 2.0))
    )
    dirs = frames.flow_direction(aoa.ravel(), aos.ravel())
    n_cells = len(np.unique(direction_keys(dirs, cache.n)))
    assert cache.precompute(dirs) == n_cells
    assert len(cache) == n_cells
    assert cache.precompute(dirs) == 0  # nothing new
    assert (cache.hits, cache.misses) == (0, 0)
    for u in dirs:
        cache.lighting(u)
    assert (cache.hits, cache.misses) == (len(dirs), 0)
    # whole sphere at a coarse resolution, with a bound smaller than the grid: LRU keeps the last
    coarse = ShadingCache(shader, resolution_deg=30.0, max_entries=20)
    assert coarse.n_cells == 54
    assert coarse.precompute() == 54
    assert len(coarse) == 20 and coarse.evictions == 34
    np.testing.assert_allclose(np.linalg.norm(coarse.grid_directions(), axis=1), 1.0)


@pytest.mark.parametrize("resolution_deg", [0.5, 2.0])
def test_cached_answers_stay_within_stated_bound(shader, scene, resolution_deg):
    cache = ShadingCache(shader, resolution_deg=resolution_deg)
    rng = np.random.default_rng(3)
    worst_ratio = 0.0
    moved = []
    for k in range(24):
        # mostly flows that throw the cube's shadow on the plate, some anywhere
        u = (
            rng.normal(size=3)
            if k % 4 == 0
            else np.array([-1.0, 0.0, 0.0]) + 0.4 * rng.normal(size=3)
        )
        u /= np.linalg.norm(u)
        cached = cache.lighting(u)
        exact = shader.lighting(u)
        bound = cache.area_error_bound(u, cached)
        e = moved_lit_area(scene, u, cached, exact)
        d_area = abs(lit_projected_area(scene, u, cached) - lit_projected_area(scene, u, exact))
        assert d_area <= e + 1e-12
        assert e <= bound
        worst_ratio = max(worst_ratio, e / bound)
        moved.append(e)
    # the directions do move the shadow (the check is not empty) ...
    assert worst_ratio > 0.005
    # ... and the error shrinks with the resolution: mean moved area < 1 % of the lit area
    # (~9 m^2) per degree of resolution (measured ~0.2 % per degree)
    assert np.mean(moved) < 0.01 * 9.0 * resolution_deg
