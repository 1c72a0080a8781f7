"""Triangulated satellite surface: :class:`PanelMesh` (mesh frame G, metres) and its checks.
trimesh is imported only when a mesh is checked (docs/benchmarks.md)."""

from __future__ import annotations

import hashlib
import logging
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from adbsat_ros.bounds import BOUNDS
from adbsat_ros.geometry.frames import cross

if TYPE_CHECKING:
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
    """What the loader found and changed: degenerate faces dropped, inward components flipped, open
    components (occluding from both sides), closed and wound, one convex body (no self-shading)."""

    dropped_zero_area: int = 0
    flipped_components: int = 0
    open_components: int = 0
    watertight: bool = True
    convex: bool = False
    components: int = 1


@dataclass(frozen=True, eq=False)
class PanelMesh:
    """Triangle panels of a satellite surface in the mesh frame G [m]. ``vertices`` (N, 3, 3)
    [m]; ``normals`` outward, (P2 - P1) x (P3 - P1) normalised; ``areas`` [m^2]; ``barycentres``
    [m]; ``material_index`` into ``material_names`` (by first use)."""

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
        """max x - min x of the vertices [m] (ADBSat's reference length)."""
        x = self.vertices[:, :, 0]
        return float(x.max() - x.min())

    @property
    def bounds(self) -> np.ndarray:
        """Axis-aligned bounding box, shape (2, 3): min and max corner [m]."""
        v = self.vertices.reshape(-1, 3)
        return np.array([v.min(axis=0), v.max(axis=0)])

    def to_trimesh(self) -> trimesh.Trimesh:
        """A trimesh.Trimesh of the panels, face i being panel i (vertices merged)."""
        import trimesh

        mesh = trimesh.Trimesh(
            vertices=self.vertices.reshape(-1, 3),
            faces=np.arange(3 * self.n_panels).reshape(-1, 3),
            process=False,
        )
        mesh.merge_vertices()
        return mesh

    def fingerprint(self) -> str:
        """A short hash of the panel geometry and materials, to match databases to meshes."""
        h = hashlib.sha256()
        h.update(np.ascontiguousarray(np.round(self.vertices, 9)).tobytes())
        h.update(np.ascontiguousarray(self.material_index).tobytes())
        h.update("\0".join(self.material_names).encode())
        return h.hexdigest()[:16]


def signed_volume(triangles: np.ndarray) -> float:
    """Volume of closed triangles (K, 3, 3) [m^3], outwards > 0: sum det(P1, P2, P3) / 6."""
    p1, p2, p3 = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    return float(np.einsum("ij,ij->", p1, np.cross(p2, p3)) / 6.0)


def panels_from_arrays(
    vertices,
    faces,
    material_index=None,
    material_names=(DEFAULT_MATERIAL,),
    *,
    source="<array>",
    fix_normals=True,
) -> PanelMesh:
    """A checked :class:`PanelMesh` of ``vertices`` (V, 3) [m] and ``faces`` (N, 3).
    The winding sets the normal (right-hand rule); ``fix_normals`` flips inward closed components.
    MeshError: no faces, NaN/Inf or beyond ``mesh_coordinate``, bad indices, all degenerate."""
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
    rule = BOUNDS["mesh_coordinate"]
    far = np.flatnonzero(((vertices < rule.low) | (vertices > rule.high)).any(axis=1))
    if far.size:
        raise MeshError(
            f"{source}: vertex {int(far[0])} at ({', '.join(f'{x:g}' for x in vertices[far[0]])})"
            f" m has a coordinate outside {rule.text()} ({rule.reason})"
            + (f"; {far.size} vertices are outside" if far.size > 1 else "")
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
        keep = ~degenerate
        faces, material_index = faces[keep], material_index[keep]
    if len(faces) == 0:
        raise MeshError(f"{source}: every face has zero area")

    # Orientation and closedness, per connected component (separate bodies are common).
    import trimesh

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
        part = (
            tm
            if n_components == 1
            else trimesh.Trimesh(vertices=tm.vertices, faces=faces_merged[sel], process=False)
        )
        if not (part.is_watertight and part.is_winding_consistent):
            open_components += 1
            continue
        if fix_normals and signed_volume(tm.vertices[part.faces]) < 0:
            flip[sel] = True
            flipped += 1
    if flipped:
        faces = faces.copy()
        faces[flip] = faces[flip][:, ::-1]

    tri = np.ascontiguousarray(vertices[faces])
    normals, areas, barycentres = triangle_geometry(tri)
    convex = False
    if open_components == 0 and n_components == 1:
        # the merged mesh with its orientation fixed (the vertices are merged once, above)
        if flipped:
            tm = trimesh.Trimesh(vertices=tm.vertices, faces=faces_merged[:, ::-1], process=False)
        convex = bool(tm.is_convex)
    report = MeshReport(
        dropped_zero_area=n_dropped,
        flipped_components=flipped,
        open_components=open_components,
        watertight=open_components == 0,
        convex=convex,
        components=n_components,
    )
    log_report(source, report)
    return PanelMesh(
        vertices=tri,
        normals=normals,
        areas=areas,
        barycentres=barycentres,
        material_index=np.ascontiguousarray(material_index),
        material_names=material_names,
        report=report,
        source=source,
    )


def triangle_geometry(tri: np.ndarray) -> tuple:
    """Unit normals (right-hand rule), areas [m^2] and barycentres [m] of triangles (N, 3, 3)."""
    t = np.asarray(tri, dtype=float)
    c = cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    double_area = np.linalg.norm(c, axis=1)
    normals = c / double_area[:, None]
    barycentres = (t[:, 0] + t[:, 1] + t[:, 2]) / 3.0
    return normals, 0.5 * double_area, barycentres


def log_report(source: str, report: MeshReport) -> None:
    """Warn of what the checks of the mesh ``source`` found and changed."""
    if report.dropped_zero_area:
        log.warning("%s: dropped %d zero-area faces", source, report.dropped_zero_area)
    if report.open_components:
        log.warning(
            "%s: %d of %d connected components are open or non-manifold; their inward/outward "
            "orientation cannot be checked (shading still works)",
            source,
            report.open_components,
            report.components,
        )
    if report.flipped_components:
        log.warning(
            "%s: %d closed components had inward-facing normals (negative signed volume); "
            "flipped them outwards",
            source,
            report.flipped_components,
        )


#: Units a mesh file is often written in, with their factor to metres.
_UNITS = ((1e-3, "millimetres"), (1e-2, "centimetres"), (0.0254, "inches"), (1e3, "kilometres"))


def check_size(path, mesh: PanelMesh) -> None:
    """MeshError if the mesh is no satellite's size (``mesh_extent``), naming the unit."""
    corners = mesh.vertices.reshape(-1, 3)
    extent = float(np.max(corners.max(axis=0) - corners.min(axis=0)))
    rule = BOUNDS["mesh_extent"]
    if rule.contains(extent):
        return
    likely = [(f, unit) for f, unit in _UNITS if rule.contains(extent * f)]
    hint = f"its units are probably {likely[0][1]} (scale {likely[0][0]:g}); " if likely else ""
    raise MeshError(
        f"{path}: the mesh is {extent:.6g} m across, outside {rule.text()} ({rule.reason}): "
        f"{hint}give the scale to metres, or accept the size as it is (--accept-size, "
        "parameter mesh_accept_size)"
    )
