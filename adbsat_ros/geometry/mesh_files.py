"""Mesh files read whole: .obj and .off here, every line read or refused; others by trimesh.

trimesh's .obj and .off readers silently skip lines they do not expect (a byte-order mark, an
indented ``v``). A byte-order mark selects UTF-8 or UTF-16; polygons become fans.
"""

from __future__ import annotations

import io
import math
import os
import re
from typing import NamedTuple

import numpy as np

from adbsat_ros.geometry.mesh import DEFAULT_MATERIAL, MeshError

#: Byte-order marks and the encodings they select.
BYTE_ORDER_MARKS = (
    (b"\xef\xbb\xbf", "utf-8"),
    (b"\xff\xfe", "utf-16-le"),
    (b"\xfe\xff", "utf-16-be"),
)
#: OBJ statements that carry no surface (normals, texture, groups, curves...): passed over.
OBJ_PASSED_OVER = frozenset(
    "vt vn vp o g s mg mtllib usemap maplib l p cstype deg bmat step curv curv2 surf parm trim "
    "hole scrv sp end con bevel c_interp d_interp lod shadow_obj trace_obj ctech stech".split()
)
#: Numbers after the three coordinates of a vertex line: OBJ's weight w, colours r g b (a
#: common extension); OFF's normal, colour and texture coordinates.
_OBJ_VERTEX_VALUES = (3, 4, 6, 7)
_OFF_VERTEX_VALUES = range(3, 13)
#: The OFF keywords read: texture coordinates, colours, normals before ``OFF``.
_OFF_KEYWORD = re.compile(r"(ST)?C?N?OFF")
_LINE_END = re.compile(r"\r\n|\r|\n")


class MeshArrays(NamedTuple):
    """A mesh file's vertices (V, 3) in its units, triangles (N, 3) and materials."""

    vertices: np.ndarray
    faces: np.ndarray
    material_index: np.ndarray | None
    material_names: tuple


def check_mesh_path(path: str) -> None:
    """MeshError unless ``path`` is a file: naming a directory as one, or a missing file."""
    if os.path.isdir(path):
        raise MeshError(f"{path}: is a directory, not a mesh file")
    if not os.path.isfile(path):
        raise MeshError(f"mesh file not found: {path}")


def decode_text(data: bytes, source: str) -> str:
    """The text of a mesh file's bytes; MeshError for a wrong encoding or a NUL."""
    for mark, encoding in BYTE_ORDER_MARKS:
        if data.startswith(mark):
            try:
                text = data[len(mark) :].decode(encoding)
            except UnicodeDecodeError as exc:
                raise MeshError(
                    f"{source}: starts with the byte-order mark of {encoding.upper()} but is "
                    f"not {encoding.upper()} text (byte {exc.start + len(mark)})"
                ) from None
            break
    else:
        text = data.decode("utf-8", errors="replace")
    if "\x00" in text:
        line = text.count("\n", 0, text.index("\x00")) + 1
        raise MeshError(
            f"{source}, line {line}: a NUL character: not a text mesh file (UTF-16 text must "
            "start with its byte-order mark)"
        )
    return text


def _statements(text: str):
    """``(line number, text)`` of every non-blank line, comments cut, continuations joined."""
    joined, first = "", None
    for number, line in enumerate(_LINE_END.split(text), 1):
        first = first or number
        line = line.split("#", 1)[0].rstrip()
        if line.endswith("\\"):
            joined += line[:-1]
            continue
        statement = (joined + line).strip()
        if statement:
            yield first, statement
        joined, first = "", None
    if joined.strip():
        yield first, joined.strip()


def _error(source: str, line: int, problem: str) -> MeshError:
    return MeshError(f"{source}, line {line}: {problem}")


def _coordinates(values, source, line, counts, statement) -> list:
    """The three coordinates of a vertex line's ``values`` (``counts`` of numbers allowed)."""
    if len(values) not in counts:
        raise _error(
            source,
            line,
            f"a vertex has three coordinates x y z ({statement}), got {' '.join(values)!r}",
        )
    try:
        numbers = [float(v) for v in values]
    except ValueError:
        bad = next(v for v in values if not _is_number(v))
        raise _error(source, line, f"{bad!r} is not a number (vertex {' '.join(values)})") from None
    for value, text in zip(numbers[:3], values):
        if not math.isfinite(value):
            raise _error(source, line, f"vertex coordinate {text!r} is not a finite number")
    return numbers[:3]


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _fan(corners: list) -> list:
    """Triangles (0, k, k + 1) of a polygon's corners."""
    return [(corners[0], corners[k], corners[k + 1]) for k in range(1, len(corners) - 1)]


def read_obj(text: str, source: str) -> MeshArrays:
    """The vertices, triangles and ``usemtl`` materials of an OBJ text; MeshError: a bad line."""
    arrays = None if "\\" in text else _obj_arrays(text)
    return arrays if arrays is not None else read_obj_by_line(text, source)


