"""An articulated body's ray scene and candidate filter from its links, made once: at any
configuration the shader answers exactly as it does when it builds them from the posed mesh."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import needs_embree

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.example_urdf import example_finned_urdf, example_satellite_urdf
from adbsat_ros.shading import posed_scene
from adbsat_ros.shading.candidates import CandidateFilter
from adbsat_ros.shading.posed_scene import LinkScenes
from adbsat_ros.shading.rays import ray_scene
from adbsat_ros.shading.shader import make_shader
from adbsat_ros.shading.topology_store import indexed_topology

DIRECTIONS = [(5.0, 3.0), (20.0, 10.0), (-30.0, 100.0), (60.0, -20.0), (170.0, 5.0)]


@pytest.fixture(scope="module", params=["wings", "fins"])
def body(request):
    text = example_satellite_urdf() if request.param == "wings" else example_finned_urdf()
    return ArticulatedBody.from_urdf(text)


def configurations(body):
    """Zero, and two configurations with every joint at its own angle within its limits."""
    out = [{}]
    for scale in (0.6, -0.9):
        out.append(
            {
                name: scale * min(joint.upper, 0.8) * (1.0 - 0.15 * k)
                for k, (name, joint) in enumerate(body.joints.items())
            }
        )
    return out


def test_shading_from_the_links_equals_shading_the_posed_mesh(backend, body):
    scenes = LinkScenes(body, backend)
    shaded = 0
    for values in configurations(body):
        mesh = body.mesh(values)
        plain = make_shader(mesh, backend=backend)
        posed = make_shader(
            mesh,
            scene=scenes.scene(mesh, body.link_poses(values)),
            candidate_filter=scenes.candidate_filter(mesh),
        )
        assert posed.backend == plain.backend == backend
        for aoa, aos in DIRECTIONS:
            u = frames.flow_direction(math.radians(aoa), math.radians(aos))
            want, got = plain.lighting(u), posed.lighting(u)
            assert posed.last_stats == plain.last_stats  # the same panels, the same rays
            np.testing.assert_array_equal(got.lit_fraction, want.lit_fraction)
            np.testing.assert_array_equal(got.shift_index, want.shift_index)
            np.testing.assert_allclose(got.shift, want.shift, rtol=0, atol=1e-15)
            shaded += want.shaded_index.size
    assert shaded > 0  # (one part shaded another somewhere)


def test_the_topology_of_the_links_is_that_of_the_posed_mesh(body):
    scenes = LinkScenes(body)
    for values in configurations(body):
        mesh = body.mesh(values)
        lo, hi = mesh.bounds
        want = CandidateFilter(
            mesh, indexed_topology(mesh, float(np.linalg.norm(hi - lo)), None)[1]
        )
        got = scenes.candidate_filter(mesh)
        np.testing.assert_array_equal(got.on_hull, want.on_hull)
        assert got.n_components == want.n_components == len(body.link_spans)
        # the same components, whatever their numbers
        pairs = set(zip(got.component.tolist(), want.component.tolist()))
        assert len(pairs) == got.n_components
        assert {tuple(sorted(e)) for e in got.adjacency.tolist()} == {
            tuple(sorted(e)) for e in want.adjacency.tolist()
        }


def test_first_hits_through_the_posed_scene(backend, body):
    scenes = LinkScenes(body, backend)
    values = configurations(body)[1]
    mesh = body.mesh(values)
    rng = np.random.default_rng(7)
    lo, hi = mesh.bounds
    origins = lo + (hi - lo) * rng.uniform(-0.5, 1.5, (400, 3))
    aims = mesh.barycentres[rng.integers(0, mesh.n_panels, 400)]  # rays toward the body
    directions = aims - origins + 0.05 * rng.normal(size=(400, 3))
    face, t = scenes.scene(mesh, body.link_poses(values)).first_hit(origins, directions)
    want_face, want_t = ray_scene(mesh, backend).first_hit(origins, directions)
    assert (face >= 0).sum() > 200  # (most rays meet the body)
    np.testing.assert_array_equal(face, want_face)
    np.testing.assert_allclose(t[face >= 0], want_t[face >= 0], rtol=1e-6)


def test_a_configuration_scene_is_built_at_its_first_ray(backend, body, monkeypatch):
    # The bundled bodies are boxes: at these directions their exact convex shadows leave no
    # ray to cast, so the configuration's scene is never built; the first ray builds it.
    built = []

    def counted(*args, **kwargs):
        built.append(ray_scene(*args, **kwargs))
        return built[-1]

    monkeypatch.setattr(posed_scene, "ray_scene", counted)
    scenes = LinkScenes(body, backend)
    values = configurations(body)[1]
    mesh = body.mesh(values)
    poses = body.link_poses(values)
    scene = scenes.scene(mesh, poses)
    shader = make_shader(
        mesh,
        scene=scene,
        candidate_filter=scenes.candidate_filter(mesh),
        hull_corners=scenes.hull_corners(poses),
    )
    for aoa, aos in DIRECTIONS[:2]:
        shader.lighting(frames.flow_direction(math.radians(aoa), math.radians(aos)))
        assert shader.last_stats["rays"] == 0
    assert not built
    origins = mesh.barycentres[:50] + 2.0 * mesh.normals[:50]
    u = -mesh.normals[0]
    got = scene.any_hit(origins, u)
    assert len(built) == 1
    np.testing.assert_array_equal(got, ray_scene(mesh, backend).any_hit(origins, u))


@needs_embree
def test_an_embree_scene_of_other_faces_is_refused(body):
    mesh = body.mesh()
    vertices = mesh.vertices.reshape(-1, 3)
    faces = np.arange(vertices.shape[0]).reshape(-1, 3)[:-1]  # (one panel short)
    with pytest.raises(ValueError, match=f"for a mesh of {mesh.n_panels} panels"):
        ray_scene(mesh, "embree", indexed=(vertices, faces))


def test_a_topology_of_another_mesh_is_refused(body):
    mesh = body.mesh()
    _, other = indexed_topology(body.link_mesh(next(iter(body.link_spans))), 1.0, None)
    with pytest.raises(ValueError, match=f"topology of {other.component.size} panels for a mesh"):
        CandidateFilter(mesh, topology=other)
