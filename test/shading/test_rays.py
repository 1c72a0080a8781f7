"""Ray casting: both backends behind one interface, the same rules, the same answers.

Every case runs with the numpy and the Embree backend (the ``backend`` fixture, conftest.py);
where both are installed, the last tests also cast the same rays with both and compare.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh
from conftest import needs_embree
from shading_scenes import cube_plate, dented_box, satellite

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.loading import panels_from_trimesh
from adbsat_ros.geometry.mesh import panels_from_arrays
from adbsat_ros.shading.rays import BACKENDS, has_embree, ray_scene, resolve_backend
from adbsat_ros.shading.shader import make_shader


def square(x0=0.0, half=0.5):
    """A square in the plane x = x0, |y|, |z| <= half, two triangles sharing the diagonal."""
    v = np.array([[x0, -half, -half], [x0, half, -half], [x0, half, half], [x0, -half, half]])
    return v, np.array([[0, 1, 2], [0, 2, 3]])


def plates(*xs):
    """Parallel squares at the given x (open surfaces, one component each)."""
    parts = [square(x) for x in xs]
    vertices = np.vstack([v for v, _ in parts])
    faces = np.vstack([f + 4 * k for k, (_, f) in enumerate(parts)])
    return panels_from_arrays(vertices, faces, source="plates")


def test_backend_names():
    assert BACKENDS == ("auto", "embree", "numpy")
    assert resolve_backend("auto") == ("embree" if has_embree else "numpy")
    assert resolve_backend("NumPy") == "numpy"
    with pytest.raises(ValueError, match="unknown backend 'bvh'; choose one of auto, embree"):
        resolve_backend("bvh")


def test_the_scene_is_of_the_backend_asked_for(backend):
    assert ray_scene(plates(0.0), backend).backend == backend


def test_only_hits_ahead_of_the_origin_count(backend):
    scene = ray_scene(plates(0.0), backend)
    origins = np.array([[1.0, 0.1, 0.2], [-1.0, 0.1, 0.2], [1.0, 0.7, 0.0], [0.5, -0.3, 0.3]])
    toward = np.array([-1.0, 0.0, 0.0])
    np.testing.assert_array_equal(scene.any_hit(origins, toward), [True, False, False, True])
    np.testing.assert_array_equal(scene.any_hit(origins, -toward), [False, True, False, False])
    assert scene.any_hit(np.zeros((0, 3)), toward).shape == (0,)


def test_a_ray_through_a_shared_edge_is_blocked(backend):
    # the diagonal (y = z) is the edge both triangles share; the corner (0.5, 0.5) a vertex of
    # both: a ray through either is inside both triangles under the inclusive rule
    scene = ray_scene(plates(0.0), backend)
    origins = np.array([[1.0, 0.1, 0.1], [1.0, -0.37, -0.37], [1.0, 0.25, 0.25]])
    assert scene.any_hit(origins, np.array([-1.0, 0.0, 0.0])).all()


def test_grazing_faces_do_not_occlude(backend):
    # A square lying in the plane y = 0; a ray travelling in that plane is not blocked by it
    # (zero projected area: the shader leaves it out of the occluders), one crossing it is.
    sq = trimesh.Trimesh(
        [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]], [[0, 1, 2], [0, 2, 3]], process=False
    )
    scene = ray_scene(panels_from_trimesh(sq), backend)
    d = np.array([1.0, 0.0, 0.0])
    occluder = np.abs(np.asarray(sq.face_normals) @ d) > 1e-6
    assert not occluder.any()
    origins = np.array([[-1.0, 0.0, 0.5], [-1.0, 0.0, 0.25]])
    assert not scene.any_hit(origins, d, occluder).any()
    crossing = np.array([[0.5, -1.0, 0.5]])
    assert scene.any_hit(crossing, np.array([0.0, 1.0, 0.0]), np.ones(2, bool)).all()


def test_panels_left_out_of_the_occluders_let_rays_through(backend):
    # three plates at x = 0, -1, -2; a ray from x = 1 along -x crosses all of them. Whatever
    # the first hit (Embree casts against every panel and casts again past a left-out one),
    # the ray is blocked iff some occluder lies on it.
    mesh = plates(0.0, -1.0, -2.0)
    scene = ray_scene(mesh, backend)
    origin = np.array([[1.0, 0.2, -0.1]])
    d = np.array([-1.0, 0.0, 0.0])
    for occluding_plates, blocked in [((), False), ((2,), True), ((1, 2), True), ((0,), True)]:
        occluder = np.zeros(mesh.n_panels, dtype=bool)
        for k in occluding_plates:
            occluder[2 * k : 2 * k + 2] = True
        assert bool(scene.any_hit(origin, d, occluder)[0]) is blocked, occluding_plates


def test_the_first_face_met_is_the_nearest_occluder(backend):
    # plates at x = 0, -1, -2 (panels 0-1, 2-3, 4-5); rays from x = 1 along -x through their
    # middle meet them in that order, and a ray beside them meets none
    mesh = plates(0.0, -1.0, -2.0)
    scene = ray_scene(mesh, backend)
    origins = np.array([[1.0, 0.2, -0.1], [1.0, -0.3, 0.25], [-0.5, 0.1, 0.1], [1.0, 2.0, 0.0]])
    d = np.array([-1.0, 0.0, 0.0])
    face = scene.first_face(origins, d)
    assert face.dtype == np.int64
    assert face[0] // 2 == 0 and face[1] // 2 == 0  # the plate at x = 0
    assert face[2] // 2 == 1  # starting between the plates: the one at x = -1
    assert face[3] == -1
    # left out of the occluders, the first plate lets the rays on to the second
    occluder = np.ones(mesh.n_panels, dtype=bool)
    occluder[0:2] = False
    face = scene.first_face(origins, d, occluder)
    assert face[0] // 2 == 1 and face[1] // 2 == 1 and face[2] // 2 == 1 and face[3] == -1
    # a face is met exactly where a ray is blocked
    np.testing.assert_array_equal(face >= 0, scene.any_hit(origins, d, occluder))


@needs_embree
@pytest.mark.parametrize("mesh_factory", [satellite, dented_box])
def test_both_backends_meet_the_same_first_faces(mesh_factory):
    mesh = mesh_factory()
    rng = np.random.default_rng(5)
    lo, hi = mesh.bounds
    origins = rng.uniform(lo - 0.5, hi + 0.5, size=(3000, 3))
    embree, numpy_ = ray_scene(mesh, "embree"), ray_scene(mesh, "numpy")
    met = 0
    for d in rng.normal(size=(4, 3)):
        d /= np.linalg.norm(d)
        occluder = np.abs(mesh.normals @ d) > 1e-6
        e, n = embree.first_face(origins, d, occluder), numpy_.first_face(origins, d, occluder)
        assert np.count_nonzero(e != n) <= 2  # (3000 rays; float32 rounding at edges)
        np.testing.assert_array_equal(n >= 0, numpy_.any_hit(origins, d, occluder))
        met += int((n >= 0).sum())
    assert 0.05 * 4 * 3000 < met < 0.95 * 4 * 3000


@needs_embree
@pytest.mark.parametrize("mesh_factory", [satellite, dented_box, lambda: cube_plate(17)])
def test_both_backends_give_the_same_hits_for_random_rays(mesh_factory):
    # Rays may differ only within float32 rounding (~1e-7 of the mesh size) of an edge, which
    # random rays practically never meet. Measured: all equal.
    mesh = mesh_factory()
    rng = np.random.default_rng(4)
    lo, hi = mesh.bounds
    origins = rng.uniform(lo - 0.5, hi + 0.5, size=(4000, 3))
    embree, numpy_ = ray_scene(mesh, "embree"), ray_scene(mesh, "numpy")
    n_hits = 0
    for d in rng.normal(size=(6, 3)):
        d /= np.linalg.norm(d)
        occluder = np.abs(mesh.normals @ d) > 1e-6
        e, n = embree.any_hit(origins, d, occluder), numpy_.any_hit(origins, d, occluder)
        assert np.count_nonzero(e != n) <= 2  # (4000 rays)
        n_hits += int(n.sum())
    assert 0.05 * 6 * 4000 < n_hits < 0.95 * 6 * 4000  # the rays do meet the mesh, not all


@needs_embree
def test_shaders_with_either_backend_agree():
    # Same rays from the same points: answers may differ only for rays within float32 rounding
    # of an edge. Tolerance: at most 0.5 % of panels differ, by at most 1/256 (one refinement
    # ray) each. Measured: all equal.
    for mesh in (satellite(), cube_plate(plate_div=17), dented_box()):
        e = make_shader(mesh, backend="embree")
        n = make_shader(mesh, backend="numpy")
        assert (e.backend, n.backend) == ("embree", "numpy")
        rng = np.random.default_rng(11)
        dirs = [frames.flow_direction(0.0, 0.0)]  # head-on: grazing faces, Embree's recast
        dirs += list(frames.flow_direction(rng.uniform(-0.8, 0.8, 5), rng.uniform(-0.8, 0.8, 5)))
        for u in dirs:
            le, ln = e.lighting(u), n.lighting(u)
            diff = np.abs(le.lit_fraction - ln.lit_fraction)
            assert np.count_nonzero(diff) <= 0.005 * mesh.n_panels
            assert diff.max() <= 1.0 / 256 + 1e-12
            assert e.last_stats["rays"] == n.last_stats["rays"]


def test_shading_is_the_same_whatever_the_backend(backend):
    # The cube's shadow on the plate at 10 deg aoa, with either backend: the shadow area is
    # 1 + tan(10 deg) m^2 to 0.5 % (test_shader.py has the full reference).
    mesh = cube_plate()
    shader = make_shader(mesh, backend=backend)
    assert shader.backend == backend
    a = math.radians(10.0)
    lighting = shader.lighting(frames.flow_direction(a, 0.0))
    shadow = float(((1.0 - lighting.lit_fraction) * mesh.areas).sum())
    assert shadow == pytest.approx(1.0 + math.tan(a), rel=5e-3)
