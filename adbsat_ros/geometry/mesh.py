"""Triangulated satellite surface: loading, checking and per-panel geometry.

A :class:`PanelMesh` holds what the panel method needs for every triangle (panel): vertices,
outward unit normal, area, barycentre and material, as contiguous float64 arrays in the mesh
(geometric, "G") frame of the file, in metres after ``scale``.

Loading goes through trimesh, so every format it reads works (.obj, .stl ascii/binary, .ply,
.off, .glb, ...). Wavefront ``usemtl`` groups become named materials; other formats give one
material named ``"default"``.
"""

from __future__ import annotations

import logging
import math
import os
import re
from dataclasses import dataclass, field

import numpy as np
import trimesh

log = logging.getLogger(__name__)

#: Name of the material given to faces with no ``usemtl`` (and to meshes of other formats).
DEFAULT_MATERIAL = "default"

#: Faces whose area is below this fraction of the mean face area are dropped as degenerate.
ZERO_AREA_RELATIVE = 1e-12


class MeshError(ValueError):
    """A mesh that cannot be used, with a message naming the file and the problem."""


@dataclass(frozen=True)
class MeshReport:
    """What the loader found and changed.

    Attributes
    ----------
    dropped_zero_area : int
        Faces removed because their area was zero (degenerate triangles).
    flipped_components : int
        Closed connected components whose faces pointed inwards (negative signed volume) and
        were flipped to point outwards.
    open_components : int
        Connected components that are not closed (watertight); their inside/outside cannot be
        checked and they occlude from both sides when shading.
    watertight : bool
        True if every component is closed and consistently wound.
    convex : bool
        True if the mesh is one closed convex body (it then never shades itself).
    """

    dropped_zero_area: int = 0
    flipped_components: int = 0
    open_components: int = 0
    watertight: bool = True
    convex: bool = False


@dataclass(frozen=True, eq=False)
class PanelMesh:
    """Triangle panels of a satellite surface in the mesh frame G [m].

    Attributes
    ----------
    vertices : ndarray, shape (N, 3, 3)
        Corner coordinates of each panel [m]; ``vertices[i, k]`` is corner k of panel i.
    normals : ndarray, shape (N, 3)
        Outward unit normals, n = (P2 - P1) x (P3 - P1) / |...|.
    areas : ndarray, shape (N,)
        Panel areas [m^2].
    barycentres : ndarray, shape (N, 3)
        Panel centroids [m].
    material_index : ndarray of int, shape (N,)
        Index into ``material_names`` for each panel.
    material_names : tuple of str
        Names of the materials, in order of first appearance.
    report : MeshReport
        What loading found and changed.
    source : str
        Where the mesh came from (a path, or a description).
    """

    vertices: np.ndarray
    normals: np.ndarray
    areas: np.ndarray
    barycentres: np.ndarray
    material_index: np.ndarray
    material_names: tuple
    report: MeshReport = field(default_factory=MeshReport)
    source: str = "<array>"

    @property
    def n_panels(self) -> int:
        """Number of panels N."""
        return int(self.areas.shape[0])

    @property
    def total_area(self) -> float:
        """Total wetted area sum(A_i) [m^2]."""
        return float(self.areas.sum())

    @property
    def x_extent(self) -> float:
        """max x - min x over all vertices [m] (ADBSat's reference length)."""
        x = self.vertices[:, :, 0]
        return float(x.max() - x.min())

    @property
    def bounds(self) -> np.ndarray:
        """Axis-aligned bounding box, shape (2, 3): min and max corner [m]."""
        v = self.vertices.reshape(-1, 3)
        return np.stack([v.min(axis=0), v.max(axis=0)])

    def to_trimesh(self) -> trimesh.Trimesh:
        """A trimesh.Trimesh of the panels, face i being panel i (vertices merged)."""
        mesh = trimesh.Trimesh(
            vertices=self.vertices.reshape(-1, 3),
            faces=np.arange(3 * self.n_panels).reshape(-1, 3),
            process=False,
        )
        mesh.merge_vertices()
        return mesh

    def fingerprint(self) -> str:
        """A short hash of the panel geometry and materials, to match databases to meshes."""
        import hashlib

        h = hashlib.sha256()
        h.update(np.ascontiguousarray(np.round(self.vertices, 9)).tobytes())
        h.update(np.ascontiguousarray(self.material_index).tobytes())
        h.update("\0".join(self.material_names).encode())
        return h.hexdigest()[:16]


