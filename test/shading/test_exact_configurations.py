"""Exact shading of an articulated body (``joint_shading_exact``): the ray-cast shading of the
body posed at the positions, for the flow direction itself; the grid cache's answer where the
grid has its own point; counted as the node reports it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbsat_ros.estimator.settings import WrenchSettings, setup_from_settings
from adbsat_ros.geometry import frames
from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.example_urdf import example_finned_urdf, example_satellite_urdf
from adbsat_ros.physics.model import build_model
from adbsat_ros.shading.shader import make_shader


@pytest.fixture(scope="module", params=["wings", "fins"])
def body(request):
    text = example_satellite_urdf() if request.param == "wings" else example_finned_urdf()
    return ArticulatedBody.from_urdf(text)


def source(body, **parameters):
    """The node's shading cache of ``body`` with these parameters."""
    settings = WrenchSettings.from_parameters(parameters)
    return build_model(setup_from_settings(settings), body).cache


def lighting(cache, u, positions):
    """``(lighting, hit)`` of one read at joint ``positions``: its one cell's."""
    hits = cache.hits
    [(_, cell)] = cache.read(u, cache.vertices(positions))
    return cell.lighting, cache.hits > hits


def random_cases(body, n, seed):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        positions = {
            name: float(rng.uniform(max(joint.lower, -1.0), min(joint.upper, 1.0)))
            for name, joint in body.joints.items()
        }
        aoa, aos = math.radians(rng.uniform(-40.0, 40.0)), math.radians(rng.uniform(-180, 180))
        yield positions, frames.flow_direction(aoa, aos)


def test_it_is_the_ray_cast_shading_of_the_body_posed_at_the_positions(body):
    """Against a shader made afresh for the posed panels (its own vertex merging and topology,
    where the exact mode reuses the links' own): the same lit fractions and shifts to rounding.
    """
    exact = source(body, joint_shading_exact=True)
    shaded = 0
    for positions, u in random_cases(body, 5, seed=3):
        lit, hit = lighting(exact, u, positions)
        reference = make_shader(body.mesh(positions), topology_store=None).lighting(u)
        np.testing.assert_allclose(lit.lit_fraction, reference.lit_fraction, atol=1e-12)
        shift = np.zeros((body.mesh().n_panels, 3))
        shift[lit.shift_index] = lit.shift
        expected = np.zeros_like(shift)
        expected[reference.shift_index] = reference.shift
        np.testing.assert_allclose(shift, expected, atol=1e-12)
        assert hit is False  # (shaded, not read)
        shaded += int((reference.lit_fraction < 1.0).any())
    assert shaded >= 2  # (some parts shade others in these cases)


def test_on_the_grid_and_at_a_cell_centre_it_is_the_grid_caches_answer(body):
    """The grid cache (nearest configuration, nearest direction cell) samples the exact mode:
    at a grid configuration and a cell centre both give the same numbers, bit for bit."""
    grid = source(body, shading_interpolation=False)
    exact = source(body, joint_shading_exact=True)
    step = math.radians(0.25)
    for k, (positions, u) in enumerate(random_cases(body, 3, seed=5)):
        on_grid = {name: round(q / step) * step for name, q in positions.items()}
        centre = grid.centre(grid.key(u))
        a, _ = lighting(grid, centre, on_grid)
        b, _ = lighting(exact, centre, on_grid)
        np.testing.assert_array_equal(a.lit_fraction, b.lit_fraction)
        np.testing.assert_array_equal(a.shift_index, b.shift_index)
        np.testing.assert_array_equal(a.shift, b.shift)


def test_its_counters_say_what_was_posed_and_what_was_shaded(body):
    cache = source(body, joint_shading_exact=True)
    (p1, u1), (p2, u2) = random_cases(body, 2, seed=8)
    lighting(cache, u1, p1)
    assert (cache.configuration_misses, cache.configuration_hits) == (1, 0)
    assert (cache.misses, cache.hits) == (1, 0)
    _, hit = lighting(cache, u1, p1)  # the same message again: the same lighting, read
    assert hit is True and (cache.misses, cache.hits) == (1, 1)
    lighting(cache, u2, p1)  # the joints have not moved: the posed body kept, shaded again
    assert (cache.configuration_misses, cache.configuration_hits) == (1, 1)
    assert cache.misses == 2
    lighting(cache, u2, p2)  # new positions: posed again
    assert cache.configuration_misses == 2 and cache.misses == 3
    assert cache.last_keys == ((tuple(p2[name] for name in body.joints), tuple(u2.tolist())),)
    assert cache.info()["misses"] == 3