#: An OBJ face's corners, each ``i``, ``i/t``, ``i//n`` or ``i/t/n``; the vertex index of each.
_OBJ_CORNERS = re.compile(r"(?:-?\d+(?:/(?:-?[1-9]\d*)?){0,2}(?:\s+|$))+")
_OBJ_VERTEX_INDEX = re.compile(r"(-?\d+)\S*")


def _obj_arrays(text: str) -> MeshArrays | None:
    """:func:`read_obj_by_line`'s arrays of a file of plain lines, or None."""
    values, heads, counts, seen, materials, names, current = [], [], [], [], [], {}, None
    for line in _LINE_END.split(text):
        parts = (line.split("#", 1)[0] if "#" in line else line).split(None, 1)
        key, rest = (parts + ["", ""])[:2]
        if key == "v":
            vertex = rest.split()
            if len(vertex) != 3:
                return None
            values += vertex
        elif key == "f":
            if not _OBJ_CORNERS.fullmatch(rest):
                return None
            corners = _OBJ_VERTEX_INDEX.findall(rest)
            heads += corners
            counts.append(len(corners))
            seen.append(len(values) // 3)
            materials.append(names.setdefault(current or DEFAULT_MATERIAL, len(names)))
        elif key == "usemtl":
            current = rest.strip() or None
        elif key and key not in OBJ_PASSED_OVER:
            return None
    try:
        coords = np.array(values, dtype=float).reshape(-1, 3)
    except ValueError:
        return None
    counts = np.array(counts, dtype=np.int64)
    index = np.array(heads, dtype=np.int64)
    so_far = np.repeat(np.array(seen, dtype=np.int64), counts)
    bad = (index == 0) | (index < -so_far) | (index > len(coords)) | (counts < 3).any()
    if bad.any() or not np.isfinite(coords).all():
        return None
    index = np.where(index > 0, index - 1, index + so_far)
    # each polygon's fan (0, k, k + 1), k = 1 .. n - 2
    triangles = counts - 2
    polygon = np.repeat(np.arange(len(counts)), triangles)
    first = (np.cumsum(counts) - counts)[polygon]
    k = np.arange(triangles.sum()) - np.repeat(np.cumsum(triangles) - triangles, triangles) + 1
    faces = np.stack([index[first], index[first + k], index[first + k + 1]], axis=1)
    material_index = np.repeat(np.array(materials, dtype=np.int64), triangles)
    return MeshArrays(coords, faces, material_index, tuple(names) or (DEFAULT_MATERIAL,))


def read_obj_by_line(text: str, source: str) -> MeshArrays:
    """:func:`read_obj`, line by line, each checked as it is read."""
    coords, triangles, lines, materials = [], [], [], []
    names: dict = {}
    current = None
    for number, line in _statements(text):
        _, key, rest = line.partition(line.split(None, 1)[0])
        values = rest.split()
        if key == "v":
            coords.extend(_coordinates(values, source, number, _OBJ_VERTEX_VALUES, "w, r g b"))
        elif key == "f":
            corners = [_obj_corner(ref, len(coords) // 3, source, number) for ref in values]
            if len(corners) < 3:
                raise _error(source, number, f"a face needs three corners or more, got {line!r}")
            fan = _fan(corners)
            triangles.extend(fan)
            lines.extend([number] * len(fan))
            materials.extend([names.setdefault(current or DEFAULT_MATERIAL, len(names))] * len(fan))
        elif key == "usemtl":
            current = rest.strip() or None
        elif key not in OBJ_PASSED_OVER:
            raise _error(
                source,
                number,
                f"{key!r} is no OBJ statement (a line is a vertex 'v', a face 'f', 'usemtl', "
                "or a statement of no surface: vt vn o g s mtllib l ...)",
            )
    n_vertices = len(coords) // 3
    faces = np.array(triangles, dtype=np.int64).reshape(-1, 3)
    beyond = np.flatnonzero((faces >= n_vertices).any(axis=1))
    if beyond.size:
        index = int(faces[beyond[0]].max()) + 1
        raise _error(
            source,
            lines[beyond[0]],
            f"face corner {index} is beyond the file's {n_vertices} vertices (1..{n_vertices})",
        )
    return MeshArrays(
        np.array(coords, dtype=float).reshape(-1, 3),
        faces,
        np.array(materials, dtype=np.int64),
        tuple(names) or (DEFAULT_MATERIAL,),
    )


def _obj_corner(ref: str, n_vertices: int, source: str, line: int) -> int:
    """The 0-based vertex index of an OBJ face corner ``ref`` (``i[/t[/n]]``)."""
    parts = ref.split("/")
    try:
        if len(parts) > 3 or any(p and int(p) == 0 for p in parts[1:]):
            raise ValueError
        index = int(parts[0])
    except ValueError:
        raise _error(
            source, line, f"face corner {ref!r} is not i, i/t, i//n or i/t/n (indices from 1)"
        ) from None
    if index > 0:
        return index - 1  # (checked once every vertex is read: a later one may be named)
    if index == 0 or index < -n_vertices:
        raise _error(
            source,
            line,
            f"face corner {index} names no vertex: indices run from 1, or back from -1 (the "
            f"last vertex so far) to -{n_vertices}",
        )
    return n_vertices + index


def read_off(text: str, source: str) -> MeshArrays:
    """The vertices and triangles of an OFF text; MeshError naming a bad line or count."""
    statements = _statements(text)
    number, line = next(statements, (1, ""))
    keyword, *counts = line.split()
    if not _OFF_KEYWORD.fullmatch(keyword or ""):
        raise _error(
            source, number, f"an OFF file starts with OFF (or COFF, NOFF...), got {line!r}"
        )
    if not counts:
        number, line = next(statements, (number, ""))
        counts = line.split()
    try:
        n_vertices, n_faces = (int(c) for c in counts[:2])
        if len(counts) not in (2, 3) or min(n_vertices, n_faces) < 0:
            raise ValueError
    except ValueError:
        raise _error(
            source, number, f"expected the counts of vertices, faces [and edges], got {line!r}"
        ) from None
    coords, triangles, faces_read = [], [], 0
    statement = "then what the keyword adds: normal, colour, texture coordinates"
    for number, line in statements:
        if len(coords) < 3 * n_vertices:
            coords.extend(_coordinates(line.split(), source, number, _OFF_VERTEX_VALUES, statement))
        elif faces_read < n_faces:
            triangles.extend(_off_face(line.split(), n_vertices, source, number))
            faces_read += 1
        else:
            raise _error(
                source,
                number,
                f"a line beyond the {n_vertices} vertices and {n_faces} faces of the counts: "
                f"{line!r}",
            )
    if len(coords) < 3 * n_vertices or faces_read < n_faces:
        raise MeshError(
            f"{source}: its counts give {n_vertices} vertices and {n_faces} faces, the file has "
            f"{len(coords) // 3} vertices and {faces_read} faces"
        )
    return MeshArrays(
        np.array(coords, dtype=float).reshape(-1, 3),
        np.array(triangles, dtype=np.int64).reshape(-1, 3),
        None,
        (DEFAULT_MATERIAL,),
    )


def _off_face(values: list, n_vertices: int, source: str, line: int) -> list:
    """The triangles of an OFF face line's ``values`` (``k i1 .. ik``, a colour may follow)."""
    try:
        k = int(values[0])
        corners = [int(v) for v in values[1 : k + 1]]
        extra = values[k + 1 :]
        if k < 3 or len(corners) < k or len(extra) > 4 or not all(map(_is_number, extra)):
            raise ValueError
    except ValueError:
        raise _error(
            source,
            line,
            f"a face is 'k i1 .. ik' (k >= 3 corners, indices from 0; a colour may follow), "
            f"got {' '.join(values)!r}",
        ) from None
    outside = [i for i in corners if not 0 <= i < n_vertices]
    if outside:
        raise _error(
            source, line, f"face corner {outside[0]} is outside the vertices 0..{n_vertices - 1}"
        )
    return _fan(corners)


#: Mesh formats read here from their text.
TEXT_READERS = {".obj": read_obj, ".off": read_off}


def read_mesh_file(path) -> MeshArrays:
    """The arrays of the mesh file ``path``; MeshError naming it if unreadable or faceless."""
    path = os.fspath(path)
    check_mesh_path(path)
    suffix = os.path.splitext(path)[1].lower()
    try:
        if suffix in TEXT_READERS or suffix in (".stl", ".ply"):
            with open(path, "rb") as fh:
                data = fh.read()
            if suffix in TEXT_READERS:
                arrays = TEXT_READERS[suffix](decode_text(data, path), path)
            else:
                arrays = _trimesh_arrays(_without_mark(data, suffix, path), suffix[1:])
        else:
            arrays = _trimesh_arrays(path, None)
    except MeshError:
        raise
    except Exception as exc:  # (trimesh raises many types for unreadable files)
        raise MeshError(f"{path}: cannot read mesh ({type(exc).__name__}: {exc})") from exc
    if arrays.faces.size == 0:
        raise MeshError(f"{path}: the mesh has no faces")
    return arrays


def _without_mark(data: bytes, suffix: str, path: str) -> bytes:
    """An .stl's or .ply's bytes with a text byte-order mark handled (a binary STL as it is)."""
    if suffix == ".stl" and len(data) >= 84:
        if len(data) == 84 + 50 * int.from_bytes(data[80:84], "little"):
            return data
    if data.startswith(BYTE_ORDER_MARKS[0][0]):
        return data[len(BYTE_ORDER_MARKS[0][0]) :]
    if any(data.startswith(mark) for mark, _ in BYTE_ORDER_MARKS):
        return decode_text(data, path).encode("utf-8")
    return data


def _trimesh_arrays(source, file_type) -> MeshArrays:
    """The arrays of trimesh's reading of a path or of bytes."""
    import trimesh

    if file_type is not None:
        source = io.BytesIO(source)
    tm = trimesh.load(source, file_type=file_type, force="mesh", process=False)
    return MeshArrays(
        np.asarray(tm.vertices, dtype=float),
        np.asarray(tm.faces, dtype=np.int64).reshape(-1, 3),
        None,
        (DEFAULT_MATERIAL,),
    )
