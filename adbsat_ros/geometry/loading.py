"""Mesh files to a PanelMesh: any format trimesh reads, .obj materials from ``usemtl`` groups.

:func:`load_mesh` reads a file (scaled to metres), :func:`resolve_mesh` also accepts the name of
the bundled example satellite (:mod:`adbsat_ros.geometry.example_satellite`), and
:func:`panels_from_trimesh` converts a ``trimesh.Trimesh``. Every mesh is checked by
:func:`adbsat_ros.geometry.mesh.panels_from_arrays`, and kept checked in the mesh store
(:mod:`adbsat_ros.geometry.mesh_store`): a file loaded before is read back from there.

trimesh (which reads the files) and yourdfpy (URDF bodies) are imported when a file is parsed
or a URDF read, not with this module: importing trimesh takes about 0.6 s, more than the
command line may take to answer (docs/benchmarks.md, command line start-up).
"""

from __future__ import annotations

import math
import os
import re
from typing import TYPE_CHECKING

import numpy as np

from adbsat_ros.geometry.concave_bodies import CONCAVE_BODIES
from adbsat_ros.geometry.example_satellite import EXAMPLE_MESH_NAME, example_satellite
from adbsat_ros.geometry.example_urdf import (
    EXAMPLE_FINNED_NAME,
    EXAMPLE_URDF_NAME,
    example_finned_urdf,
    example_satellite_urdf,
)
from adbsat_ros.geometry.mesh import (
    DEFAULT_MATERIAL,
    MeshError,
    PanelMesh,
    check_size,
    log_report,
    panels_from_arrays,
)
from adbsat_ros.geometry.mesh_store import STORED_SUFFIXES, MeshStore

if TYPE_CHECKING:
    import trimesh

    from adbsat_ros.geometry.articulated import ArticulatedBody

#: The bundled URDF bodies by name.
BUNDLED_URDFS = {
    EXAMPLE_URDF_NAME: example_satellite_urdf,
    EXAMPLE_FINNED_NAME: example_finned_urdf,
}

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
    import trimesh

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


#: ``store`` of :func:`load_mesh` by default: the store of the environment's cache directory.
DEFAULT_STORE = "default"


def load_mesh(
    path,
    scale: float = 1.0,
    *,
    fix_normals: bool = True,
    accept_size: bool = False,
    store: MeshStore | str | None = DEFAULT_STORE,
) -> PanelMesh:
    """Load a triangulated surface mesh from a file.

    Parameters
    ----------
    path : str or os.PathLike
        Mesh file in any format trimesh reads (.obj, .stl, .ply, .off, .glb, ...).
    scale : float
        Factor applied to all coordinates to get metres (e.g. 1e-3 for CAD in millimetres).
    fix_normals : bool
        Flip closed bodies whose faces point inwards (negative signed volume), with a warning.
    accept_size : bool
        Take a mesh of scale 1 whose size is no satellite's (``mesh_extent`` of
        :data:`adbsat_ros.bounds.BOUNDS`: 1 mm to 200 m across), which is otherwise refused
        as probably not in metres.
    store : MeshStore, "default" or None
        Where the checked mesh is kept and, for a file of the same content loaded before, read
        back from (the same panels, report and warnings); by default the store of the
        environment's cache directory (``MeshStore.resolve``);
        None for none.

    Returns
    -------
    PanelMesh
        Panels in the file's coordinate frame, scaled to metres.

    Raises
    ------
    MeshError
        Missing or unreadable file, no faces, NaN/Inf vertices, no usable face, or a size
        that is no satellite's (naming the likely unit).
    """
    path = os.fspath(path)
    if not math.isfinite(scale) or scale <= 0:
        raise MeshError(f"{path}: scale must be a finite number > 0, got {scale!r}")
    if not os.path.isfile(path):
        raise MeshError(f"mesh file not found: {path}")
    store = MeshStore.resolve(store)
    if not path.lower().endswith(STORED_SUFFIXES):
        store = None
    try:
        key = None if store is None else store.key(path, scale, fix_normals)
    except OSError as exc:
        raise MeshError(f"{path}: cannot read mesh ({type(exc).__name__}: {exc})") from exc
    mesh = None if key is None else store.get(key, path)
    if mesh is not None:
        log_report(path, mesh.report)  # (what the checks found, told again)
    else:
        mesh = _parse(path, scale, fix_normals)
        if key is not None:
            store.put(key, mesh)
    if scale == 1.0 and not accept_size:
        check_size(path, mesh)
    return mesh


def _parse(path: str, scale: float, fix_normals: bool) -> PanelMesh:
    """The checked panels of the mesh file ``path``, parsed by trimesh."""
    import trimesh

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
    """A checked :class:`PanelMesh` of a trimesh.Trimesh (one material, ``"default"``).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Triangles in metres; the winding sets the outward normal (right-hand rule).
    source : str
        Name used in messages.
    **kwargs
        ``fix_normals`` etc., as :func:`adbsat_ros.geometry.mesh.panels_from_arrays`.

    Returns
    -------
    PanelMesh

    Raises
    ------
    MeshError
        As :func:`adbsat_ros.geometry.mesh.panels_from_arrays`.
    """
    return panels_from_arrays(mesh.vertices, mesh.faces, source=source, **kwargs)


def is_urdf(spec) -> bool:
    """Whether a mesh spec names a URDF: a ``.urdf`` file or a bundled one (BUNDLED_URDFS)."""
    name = str(spec)
    return name in BUNDLED_URDFS or name.lower().endswith(".urdf")


def articulated_body(spec, accept_size: bool = False) -> ArticulatedBody:
    """The :class:`ArticulatedBody` of a URDF spec (:func:`is_urdf`)."""
    from adbsat_ros.geometry.articulated import ArticulatedBody  # (yourdfpy imports trimesh)

    name = str(spec)
    if name in BUNDLED_URDFS:
        return ArticulatedBody.from_urdf(
            BUNDLED_URDFS[name](), accept_size=accept_size, source=name
        )
    return ArticulatedBody.from_urdf(spec, accept_size=accept_size)


def resolve_mesh(spec, scale: float = 1.0, accept_size: bool = False) -> PanelMesh:
    """A PanelMesh from a file path, or a bundled body by name: ``"example"`` (the example
    satellite) or one of :data:`~adbsat_ros.geometry.concave_bodies.CONCAVE_BODIES`
    (``grooved-cylinder``, ``cylinder``, ``intake-box``); a URDF (a ``.urdf`` file, or
    ``example-articulated``, ``example-finned``) at zero joint positions
    (:func:`articulated_body` for others).

    Raises
    ------
    MeshError
        As :func:`load_mesh`, or a ``scale`` other than 1 with a bundled body or a URDF (they
        are in metres).
    """
    name = str(spec)
    if name == EXAMPLE_MESH_NAME or name in CONCAVE_BODIES or is_urdf(name):
        if scale != 1.0:
            raise MeshError(f"the {name} mesh is in metres; scale applies to mesh files only")
        if is_urdf(name):
            return articulated_body(name, accept_size).mesh()
        return example_satellite() if name == EXAMPLE_MESH_NAME else CONCAVE_BODIES[name]()
    return load_mesh(spec, scale=scale, accept_size=accept_size)
