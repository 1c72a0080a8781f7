"""Mesh files read whole: a byte-order mark or other line ends change nothing, a line that cannot
be read whole is refused with its file and line, a far vertex or a directory is named as such."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.loading import load_mesh
from adbsat_ros.geometry.mesh import MeshError

BOX = trimesh.creation.box(extents=(1.0, 0.8, 0.6))
#: A cube's OBJ with a vertex no face uses (after the cube's eight).
CUBE_LINES = [f"v {x} {y} {z}" for x, y, z in BOX.vertices.tolist()] + ["v 5 5 5"]
CUBE_LINES += ["f " + " ".join(str(i + 1) for i in face) for face in BOX.faces]
ENCODINGS = {
    "utf-8 mark": lambda text: b"\xef\xbb\xbf" + text.encode(),
    "utf-16-le mark": lambda text: b"\xff\xfe" + text.encode("utf-16-le"),
    "utf-16-be mark": lambda text: b"\xfe\xff" + text.encode("utf-16-be"),
    "crlf": lambda text: text.replace("\n", "\r\n").encode(),
    "cr": lambda text: text.replace("\n", "\r").encode(),
}


def panels(path, **kwargs):
    return load_mesh(path, store=None, **kwargs)


def assert_same_panels(a, b):
    np.testing.assert_array_equal(a.vertices, b.vertices)
    np.testing.assert_array_equal(a.normals, b.normals)
    assert a.material_names == b.material_names
    np.testing.assert_array_equal(a.material_index, b.material_index)


@pytest.mark.parametrize("encoding", sorted(ENCODINGS))
def test_a_byte_order_mark_or_other_line_ends_change_no_panel(tmp_path, encoding):
    text = "\n".join(CUBE_LINES) + "\n"
    plain, other = tmp_path / "plain.obj", tmp_path / "other.obj"
    plain.write_text(text)
    other.write_bytes(ENCODINGS[encoding](text))
    expected = panels(plain)
    assert expected.n_panels == 12 and expected.total_area == pytest.approx(BOX.area)
    assert_same_panels(panels(other), expected)


@pytest.mark.parametrize("encoding", ["utf-8 mark", "utf-16-le mark", "utf-16-be mark"])
@pytest.mark.parametrize("suffix", ["stl", "ply", "off"])
def test_text_formats_read_by_trimesh_or_here_take_a_byte_order_mark(tmp_path, suffix, encoding):
    text = {
        "stl": lambda: trimesh.exchange.stl.export_stl_ascii(BOX),
        "ply": lambda: trimesh.exchange.ply.export_ply(BOX, encoding="ascii").decode(),
        "off": lambda: trimesh.exchange.off.export_off(BOX),
    }[suffix]()
    plain, other = tmp_path / f"plain.{suffix}", tmp_path / f"other.{suffix}"
    plain.write_text(text)
    other.write_bytes(ENCODINGS[encoding](text))
    expected = panels(plain)
    assert expected.total_area == pytest.approx(BOX.area)
    assert_same_panels(panels(other), expected)


def test_obj_lines_written_every_way_give_the_same_panels(tmp_path):
    plain = tmp_path / "plain.obj"
    plain.write_text("\n".join(CUBE_LINES) + "\n")
    lines = ["# a cube, written every way", "mtllib none.mtl", "o cube", ""]
    for k, line in enumerate(CUBE_LINES):
        if line.startswith("v "):
            line = ("\t" if k % 2 else "  ") + line.replace(" ", "\t" if k % 3 else "  ")
            lines += [line + "  # a comment", "vn 0 0 1", "vt 0.5 0.5"]
        else:
            refs = line.split()[1:]
            if k % 3 == 0:  # counted back from the last vertex (9 so far)
                refs = [str(int(r) - 10) for r in refs]
            elif k % 3 == 1:
                refs = [f"{r}/1/1" for r in refs]
            else:
                refs = [f"{r}//1" for r in refs[:2]] + ["\\", refs[2] + "//1"]
            lines += ["s 1", "g side", "f " + " ".join(refs)]
    other = tmp_path / "other.obj"
    other.write_text("\n".join(lines).replace("\\ ", "\\\n"))
    assert_same_panels(panels(other), panels(plain))


BAD_OBJ_LINES = [
    ("v 1 2", "a vertex has three coordinates x y z"),
    ("v 1 x 3", "'x' is not a number"),
    ("v nan 0 0", "vertex coordinate 'nan' is not a finite number"),
    ("v 1 2 3 4 5", "a vertex has three coordinates x y z"),
    ("f 1 2", "a face needs three corners or more"),
    ("f 1 2 99", r"face corner 99 is beyond the file's 9 vertices \(1..9\)"),
    ("f 0 1 2", "face corner 0 names no vertex"),
    ("f -10 1 2", "face corner -10 names no vertex"),
    ("f 1/a 2 3", "face corner '1/a' is not i, i/t, i//n or i/t/n"),
    ("f 1.5 2 3", "face corner '1.5' is not"),
    ("vv 1 2 3", "'vv' is no OBJ statement"),
    ("\ufeffv 1 2 3", r"'\\ufeffv' is no OBJ statement"),  # (a mark inside the text: shown)
]


@pytest.mark.parametrize("line, message", BAD_OBJ_LINES)
def test_an_obj_line_that_cannot_be_read_whole_is_refused_with_its_line(tmp_path, line, message):
    path = tmp_path / "bad.obj"
    lines = list(CUBE_LINES)
    lines.insert(9, line)  # the tenth line: after the vertices
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(MeshError, match=rf"^{path}, line 10: {message}"):
        panels(path)


OFF_CUBE = trimesh.exchange.off.export_off(BOX).splitlines()
BAD_OFF = [
    (["OFF", "8 12"] + OFF_CUBE[2:3] + ["0 0"] + OFF_CUBE[4:], 4, "a vertex has three"),
    (OFF_CUBE[:-1] + ["3 1 2 8"], 22, "face corner 8 is outside the vertices 0..7"),
    (OFF_CUBE[:-1] + ["2 1 2"], 22, "a face is 'k i1 .. ik'"),
    (OFF_CUBE + ["3 1 2 3"], 23, "a line beyond the 8 vertices and 12 faces"),
    (["OFF", "8 x 0"] + OFF_CUBE[2:], 2, "expected the counts"),
    (["PLY"] + OFF_CUBE[1:], 1, "an OFF file starts with OFF"),
]


@pytest.mark.parametrize("lines, number, message", BAD_OFF)
def test_an_off_line_that_cannot_be_read_whole_is_refused_with_its_line(
    tmp_path, lines, number, message
):
    path = tmp_path / "bad.off"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(MeshError, match=rf"^{path}, line {number}: {message}"):
        panels(path)


def test_an_off_file_shorter_than_its_counts_is_refused(tmp_path):
    path = tmp_path / "short.off"
    path.write_text("\n".join(OFF_CUBE[:-2]) + "\n")
    with pytest.raises(MeshError, match="counts give 8 vertices and 12 faces, the file has 8 "):
        panels(path)


def test_off_comments_after_numbers_and_blank_lines_are_passed_over(tmp_path):
    plain, other = tmp_path / "plain.off", tmp_path / "other.off"
    plain.write_text("\n".join(OFF_CUBE) + "\n")
    other.write_text("# a cube\n\n" + "\n\n".join(f"{line}  # note" for line in OFF_CUBE) + "\n")
    assert_same_panels(panels(other), panels(plain))


@pytest.mark.parametrize("scale", [1.0, 1e-3])
def test_a_vertex_beyond_a_thousand_kilometres_is_refused_naming_it_and_the_range(tmp_path, scale):
    path = tmp_path / "far.obj"
    lines = list(CUBE_LINES)
    lines[3] = "v 1e300 0 0"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(MeshError) as caught:
        panels(path, scale=scale)
    text = str(caught.value)
    assert f"vertex 3 at ({1e300 * scale:g}, 0, 0) m" in text
    assert "outside [-1e+06, 1e+06] m" in text


def test_a_directory_is_named_as_no_mesh_file(tmp_path):
    with pytest.raises(MeshError, match=rf"^{tmp_path}: is a directory, not a mesh file$"):
        panels(tmp_path)
    with pytest.raises(MeshError, match="mesh file not found"):
        panels(tmp_path / "missing.obj")


def test_a_urdf_mesh_file_is_read_whole_byte_order_mark_and_all(tmp_path):
    (tmp_path / "plain.obj").write_text("\n".join(CUBE_LINES) + "\n")
    (tmp_path / "marked.obj").write_bytes(ENCODINGS["utf-8 mark"]("\n".join(CUBE_LINES)))
    bodies = []
    for name in ("plain", "marked"):
        urdf = tmp_path / f"{name}.urdf"
        urdf.write_text(
            f"<robot name='r'><link name='bus'><visual><geometry><mesh filename='{name}.obj'/>"
            "</geometry></visual></link></robot>"
        )
        bodies.append(ArticulatedBody.from_urdf(str(urdf)).mesh())
    assert bodies[0].total_area == pytest.approx(BOX.area)
    assert_same_panels(bodies[1], bodies[0])
    bad = tmp_path / "bad.obj"
    bad.write_text("\n".join(CUBE_LINES[:3] + ["v 1 2"] + CUBE_LINES[3:]) + "\n")
    urdf = tmp_path / "bad.urdf"
    urdf.write_text(
        "<robot name='r'><link name='bus'><visual><geometry><mesh filename='bad.obj'/>"
        "</geometry></visual></link></robot>"
    )
    with pytest.raises(MeshError, match=rf"{bad}, line 4: a vertex has three coordinates"):
        ArticulatedBody.from_urdf(str(urdf))