def panels_from_arrays(
    vertices,
    faces,
    material_index=None,
    material_names=(DEFAULT_MATERIAL,),
    *,
    source="<array>",
    fix_normals=True,
) -> PanelMesh:
    """Build a checked :class:`PanelMesh` from vertex and face arrays.

    Parameters
    ----------
    vertices : array_like, shape (V, 3)
        Vertex coordinates [m].
    faces : array_like of int, shape (N, 3)
        Vertex indices of each triangle; the winding sets the normal (right-hand rule).
    material_index : array_like of int, shape (N,), optional
        Material of each face (index into ``material_names``); default all 0.
    material_names : sequence of str
        Material names.
    source : str
        Name used in messages.
    fix_normals : bool
        Flip closed components with negative signed volume so normals point outwards.

    Raises
    ------
    MeshError
        No faces, NaN/Inf coordinates, bad indices, or nothing left after dropping degenerate faces.
    """
    vertices = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces)
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise MeshError(f"{source}: vertices must have shape (V, 3), got {vertices.shape}")
    if faces.size == 0:
        raise MeshError(f"{source}: the mesh has no faces")
    if faces.ndim != 2 or faces.shape[1] != 3:
        raise MeshError(f"{source}: faces must be triangles, shape (N, 3), got {faces.shape}")
    if not np.issubdtype(faces.dtype, np.integer):
        raise MeshError(f"{source}: face indices must be integers")
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise MeshError(f"{source}: face indices out of range 0..{len(vertices) - 1}")
    bad = ~np.isfinite(vertices).all(axis=1)
    if bad.any():
        raise MeshError(
            f"{source}: {int(bad.sum())} vertices have NaN or Inf coordinates "
            f"(first: vertex {int(np.flatnonzero(bad)[0])})"
        )
    if material_index is None:
        material_index = np.zeros(len(faces), dtype=np.int64)
    material_index = np.asarray(material_index, dtype=np.int64)
    if material_index.shape != (len(faces),):
        raise MeshError(f"{source}: material_index must have one entry per face")
    material_names = tuple(str(m) for m in material_names)
    if material_index.min() < 0 or material_index.max() >= len(material_names):
        raise MeshError(f"{source}: material_index out of range of material_names")

    tri = vertices[faces]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    double_area = np.linalg.norm(cross, axis=1)
    scale = np.abs(tri).max() if tri.size else 1.0
    degenerate = double_area <= ZERO_AREA_RELATIVE * max(scale, 1e-300) ** 2
    n_dropped = int(degenerate.sum())
    if n_dropped:
        log.warning("%s: dropped %d zero-area faces", source, n_dropped)
        keep = ~degenerate
        faces, material_index = faces[keep], material_index[keep]
    if len(faces) == 0:
        raise MeshError(f"{source}: every face has zero area")

    # Orientation and closedness, per connected component (separate bodies are common).
    tm = trimesh.Trimesh(vertices=vertices, faces=faces, process=False)
    tm.merge_vertices()
    faces_merged = tm.faces
    labels = trimesh.graph.connected_component_labels(
        tm.face_adjacency, node_count=len(faces_merged)
    )
    flipped = 0
    open_components = 0
    flip = np.zeros(len(faces), dtype=bool)
    n_components = int(labels.max()) + 1
    for comp in range(n_components):
        sel = labels == comp
        part = trimesh.Trimesh(vertices=tm.vertices, faces=faces_merged[sel], process=False)
        part.remove_unreferenced_vertices()
        if not (part.is_watertight and part.is_winding_consistent):
            open_components += 1
            continue
        if fix_normals and part.volume < 0:
            flip[sel] = True
            flipped += 1
    if open_components:
        log.warning(
            "%s: %d of %d connected components are open or non-manifold; their inward/outward "
            "orientation cannot be checked (shading still works)",
            source,
            open_components,
            n_components,
        )
    if flipped:
        log.warning(
            "%s: %d closed components had inward-facing normals (negative signed volume); "
            "flipped them outwards",
            source,
            flipped,
        )
        faces = faces.copy()
        faces[flip] = faces[flip][:, ::-1]

    tri = np.ascontiguousarray(vertices[faces])
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    double_area = np.linalg.norm(cross, axis=1)
    normals = np.ascontiguousarray(cross / double_area[:, None])
    convex = False
    if open_components == 0 and n_components == 1:
        tm_fixed = trimesh.Trimesh(vertices=vertices, faces=faces, process=False)
        tm_fixed.merge_vertices()
        convex = bool(tm_fixed.is_convex)
    report = MeshReport(
        dropped_zero_area=n_dropped,
        flipped_components=flipped,
        open_components=open_components,
        watertight=open_components == 0,
        convex=convex,
    )
    return PanelMesh(
        vertices=tri,
        normals=normals,
        areas=np.ascontiguousarray(0.5 * double_area),
        barycentres=np.ascontiguousarray(tri.mean(axis=1)),
        material_index=np.ascontiguousarray(material_index),
        material_names=material_names,
        report=report,
        source=source,
    )


_FACE_LINE = re.compile(r"^\s*f\s+(.*)$")
_USEMTL_LINE = re.compile(r"^\s*usemtl\s+(.*?)\s*$")


