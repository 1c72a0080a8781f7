"""Mesh files, bundled bodies by name and trimesh meshes to a checked PanelMesh (trimesh and
yourdfpy imported only when a file is parsed)."""

from __future__ import annotations

import math
import os
from typing import TYPE_CHECKING

from adbsat_ros.geometry.concave_bodies import CONCAVE_BODIES
from adbsat_ros.geometry.example_satellite import EXAMPLE_MESH_NAME, example_satellite
from adbsat_ros.geometry.example_urdf import (
    EXAMPLE_FINNED_NAME,
    EXAMPLE_URDF_NAME,
    example_finned_urdf,
    example_satellite_urdf,
)
from adbsat_ros.geometry.mesh import (
    MeshError,
    PanelMesh,
    check_size,
    log_report,
    panels_from_arrays,
)
from adbsat_ros.geometry.mesh_files import check_mesh_path, read_mesh_file
from adbsat_ros.geometry.mesh_store import STORED_SUFFIXES, MeshStore

if TYPE_CHECKING:
    import trimesh

    from adbsat_ros.geometry.articulated import ArticulatedBody

#: The bundled URDF bodies by name.
BUNDLED_URDFS = {
    EXAMPLE_URDF_NAME: example_satellite_urdf,
    EXAMPLE_FINNED_NAME: example_finned_urdf,
}

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
    """Load a triangulated surface mesh file (any trimesh format; .obj ``usemtl`` materials) [m].
    scale: factor to metres (1e-3 for CAD in millimetres); fix_normals: flip closed bodies whose
    faces point inwards, with a warning; accept_size: take a mesh outside ``mesh_extent`` (1 mm to
    200 m across); store: a MeshStore, "default" or None, keeping checked meshes by file content.
    MeshError: a missing, unreadable or bad file (the line), no usable face, a coordinate beyond
    ``mesh_coordinate``, or a size that is no satellite's (naming the likely unit)."""
    path = os.fspath(path)
    if not math.isfinite(scale) or scale <= 0:
        raise MeshError(f"{path}: scale must be a finite number > 0, got {scale!r}")
    check_mesh_path(path)
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
    """The checked panels of the mesh file ``path``."""
    arrays = read_mesh_file(path)
    return panels_from_arrays(
        arrays.vertices * scale,
        arrays.faces,
        arrays.material_index,
        arrays.material_names,
        source=path,
        fix_normals=fix_normals,
    )


def panels_from_trimesh(mesh: trimesh.Trimesh, *, source="<trimesh>", **kwargs) -> PanelMesh:
    """A checked PanelMesh of a trimesh.Trimesh [m]; as :func:`.mesh.panels_from_arrays`."""
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
    """A PanelMesh of a file path or a bundled body's name (URDFs at zero joint positions).

    MeshError: as :func:`load_mesh`, or a ``scale`` other than 1 with a bundled body or URDF.
    """
    name = str(spec)
    if name == EXAMPLE_MESH_NAME or name in CONCAVE_BODIES or is_urdf(name):
        if scale != 1.0:
            raise MeshError(f"the {name} mesh is in metres; scale applies to mesh files only")
        if is_urdf(name):
            return articulated_body(name, accept_size).mesh()
        return example_satellite() if name == EXAMPLE_MESH_NAME else CONCAVE_BODIES[name]()
    return load_mesh(spec, scale=scale, accept_size=accept_size)
