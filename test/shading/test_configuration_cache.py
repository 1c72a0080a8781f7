"""The shading of an articulated body cached per joint configuration: the nearest grid point, or
the blend of the Kuhn simplex of grid points around the positions (continuous in them)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.example_urdf import example_finned_urdf, example_satellite_urdf
from adbsat_ros.shading.cache import ShadingCache
from adbsat_ros.shading.configurations import ConfigurationShadingCache
from adbsat_ros.shading.lighting import lit_projected_area
from adbsat_ros.shading.shader import make_shader

STEP = math.radians(2.0)


@pytest.fixture(scope="module")
def wings():
    return ArticulatedBody.from_urdf(example_satellite_urdf())


@pytest.fixture(scope="module")
def fins():
    return ArticulatedBody.from_urdf(example_finned_urdf())


def configuration_cache(body, interpolate, step=STEP):
    def make(positions):
        return ShadingCache(make_shader(body.mesh(positions)), 0.25, interpolate=False)

    return ConfigurationShadingCache(body, make, step, 1e-3, 256, interpolate=interpolate)


def test_the_simplex_weights_reproduce_the_positions(fins):
    cache = configuration_cache(fins, True)
    rng = np.random.default_rng(11)
    names = list(fins.joints)
    for _ in range(50):
        q = rng.uniform(-0.5, 0.5, len(names))
        vertices = cache.vertices(dict(zip(names, q.tolist())))
        weights = np.array([w for w, _ in vertices])
        points = np.array([key for _, key in vertices], dtype=float) * STEP
        assert 1 <= len(vertices) <= len(names) + 1
        assert (weights > 0.0).all() and weights.sum() == pytest.approx(1.0, abs=1e-12)
        np.testing.assert_allclose(weights @ points, q, rtol=0, atol=1e-12)
        # the vertices are corners of the grid cell around q
        assert (np.abs(points - q) <= STEP * (1 + 1e-9)).all()


def test_at_and_near_a_joint_limit_the_blend_reproduces_the_positions(fins):
    """The fins' limits (+-0.6 rad) are no multiple of 2 deg: in the cell the limit cuts, the
    weights are measured between the clipped grid positions."""
    cache = configuration_cache(fins, True)
    names = list(fins.joints)
    for q0 in (0.6, 0.599, -0.6, -0.5995):
        positions = {name: (q0 if k == 0 else 0.1 * k) for k, name in enumerate(names)}
        vertices = cache.vertices(positions)
        weights = np.array([w for w, _ in vertices])
        points = np.array([list(cache.configuration(key).values()) for _, key in vertices])
        assert (weights > 0.0).all() and weights.sum() == pytest.approx(1.0, abs=1e-12)
        np.testing.assert_allclose(weights @ points, list(positions.values()), atol=1e-12)
    at_limit = {name: 0.6 for name in names}
    assert [list(cache.configuration(key).values()) for _, key in cache.vertices(at_limit)] == [
        [0.6] * 4
    ]


def test_on_a_grid_point_one_configuration_is_used(fins):
    cache = configuration_cache(fins, True)
    on_grid = {name: math.radians(2.0 * k) for k, name in enumerate(fins.joints)}  # (rounding)
    assert cache.vertices(on_grid) == [(1.0, (0, 1, 2, 3))]
    equal = dict.fromkeys(fins.joints, 0.3)  # one fraction for all: two points, not five
    assert len(cache.vertices(equal)) == 2
    assert configuration_cache(fins, False).vertices(equal) == [(1.0, cache.key(equal))]


def lit_area(body, cache, positions, u):
    return lit_projected_area(body.mesh(positions), u, cache.lighting(u, positions))


def test_the_blend_is_continuous_across_the_grid_and_exact_on_it(wings):
    """A wing turning through grid lines behind the body: the snapped lighting steps at the
    midpoints between grid points, the blend does not, and on a grid point it is that point's."""
    u = frames.flow_direction(0.0, math.radians(150.0))  # the body shades the left wing
    blend, snap = configuration_cache(wings, True), configuration_cache(wings, False)
    name = "wing_left_hinge"
    mid = 7.5 * STEP  # between grid points 7 and 8
    eps = 1e-7
    other = {"wing_right_hinge": 0.0}
    below, above = {name: mid - eps, **other}, {name: mid + eps, **other}
    mesh = wings.mesh({name: mid, **other})  # (one mesh: the lightings' change alone)

    def step(cache):
        return lit_projected_area(mesh, u, cache.lighting(u, above)) - lit_projected_area(
            mesh, u, cache.lighting(u, below)
        )

    step_snap, step_blend = step(snap), step(blend)
    assert abs(step_snap) > 1e-6  # m^2: the nearest point changes here, and its shadow
    assert abs(step_blend) < 1e-3 * abs(step_snap)
    at = {name: 8 * STEP, **other}
    np.testing.assert_array_equal(
        blend.lighting(u, at).lit_fraction, snap.lighting(u, at).lit_fraction
    )
    assert blend.last_keys == (((8, 0), blend.cache_at((8, 0)).last_keys[0]),)


def test_the_blend_is_closer_to_the_exact_shading_than_the_nearest_point(fins):
    """Lit projected area against shading at the exact configuration, over attitudes and
    deflections where the parts shade each other."""
    blend, snap = configuration_cache(fins, True), configuration_cache(fins, False)
    rng = np.random.default_rng(5)
    errors = {"blend": [], "snap": []}
    for _ in range(6):
        u = frames.flow_direction(math.radians(rng.uniform(-40, 40)), math.radians(160.0))
        q = dict(zip(fins.joints, rng.uniform(-0.17, 0.17, 4).tolist()))
        exact = lit_projected_area(fins.mesh(q), u, make_shader(fins.mesh(q)).lighting(u))
        errors["blend"].append(abs(lit_area(fins, blend, q, u) - exact))
        errors["snap"].append(abs(lit_area(fins, snap, q, u) - exact))
    assert max(errors["snap"]) > 0.0  # (inter-part shading changed with the deflections)
    assert sum(errors["blend"]) < 0.5 * sum(errors["snap"])
    # counters: every grid point read is counted, kept or made
    assert blend.configuration_hits + blend.configuration_misses >= 6
    assert blend.misses >= len(blend) >= 6  # (each point made has shaded its cell)
