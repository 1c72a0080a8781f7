"""Mesh import: formats, materials, scale, and every kind of bad mesh."""

import logging
import math

import numpy as np
import pytest
import trimesh
from meshes import write_obj

from adbsat_ros.geometry.example_satellite import example_satellite
from adbsat_ros.geometry.loading import load_mesh, resolve_mesh
from adbsat_ros.geometry.mesh import MeshError, panels_from_arrays, triangle_geometry

BOX = trimesh.creation.box(extents=(1.0, 2.0, 3.0))
BOX_AREA = 2 * (1 * 2 + 2 * 3 + 1 * 3)


@pytest.mark.parametrize("ext", ["stl", "ply", "off", "obj"])
def test_formats_give_the_same_panels(tmp_path, ext):
    path = tmp_path / f"box.{ext}"
    BOX.export(path)
    mesh = load_mesh(path)
    assert mesh.n_panels == 12
    assert mesh.total_area == pytest.approx(BOX_AREA, rel=1e-9)
    # outward normals: normal . (barycentre - centre) > 0 for a box centred on the origin
    assert np.all(np.einsum("ij,ij->i", mesh.normals, mesh.barycentres) > 0)
    assert mesh.report.watertight and mesh.report.convex


def test_ascii_stl(tmp_path):
    path = tmp_path / "box_ascii.stl"
    path.write_bytes(trimesh.exchange.stl.export_stl_ascii(BOX).encode())
    assert load_mesh(path).total_area == pytest.approx(BOX_AREA)


def test_scale_turns_millimetres_into_metres(tmp_path):
    path = tmp_path / "box_mm.stl"
    BOX.copy().apply_scale(1000.0).export(path)
    mesh = load_mesh(path, scale=1e-3)
    assert mesh.total_area == pytest.approx(BOX_AREA)
    assert mesh.x_extent == pytest.approx(1.0)


def test_obj_usemtl_groups_become_named_materials(tmp_path):
    # a unit tetrahedron with a quad-free mix of face syntaxes and three usemtl runs
    text = "\n".join(
        [
            "v 0 0 0",
            "v 1 0 0",
            "v 0 1 0",
            "v 0 0 1",
            "vn 0 0 1",
            "vt 0 0",
            "f 1 3 2",
            "usemtl hull",
            "f 1/1 2/1 4/1",
            "usemtl radiator",
            "f 1//1 4//1 3//1",
            "usemtl hull",
            "f 2/1/1 3/1/1 4/1/1",
        ]
    )
    path = tmp_path / "tet.obj"
    path.write_text(text + "\n")
    mesh = load_mesh(path)
    assert mesh.material_names == ("default", "hull", "radiator")
    assert [mesh.material_names[i] for i in mesh.material_index] == [
        "default",
        "hull",
        "radiator",
        "hull",
    ]
    # face order kept: the last face is the slanted one with normal (1,1,1)/sqrt(3)
    assert np.allclose(mesh.normals[3], np.ones(3) / np.sqrt(3))


def test_obj_quads_are_triangulated_with_their_material(tmp_path):
    v = BOX.vertices
    lines = [f"v {x} {y} {z}" for x, y, z in v]
    lines.append("usemtl a")
    lines += [f"f {f[0] + 1} {f[1] + 1} {f[2] + 1}" for f in BOX.faces[:6]]
    lines.append("usemtl b")
    lines += [f"f {f[0] + 1} {f[1] + 1} {f[2] + 1}" for f in BOX.faces[6:]]
    path = tmp_path / "box.obj"
    path.write_text("\n".join(lines) + "\n")
    mesh = load_mesh(path)
    assert mesh.material_names == ("a", "b")
    assert np.bincount(mesh.material_index).tolist() == [6, 6]


def test_missing_file_is_named():
    with pytest.raises(MeshError, match="not found: .*nowhere.obj"):
        load_mesh("nowhere.obj")


def test_unreadable_file(tmp_path):
    path = tmp_path / "junk.stl"
    path.write_bytes(b"\x00\x01garbage")
    with pytest.raises(MeshError, match="junk.stl"):
        load_mesh(path)


def test_no_faces(tmp_path):
    path = tmp_path / "points.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\n")
    with pytest.raises(MeshError, match="no faces"):
        load_mesh(path)


def test_nan_vertices_are_an_error():
    v = BOX.vertices.copy()
    v[3, 1] = np.nan
    with pytest.raises(MeshError, match="NaN or Inf"):
        panels_from_arrays(v, BOX.faces)
    v[3, 1] = np.inf
    with pytest.raises(MeshError, match="vertex 3"):
        panels_from_arrays(v, BOX.faces)


def test_zero_area_faces_are_dropped_and_counted(caplog):
    faces = np.vstack([BOX.faces, [[0, 0, 1], [2, 2, 2]]])
    with caplog.at_level(logging.WARNING):
        mesh = panels_from_arrays(BOX.vertices, faces)
    assert mesh.n_panels == 12
    assert mesh.report.dropped_zero_area == 2
    assert "dropped 2 zero-area faces" in caplog.text


def test_inward_normals_are_flipped_per_body(caplog):
    # two separate closed boxes, the second one wound inside-out
    other = BOX.copy()
    other.apply_translation((5.0, 0.0, 0.0))
    faces = np.vstack([BOX.faces, other.faces[:, ::-1] + len(BOX.vertices)])
    vertices = np.vstack([BOX.vertices, other.vertices])
    with caplog.at_level(logging.WARNING):
        mesh = panels_from_arrays(vertices, faces)
    assert mesh.report.flipped_components == 1
    assert "inward-facing normals" in caplog.text
    centres = np.where(mesh.barycentres[:, :1] > 2.5, [5.0, 0, 0], [0.0, 0, 0])
    assert np.all(np.einsum("ij,ij->i", mesh.normals, mesh.barycentres - centres) > 0)


