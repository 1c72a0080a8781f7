"""Property tests (hypothesis) of reading mesh files: a closed convex body written as .obj, .off or
ASCII .ply, every way those formats allow (byte-order marks, line ends, comments, blank lines,
unused vertices, indices counted back, materials), loads as exactly its triangles; a line that
cannot be read whole is refused with its file and line."""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

from adbsat_ros.geometry.loading import load_mesh
from adbsat_ros.geometry.mesh import MeshError
from adbsat_ros.geometry.mesh_files import _obj_arrays, read_obj_by_line

SETTINGS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])

MARKS = {
    "none": lambda text: text.encode(),
    "utf-8": lambda text: b"\xef\xbb\xbf" + text.encode(),
    "utf-16-le": lambda text: b"\xff\xfe" + text.encode("utf-16-le"),
    "utf-16-be": lambda text: b"\xfe\xff" + text.encode("utf-16-be"),
}


def convex_body(seed: int, n_points: int, radius: float, inward: bool):
    """Vertices (V, 3) and triangles (F, 3) of the hull of points on a sphere, all facing
    outwards (or all inwards)."""
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(n_points, 3))
    points = radius * points / np.linalg.norm(points, axis=1)[:, None] + rng.uniform(-1, 1, 3)
    hull = ConvexHull(points)
    faces = hull.simplices.copy()
    tri = points[faces]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    outward = np.einsum("ij,ij->i", normal, tri.mean(axis=1) - points.mean(axis=0)) > 0
    faces[~outward] = faces[~outward][:, ::-1]
    return points, (faces[:, ::-1] if inward else faces)


class Written(NamedTuple):
    """A body's file written some way (its lines, line end, byte-order mark) and what it holds:
    vertices in the file's units, the used triangles in order, each triangle's material."""

    suffix: str
    lines: list
    end: str
    mark: str
    table: np.ndarray
    faces: np.ndarray
    materials: list
    scale: float

    def write(self, lines=None) -> Path:
        path = Path(tempfile.mkdtemp(prefix="mesh_files_")) / f"body.{self.suffix}"
        text = self.end.join(self.lines if lines is None else lines) + self.end
        path.write_bytes(MARKS[self.mark](text))
        return path


@st.composite
def mesh_files(draw, suffixes=("obj", "off", "ply")):
    """A :class:`Written` body."""
    suffix = draw(st.sampled_from(suffixes))
    scale = draw(st.sampled_from([1.0, 1e-3]))
    vertices, faces = convex_body(
        draw(st.integers(0, 2**32 - 1)),
        draw(st.integers(4, 16)),
        draw(st.floats(0.05, 20.0)),
        draw(st.booleans()),
    )
    vertices = vertices / scale
    # unused vertices, anywhere in the list
    n_unused = draw(st.integers(0, 3))
    order = draw(st.permutations(range(len(vertices) + n_unused)))
    table = np.concatenate([vertices, np.full((n_unused, 3), 0.25 / scale)])[np.argsort(order)]
    faces = np.asarray(order)[faces]  # (the place of each vertex in the table)
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    if suffix == "obj":
        names = draw(st.lists(st.sampled_from(["hull", "radiator", "default"]), max_size=3))
        lines, materials = obj_lines(table, faces, names, rng)
    elif suffix == "off":
        lines, materials = off_lines(table, faces, rng), ["default"] * len(faces)
    else:
        lines, materials = ply_lines(table, faces), ["default"] * len(faces)
    end = draw(st.sampled_from(["\n", "\r\n"] + (["\r"] if suffix != "ply" else [])))
    mark = draw(st.sampled_from(sorted(MARKS)))
    return Written(suffix, lines, end, mark, table, faces, materials, scale)


def noise(rng, lines: list, blank=True) -> list:
    """``lines`` with comments and blank lines among them and after some."""
    out = []
    for line in lines:
        roll = rng.integers(0, 8)
        if roll == 0:
            out.append("# a comment" if not blank or rng.integers(0, 2) else "")
        out.append(line + ("  # a note" if roll == 1 else ""))
    return out


