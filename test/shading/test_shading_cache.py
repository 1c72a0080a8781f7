"""Shading cache: quantisation bound on the whole sphere, LRU behaviour, counters, precompute,
the stated error bound of a cached answer on the cube-before-plate scene; cells and their sums,
uncounted reads, exact mode, and an articulated body's configurations (the shading of the body
posed at grid points, or at the positions themselves)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from meshes import grid_box

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.example_urdf import example_satellite_urdf
from adbsat_ros.geometry.mesh import panels_from_arrays
from adbsat_ros.geometry.poses import Joint
from adbsat_ros.shading import joint_grid
from adbsat_ros.shading.cache import Cell, ShadingCache, moved_lit_area
from adbsat_ros.shading.cube_map import cells_per_edge, direction_keys, key_centres
from adbsat_ros.shading.lighting import LightingBlend, PanelLighting, lit_projected_area
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
        "configurations": 1,
        "max_configurations": 1,
        "configuration_hits": 0,
        "configuration_misses": 0,
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


# ---------------------------------------------------------------- the one cache: cells, hooks
def test_directions_prepared_in_one_call_are_read_as_shaded_one_at_a_time(shader):
    aoa, aos = np.meshgrid(np.radians([-170.0, -20.0, 0.0, 35.0]), np.radians([-60.0, 0.0, 5.0]))
    dirs = frames.flow_direction(aoa.ravel(), aos.ravel())
    one, ahead = ShadingCache.exact_mode(shader), ShadingCache.exact_mode(shader)
    ahead.prepare(dirs)
    for u in dirs:
        a, b = ahead.lighting(u), one.lighting(u)
        for name in ("lit_fraction", "shift"):
            np.testing.assert_allclose(getattr(a, name), getattr(b, name), atol=1e-12)
        np.testing.assert_array_equal(a.shift_index, b.shift_index)
    assert (ahead.hits, ahead.misses) == (one.hits, one.misses) == (0, len(dirs))
    assert not ahead._ahead  # (each read took its prepared lighting)


def _same(a, b):
    """Bit-equality of two lightings or blends (weights, parts, arrays)."""
    if isinstance(a, LightingBlend):
        assert isinstance(b, LightingBlend) and len(a.parts) == len(b.parts)
        for (wa, la), (wb, lb) in zip(a.parts, b.parts):
            assert wa == wb
            _same(la, lb)
        return
    assert isinstance(b, PanelLighting) and not isinstance(a, LightingBlend)
    for name in ("lit_fraction", "shift_index", "shift"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))


@pytest.mark.parametrize("interpolate", [False, True])
def test_reads_are_the_cell_centres_shading_in_the_triangles_order(shader, interpolate):
    """read() gives (weight, Cell) of the cells around u (the triangulation's order, weight 0
    dropped); each cell's lighting is the shader's at its centre, bit for bit; lighting() is
    their blend, or the one stored lighting itself."""
    cache = ShadingCache(shader, resolution_deg=2.0, interpolate=interpolate)
    rng = np.random.default_rng(4)
    for _ in range(6):
        u = np.array([-1.0, 0.0, 0.0]) + 0.4 * rng.normal(size=3)
        x, y, z = u.tolist()
        if interpolate:
            expected = [(w, k) for k, w in zip(*cache.triangulation.locate(x, y, z)) if w > 0.0]
        else:
            expected = [(1.0, cache.key(u))]
        parts = cache.read(u)
        assert [w for w, _ in parts] == [w for w, _ in expected]
        assert cache.last_keys == tuple(k for _, k in expected)
        for (_, cell), (_, k) in zip(parts, expected):
            assert isinstance(cell, Cell) and cell.sums is None
            _same(cell.lighting, shader.lighting(cache.centre(k)))
        reference = LightingBlend.of([(w, shader.lighting(cache.centre(k))) for w, k in expected])
        _same(cache.lighting(u), reference)
        if len(parts) == 1:
            assert cache.lighting(u) is parts[0][1].lighting


def test_the_summarise_hook_runs_once_per_cell(shader):
    """Sums are made on first use, once per stored cell, from that cell's lighting; a cell
    evicted and read again is made again (and summarised again)."""
    calls = []

    def summarise(lighting):
        calls.append(lighting)
        return float(lighting.lit_fraction.sum())

    cache = ShadingCache(shader, resolution_deg=5.0, max_entries=2, summarise=summarise)
    ua, ub, uc = (frames.flow_direction(math.radians(a), 0.0) for a in (0.0, 20.0, 40.0))
    (_, cell), *rest = cache.read(ua)
    assert rest == [] and calls == []  # lazy: not made with the lighting
    assert cell.sums == float(cell.lighting.lit_fraction.sum())
    for _ in range(3):
        assert cache.read(ua)[0][1] is cell and cell.sums == calls[0].lit_fraction.sum()
    assert len(calls) == 1 and calls[0] is cell.lighting
    cache.read(ub)[0][1].sums
    cache.read(uc)  # evicts ua's cell
    assert cache.key(ua) not in cache and len(calls) == 2
    again = cache.read(ua)[0][1]
    assert again is not cell and again.sums == cell.sums and len(calls) == 3
    precomputed = ShadingCache(shader, resolution_deg=30.0, summarise=summarise)
    precomputed.precompute()
    assert len(calls) == 3  # (sums are not precomputed)


def test_uncounted_reads_share_the_cells_and_leave_their_keys_apart(shader):
    """count=False (the sun's reads) leaves hits and misses alone, stores its cells in the
    same bound, and gives its keys in last_uncounted until the next counted read."""
    cache = ShadingCache(shader, resolution_deg=5.0, max_entries=2)
    ua, ub = frames.flow_direction(0.1, 0.0), frames.flow_direction(0.5, 0.3)
    cache.read(ua)
    cache.read(ub, count=False)
    assert (cache.hits, cache.misses, len(cache)) == (0, 1, 2)
    assert cache.last_keys == (cache.key(ua),) and cache.last_uncounted == (cache.key(ub),)
    cache.read(ub)  # stored by the uncounted read: a hit
    assert (cache.hits, cache.misses) == (1, 1) and cache.last_uncounted == ()
    cache.read(-ua, count=False)  # a third cell evicts the least recently used (ua's)
    assert cache.evictions == 1 and cache.key(ua) not in cache
    # the error bound reads uncounted (its answer, when not given, is the cached one)
    u = frames.flow_direction(math.radians(8.4), math.radians(-3.3))
    bound = cache.area_error_bound(u)
    assert bound == cache.area_error_bound(u, cache.lighting(u)) > 0.0


def test_exact_mode_of_a_rigid_body(shader):
    """Exact mode: the lighting of the direction itself (the shader's, bit for bit), keyed by
    its components; bounds 1 cell and 1 shader; no interpolation, no cube-map filling."""
    cache = ShadingCache.exact_mode(shader)
    assert cache.exact and cache.max_entries == 1 and cache.info()["max_configurations"] == 1
    u = frames.flow_direction(math.radians(8.4), math.radians(-3.3))
    v = frames.flow_direction(math.radians(-5.0), math.radians(2.0))
    _same(cache.lighting(u), shader.lighting(u))
    assert cache.last_keys == (tuple(u.tolist()),) and tuple(u.tolist()) in cache
    cache.lighting(u)
    cache.lighting(v)
    _same(cache.lighting(v), shader.lighting(v))
    assert (cache.hits, cache.misses, cache.evictions, len(cache)) == (2, 2, 1, 1)
    assert (cache.configuration_hits, cache.configuration_misses) == (0, 0)
    with pytest.raises(ValueError, match="exact mode has no cells to interpolate"):
        ShadingCache(shader, interpolate=True, exact=True)
    with pytest.raises(ValueError, match="rigid body's cube-map cells"):
        cache.precompute()
    with pytest.raises(ValueError, match="rigid body's shader, or an articulated body"):
        ShadingCache()


# ---------------------------------------------------------------- articulated bodies
@pytest.fixture(scope="module")
def wings():
    return ArticulatedBody.from_urdf(example_satellite_urdf())


def _posed(body, mode="raycast"):
    def posed_shader(positions):
        return make_shader(body.mesh(positions), mode=mode)

    return posed_shader


def _grid(body, joint_interpolate, interpolate, mode="raycast", **bounds):
    """The one cache over an articulated body's joint grid (2 deg) and cells (2 deg)."""
    return ShadingCache(
        None,
        2.0,
        bounds.get("max_entries", 4096),
        interpolate,
        body=body,
        posed_shader=_posed(body, mode),
        angle_step=math.radians(2.0),
        length_step=1e-3,
        joint_interpolate=joint_interpolate,
        max_configurations=bounds.get("max_configurations", 8),
    )


def _joint_cases(body, n, seed):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        positions = {
            name: float(rng.uniform(max(joint.lower, -1.0), min(joint.upper, 1.0)))
            for name, joint in body.joints.items()
        }
        u = frames.flow_direction(
            math.radians(rng.uniform(-30.0, 30.0)), math.radians(rng.uniform(120.0, 180.0))
        )
        yield positions, u


def _direction_weights(cache, u):
    """{cell key: weight} of the cells an answer at ``u`` blends (weight 0 dropped)."""
    if cache.triangulation is None:
        return {cache.key(u): 1.0}
    keys, weights = cache.triangulation.locate(*frames.direction_components(u))
    return {int(k): w for k, w in zip(keys, weights) if w > 0.0}


@pytest.mark.parametrize(
    "joint_interpolate, interpolate", [(False, False), (True, False), (True, True)]
)
def test_grid_parts_are_the_posed_shading_at_grid_points_and_cell_centres(
    wings, joint_interpolate, interpolate
):
    """Each part is the shading of the body posed at a grid configuration for a cell centre,
    bit for bit; parts come configuration major with weight w_configuration * w_direction; a
    repeated read is all hits, counted per part and per configuration read."""
    cache = _grid(wings, joint_interpolate, interpolate)
    posed_shader = _posed(wings)
    for positions, u in _joint_cases(wings, 4, seed=2):
        vertices = cache.vertices(positions)
        parts = cache.read(u, vertices)
        keys = cache.last_keys
        directions = _direction_weights(cache, u)
        expected = [(c, cell) for _, c in vertices for cell in directions]
        assert list(keys) == expected and len(parts) == len(keys)
        weight_of = {c: w for w, c in vertices}
        for (w, cell), (configuration, key) in zip(parts, keys):
            assert w == weight_of[configuration] * directions[key]
            at = posed_shader(cache.configuration(configuration)).lighting(cache.centre(key))
            _same(cell.lighting, at)
        counts = (cache.hits, cache.misses, cache.configuration_hits, cache.configuration_misses)
        again = cache.read(u, vertices)
        assert [c for _, c in again] == [c for _, c in parts]  # (the same stored cells)
        assert (
            cache.hits,
            cache.misses,
            cache.configuration_hits,
            cache.configuration_misses,
        ) == (counts[0] + len(parts), counts[1], counts[2] + len(vertices), counts[3])
        _same(cache.lighting(u, vertices), LightingBlend.of([(w, c.lighting) for w, c in parts]))
    with pytest.raises(ValueError, match="needs vertices"):
        cache.read(u)


def test_the_grid_shares_one_bound_of_cells_and_keeps_its_shaders_apart(wings):
    """Cells of every configuration share max_entries; shaders are kept by configuration key
    up to max_configurations; eviction changes the counters, never the lightings."""
    cache = _grid(wings, False, False, mode="projection", max_entries=3, max_configurations=2)
    names = list(wings.joints)
    u = frames.flow_direction(0.0, math.radians(150.0))
    sequence = [{names[0]: math.radians(2.0 * k), names[1]: 0.0} for k in (0, 1, 2, 0, 3, 0)]
    for positions in sequence:
        at = make_shader(wings.mesh(positions), mode="projection").lighting(
            cache.centre(cache.key(u))
        )
        _same(cache.lighting(u, cache.vertices(positions)), at)
    assert len(cache) == 3 and cache.evictions == 1  # 4 configurations' cells, 3 kept
    assert cache.info()["configurations"] == 2
    assert cache.configuration_misses == 5 and cache.configuration_hits == 1  # (shaders: 2 kept)
    assert (cache.hits, cache.misses) == (2, 4)
    assert ((0, 0), cache.key(u)) in cache and ((1, 0), cache.key(u)) not in cache


def test_exact_mode_of_an_articulated_body(wings):
    """Exact positions and direction: the shading of the body posed at the positions for the
    direction itself, bit for bit; 1 cell and 1 shader kept; a repeated message is a hit, a new
    direction at the same positions reuses the posed shader."""
    posed_shader = _posed(wings)
    cache = ShadingCache.exact_mode(body=wings, posed_shader=posed_shader)
    cases = list(_joint_cases(wings, 3, seed=5))
    (p0, u0), (p1, u1), (_, u2) = cases
    for positions, u in [(p0, u0), (p0, u0), (p0, u1), (p1, u1), (p1, u2), (p0, u0)]:
        vertices = cache.vertices(positions)
        key = tuple(positions[name] for name in wings.joints)
        assert vertices == [(1.0, key)]
        _same(cache.lighting(u, vertices), posed_shader(positions).lighting(u))
        assert cache.last_keys == ((key, tuple(u.tolist())),)
    counters = (cache.hits, cache.misses, cache.configuration_hits, cache.configuration_misses)
    assert counters == (1, 5, 2, 3)
    assert len(cache) == 1 and cache.info()["configurations"] == 1


def test_joint_grid_steps_keys_and_clipping(wings):
    """Prismatic joints take the length step, others the angle step; keys round to the nearest
    grid point; grid positions are clipped to the limits; steps must be positive."""
    joints = {
        "slide": Joint("slide", "prismatic", "a", "b", (1.0, 0.0, 0.0), 0.0, 0.0105),
        "hinge": Joint("hinge", "revolute", "a", "c", (0.0, 0.0, 1.0), -0.5, 0.5),
    }
    steps = joint_grid.grid_steps(joints, 0.1, 0.002)
    assert steps == (0.002, 0.1)
    assert joint_grid.grid_key(joints, steps, {"slide": 0.0049, "hinge": -0.26}) == (2, -3)
    assert joint_grid.grid_configuration(joints, steps, (6, -6)) == {"slide": 0.0105, "hinge": -0.5}
    vertices = joint_grid.grid_vertices(joints, steps, {"slide": 0.0103, "hinge": 0.25}, True)
    weights = np.array([w for w, _ in vertices])
    points = np.array(
        [list(joint_grid.grid_configuration(joints, steps, k).values()) for _, k in vertices]
    )
    np.testing.assert_allclose(weights @ points, [0.0103, 0.25], atol=1e-12)
    with pytest.raises(ValueError, match="steps must be positive"):
        joint_grid.grid_steps(joints, 0.0, 0.002)
    with pytest.raises(ValueError, match="needs angle_step and length_step"):
        ShadingCache(body=wings, posed_shader=_posed(wings))