def test_open_mesh_warns_but_loads(caplog):
    with caplog.at_level(logging.WARNING):
        mesh = panels_from_arrays(BOX.vertices, BOX.faces[:10])
    assert mesh.report.open_components == 1 and not mesh.report.watertight
    assert "open or non-manifold" in caplog.text


def test_example_satellite_is_closed_nonconvex_with_two_materials(tmp_path):
    mesh = example_satellite()
    assert 3000 <= mesh.n_panels <= 8000
    assert mesh.material_names == ("body", "solar_array")
    assert mesh.report.watertight and not mesh.report.convex
    assert mesh.report.flipped_components == 0
    # body 1.2 x 0.5 x 0.5 plus two wings 0.5 x 1.0 x 0.03
    body = 2 * (1.2 * 0.5 * 2 + 0.5 * 0.5)
    wing = 2 * (0.5 * 1.0 + 0.5 * 0.03 + 1.0 * 0.03)
    assert mesh.total_area == pytest.approx(body + 2 * wing, rel=1e-9)
    path = tmp_path / "sat.obj"
    write_obj(mesh, path)
    again = load_mesh(path)
    assert np.allclose(again.vertices, mesh.vertices)
    assert np.array_equal(again.material_index, mesh.material_index)
    assert resolve_mesh("example").n_panels == mesh.n_panels


def test_an_obj_written_with_17_digits_reads_back_the_same_panels(tmp_path):
    # A mesh turned off the axes: with 17 significant digits every coordinate, and so every
    # normal, comes back exactly (its flat faces still share their planes); with 9, a turned
    # face's normals scatter in their last digits.
    mesh = example_satellite(max_edge=0.3)
    turn = trimesh.transformations.rotation_matrix(0.3, [0.2, 1.0, 0.1])[:3, :3]
    points = mesh.vertices.reshape(-1, 3) @ turn.T
    turned = panels_from_arrays(points, np.arange(len(points)).reshape(-1, 3))
    exact, rounded = tmp_path / "exact.obj", tmp_path / "rounded.obj"
    write_obj(turned, exact, digits=17)
    write_obj(turned, rounded)
    assert np.array_equal(load_mesh(exact).vertices, turned.vertices)
    assert np.array_equal(load_mesh(exact).normals, turned.normals)
    assert not np.array_equal(load_mesh(rounded).normals, turned.normals)


@pytest.mark.parametrize(
    "radius, unit, scale",
    [(500.0, "millimetres", 1e-3), (2e-4, "kilometres", 1e3)],
)
def test_a_mesh_of_no_satellites_size_is_refused_naming_its_likely_unit(
    tmp_path, radius, unit, scale
):
    """A file at scale 1 that is over 200 m or under 1 mm across is most likely not in metres:
    refused with the unit it is probably in; its scale, or accepting the size, loads it."""
    path = tmp_path / "body.stl"
    trimesh.creation.icosphere(subdivisions=1, radius=radius).export(path)
    with pytest.raises(MeshError) as caught:
        load_mesh(path)
    text = str(caught.value)
    assert str(path) in text and f"{2 * radius:.6g} m across" in text
    assert f"probably {unit} (scale {scale:g})" in text and "--accept-size" in text
    assert load_mesh(path, scale=scale).n_panels == 80
    assert load_mesh(path, accept_size=True).n_panels == 80
    with pytest.raises(MeshError):
        resolve_mesh(str(path))
    assert resolve_mesh(str(path), accept_size=True).n_panels == 80


def test_a_mesh_from_a_millimetre_to_200_m_across_loads(tmp_path):
    for radius in (0.5e-3, 100.0):
        path = tmp_path / f"r{radius}.stl"
        trimesh.creation.icosphere(subdivisions=1, radius=radius).export(path)
        assert load_mesh(path).n_panels == 80


def test_an_obj_with_latin1_text_loads(tmp_path):
    """A comment and a material name in Latin-1 (not UTF-8): the file still loads, its
    geometry intact (the text is decoded by detection)."""
    path = tmp_path / "latin1.obj"
    text = (
        "# modèle réalisé à Toulouse\n"
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
        "usemtl aluminium_poli\n"
        "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
    )
    path.write_bytes(text.encode("latin-1"))
    with pytest.raises(UnicodeDecodeError):
        path.read_bytes().decode("utf-8")
    mesh = load_mesh(path, accept_size=False)
    assert mesh.n_panels == 4
    assert mesh.total_area == pytest.approx(1.5 + math.sqrt(3) / 2)


def test_triangle_geometry_gives_numpys_numbers():
    """Normals, areas and barycentres as np.cross, np.linalg.norm and np.mean give them, bit
    for bit (meshes posed from parts must equal the parts merged), at three scales."""
    rng = np.random.default_rng(11)
    for scale in (1e-3, 1.0, 1e3):
        tri = rng.normal(size=(5000, 3, 3)) * scale + rng.normal(size=3) * 10 * scale
        cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        double_area = np.linalg.norm(cross, axis=1)
        normals, areas, barycentres = triangle_geometry(tri)
        np.testing.assert_array_equal(normals, cross / double_area[:, None])
        np.testing.assert_array_equal(areas, 0.5 * double_area)
        np.testing.assert_array_equal(barycentres, tri.mean(axis=1))
        assert all(a.flags.c_contiguous for a in (normals, areas, barycentres))