def obj_lines(table, faces, names, rng):
    lines = []
    for x, y, z in table.tolist():
        pad = "\t" if rng.integers(0, 2) else " "
        lines += [f"{' ' * int(rng.integers(0, 2))}v{pad}{x!r} {y!r}{pad}{z!r}", "vn 0 0 1"]
    lines += ["vt 0 0", "g body", "s off"]
    runs = np.sort(rng.integers(0, len(faces), len(names)))
    materials, current = [], "default"
    for k, face in enumerate(faces.tolist()):
        for run, name in zip(runs, names):
            if run == k:
                lines.append(f"usemtl {name}")
                current = name
        style = int(rng.integers(0, 4))
        if style == 0:
            refs = [str(i + 1) for i in face]
        elif style == 1:  # counted back from the last vertex
            refs = [str(i - len(table)) for i in face]
        elif style == 2:
            refs = [f"{i + 1}/1/1" for i in face]
        else:
            refs = [f"{i + 1}//1" for i in face]
        lines.append("f " + " ".join(refs))
        materials.append(current)
    return noise(rng, lines), materials


def off_lines(table, faces, rng):
    lines = ["OFF", f"{len(table)} {len(faces)} 0"]
    lines += [f"{x!r} {y!r} {z!r}" for x, y, z in table.tolist()]
    lines += ["3 " + " ".join(map(str, face)) for face in faces.tolist()]
    return noise(rng, lines)


def ply_lines(table, faces):
    lines = ["ply", "format ascii 1.0", "comment a body", f"element vertex {len(table)}"]
    lines += [f"property double {c}" for c in "xyz"]
    lines += [f"element face {len(faces)}", "property list uchar int vertex_indices"]
    lines += ["end_header"] + [f"{x!r} {y!r} {z!r}" for x, y, z in table.tolist()]
    return lines + ["3 " + " ".join(map(str, face)) for face in faces.tolist()]


@SETTINGS
@given(mesh_files())
def test_a_body_written_any_way_loads_as_its_triangles(written):
    mesh = load_mesh(written.write(), scale=written.scale, store=None)
    # the file's triangles, in order, at the scale; a body written inwards is turned outwards
    expected = (written.table * written.scale)[written.faces]
    assert mesh.report.watertight and mesh.report.dropped_zero_area == 0
    if mesh.report.flipped_components:
        expected = expected[:, ::-1]
    np.testing.assert_array_equal(mesh.vertices, expected)
    assert [mesh.material_names[i] for i in mesh.material_index] == written.materials
    # turned outwards: every normal points away from the body's centre
    centre = expected.reshape(-1, 3).mean(axis=0)
    assert np.all(np.einsum("ij,ij->i", mesh.normals, mesh.barycentres - centre) > 0)
    if written.suffix == "obj":  # the fast path takes the file, and reads it as line by line
        text = written.end.join(written.lines)
        fast, reference = _obj_arrays(text), read_obj_by_line(text, "body")
        assert fast is not None
        for got, want in zip(fast, reference, strict=True):
            np.testing.assert_array_equal(got, want)


#: Lines no reader may pass over, each refused with its line: anywhere in an .obj; among an
#: .off's vertices and faces (the last ones: among its faces only).
BROKEN = {
    "obj": ["v 1 2", "v 1 two 3", "v 1 2 3 4 5", "vx 1 2 3", "f 1 2", "f 1 0 2", "f 1 2 99999"],
    "off": ["1 2", "1 two 3", "3 0 1"],
}


@SETTINGS
@given(mesh_files(suffixes=("obj", "off")), st.data())
def test_a_line_that_cannot_be_read_whole_is_refused_with_its_line(written, data):
    bad = data.draw(st.sampled_from(BROKEN[written.suffix]))
    where = range(len(written.lines) + 1)
    if written.suffix == "off":  # after the keyword and counts: among the vertices or faces
        content = [k for k, line in enumerate(written.lines) if line.split("#")[0].strip()]
        n_vertices = len(written.table)
        where = range(content[2] if bad != "3 0 1" else content[2 + n_vertices], content[-1])
    index = data.draw(st.sampled_from(where))
    lines = list(written.lines)
    lines.insert(index, bad)
    path = written.write(lines)
    with pytest.raises(MeshError, match=rf"^{path}, line {index + 1}: "):
        load_mesh(path, scale=written.scale, store=None)