def _obj_material_runs(path: str):
    """Runs of consecutive faces sharing a ``usemtl`` name in an OBJ file.

    Returns a list of ``(material_name, n_triangles)`` in file order; an n-gon counts as
    n - 2 triangles (trimesh triangulates polygons as a fan).
    """
    runs = []
    current = None
    count = 0
    with open(path, "r", errors="replace") as fh:
        for line in fh:
            m = _USEMTL_LINE.match(line)
            if m:
                if count:
                    runs.append((current, count))
                current, count = m.group(1) or None, 0
                continue
            m = _FACE_LINE.match(line)
            if m:
                count += max(len(m.group(1).split()) - 2, 0)
    if count:
        runs.append((current, count))
    return runs


def _load_obj(path: str):
    """Vertices, faces and per-face material names of an OBJ file, through trimesh."""
    runs = _obj_material_runs(path)
    names = {name for name, _ in runs}
    if names <= {None}:
        tm = trimesh.load(path, force="mesh", process=False, skip_materials=True)
        return tm.vertices, tm.faces, None, (DEFAULT_MATERIAL,)
    # trimesh splits an OBJ at every usemtl into one geometry per run (group_material=False);
    # its scene keeps the runs in reverse file order. Verify the split against our own count.
    scene = trimesh.load(
        path,
        force="scene",
        process=False,
        group_material=False,
        skip_materials=True,
        maintain_order=True,
    )
    geoms = list(scene.geometry.values())[::-1]
    counts = [len(g.faces) for g in geoms]
    if counts != [n for _, n in runs]:
        raise MeshError(
            f"{path}: could not map usemtl groups to faces (trimesh read runs of {counts} "
            f"faces, the file has {[n for _, n in runs]})"
        )
    material_names = []
    for name, _ in runs:
        name = name or DEFAULT_MATERIAL
        if name not in material_names:
            material_names.append(name)
    verts, faces, mat = [], [], []
    offset = 0
    for (name, _), g in zip(runs, geoms):
        verts.append(np.asarray(g.vertices, dtype=float))
        faces.append(np.asarray(g.faces, dtype=np.int64) + offset)
        mat.append(np.full(len(g.faces), material_names.index(name or DEFAULT_MATERIAL)))
        offset += len(g.vertices)
    return np.vstack(verts), np.vstack(faces), np.concatenate(mat), tuple(material_names)


def load_mesh(path, scale: float = 1.0, *, fix_normals: bool = True) -> PanelMesh:
    """Load a triangulated surface mesh from a file.

    Parameters
    ----------
    path : str or os.PathLike
        Mesh file in any format trimesh reads (.obj, .stl, .ply, .off, .glb, ...).
    scale : float
        Factor applied to all coordinates to get metres (e.g. 1e-3 for CAD in millimetres).
    fix_normals : bool
        Flip closed bodies whose faces point inwards (negative signed volume), with a warning.

    Returns
    -------
    PanelMesh
        Panels in the file's coordinate frame, scaled to metres.

    Raises
    ------
    MeshError
        Missing or unreadable file, no faces, NaN/Inf vertices, or no usable face.
    """
    path = os.fspath(path)
    if not math.isfinite(scale) or scale <= 0:
        raise MeshError(f"{path}: scale must be a finite number > 0, got {scale!r}")
    if not os.path.isfile(path):
        raise MeshError(f"mesh file not found: {path}")
    try:
        if path.lower().endswith(".obj"):
            vertices, faces, material_index, material_names = _load_obj(path)
        else:
            tm = trimesh.load(path, force="mesh", process=False)
            vertices, faces = tm.vertices, tm.faces
            material_index, material_names = None, (DEFAULT_MATERIAL,)
    except MeshError:
        raise
    except Exception as exc:  # trimesh raises many types for unreadable files
        raise MeshError(f"{path}: cannot read mesh ({type(exc).__name__}: {exc})") from exc
    vertices = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces)
    if faces.size == 0:
        raise MeshError(f"{path}: the mesh has no faces")
    return panels_from_arrays(
        vertices * scale,
        faces.astype(np.int64),
        material_index,
        material_names,
        source=path,
        fix_normals=fix_normals,
    )


def panels_from_trimesh(mesh: trimesh.Trimesh, *, source="<trimesh>", **kwargs) -> PanelMesh:
    """A checked :class:`PanelMesh` of a trimesh.Trimesh (one material, ``"default"``)."""
    return panels_from_arrays(mesh.vertices, mesh.faces, source=source, **kwargs)


def resolve_mesh(spec, scale: float = 1.0) -> PanelMesh:
    """A PanelMesh from a file path, or the bundled example for the name ``"example"``."""
    from adbsat_ros.geometry.example_satellite import EXAMPLE_MESH_NAME, example_satellite

    if str(spec) == EXAMPLE_MESH_NAME:
        mesh = example_satellite()
        if scale != 1.0:
            raise MeshError("the example mesh is in metres; scale applies to mesh files only")
        return mesh
    return load_mesh(spec, scale=scale)
