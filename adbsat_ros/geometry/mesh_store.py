"""Checked meshes kept on disk by their file's content (SHA-256, suffix, scale, options, code),
at most 64, in ``$ADBSAT_ROS_CACHE_DIR/meshes`` (docs/architecture.md).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from adbsat_ros.geometry.mesh import MeshReport, PanelMesh
from adbsat_ros.npz_store import NpzStore, file_digest

#: Mesh formats kept: those held whole in one file (a .gltf's buffers may be other files).
STORED_SUFFIXES = (".obj", ".stl", ".ply", ".off")
#: The report's fields, in the order they are stored.
_REPORT_FIELDS = tuple(f.name for f in dataclasses.fields(MeshReport))
_ARRAYS = ("vertices", "normals", "areas", "barycentres", "material_index")


class MeshStore(NpzStore):
    """Checked meshes on disk by their file's content (an ``NpzStore``)."""

    KIND = "meshes"
    MAKERS = (
        "adbsat_ros.geometry.mesh",
        "adbsat_ros.geometry.mesh_files",
        "adbsat_ros.geometry.loading",
    )
    PACKAGES = ("trimesh",)

    @classmethod
    def key(cls, path, scale: float, fix_normals: bool) -> str:
        """Hex SHA-256 key of ``path`` at ``scale``, ``fix_normals``; OSError if unreadable."""
        suffix = Path(path).suffix.lower()
        return cls.finish_key(file_digest(path), suffix, float(scale), bool(fix_normals))

    def get(self, key: str, source: str) -> PanelMesh | None:
        """The mesh kept for ``key`` (named ``source``), or None (counted as a miss)."""
        data = self.read(key, (*_ARRAYS, "material_names", "report"))
        if data is None:
            return None
        report = data.pop("report").tolist()
        names = tuple(str(name) for name in data.pop("material_names"))
        return PanelMesh(
            **data,
            material_names=names,
            report=MeshReport(
                **{
                    name: (bool(value) if name in ("watertight", "convex") else int(value))
                    for name, value in zip(_REPORT_FIELDS, report)
                }
            ),
            source=source,
        )

    def put(self, key: str, mesh: PanelMesh) -> None:
        """Keep ``mesh`` for ``key``."""
        self.write(
            key,
            {
                **{name: getattr(mesh, name) for name in _ARRAYS},
                "material_names": np.array(mesh.material_names, dtype=str),
                "report": np.array([int(getattr(mesh.report, name)) for name in _REPORT_FIELDS]),
            },
        )
