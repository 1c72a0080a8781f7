"""Checked meshes kept on disk by their file's content, read back instead of parsed again.

Loading a mesh file parses it with trimesh and checks it (orientation, closedness, convexity
per connected component); importing trimesh alone takes longer than a one-attitude
``adbsat-ros coeff`` may take (docs/benchmarks.md, command line start-up). :class:`MeshStore`
keeps what the checks made, so that the next load of the same file reads the panels back
with numpy alone, as ADBSat reads a mesh once imported to a .mat file.

Key: the SHA-256 of the file's bytes, its suffix, the scale to metres, whether normals are
fixed, the store's format and the code that makes the entries (the source of the loading and
checking modules, the installed trimesh: :func:`~adbsat_ros.npz_store.code_fingerprint`), so a
changed file or a changed parser makes the entry anew (a byte-order mark, or other line ends,
make another key: the file is read again, to the same panels). Only formats held in one file
are kept (:data:`STORED_SUFFIXES`). Value: the
:class:`~adbsat_ros.geometry.mesh.PanelMesh` arrays, material names and report. Bound: the 64
most recently used entries. Counters: ``hits``, ``misses``, ``writes``. On disk as
:class:`~adbsat_ros.npz_store.NpzStore` keeps them, in ``$ADBSAT_ROS_CACHE_DIR/meshes`` (by
default ``~/.cache/adbsat_ros/meshes``; ``ADBSAT_ROS_CACHE_DIR=off``: none). A store that cannot
be written (a read-only home, a full disk) or an entry that cannot be read is passed over:
loading then works as without the store.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from adbsat_ros.geometry.mesh import MeshReport, PanelMesh
from adbsat_ros.npz_store import NpzStore, file_digest, shared_store

#: Mesh formats kept: those held whole in one file (a .gltf's buffers may be other files).
STORED_SUFFIXES = (".obj", ".stl", ".ply", ".off")
#: The report's fields, in the order they are stored.
_REPORT_FIELDS = (
    "dropped_zero_area",
    "flipped_components",
    "open_components",
    "watertight",
    "convex",
    "components",
)
_ARRAYS = ("vertices", "normals", "areas", "barycentres", "material_index")


class MeshStore(NpzStore):
    """Checked meshes on disk, by the content of the file they were loaded from (an
    :class:`~adbsat_ros.npz_store.NpzStore`: ``directory``, ``max_entries``, counters)."""

    KIND = "meshes"
    MAKERS = (
        "adbsat_ros.geometry.mesh",
        "adbsat_ros.geometry.mesh_files",
        "adbsat_ros.geometry.loading",
    )
    PACKAGES = ("trimesh",)

    @classmethod
    def key(cls, path, scale: float, fix_normals: bool) -> str:
        """The key of the file ``path`` loaded at ``scale`` with or without ``fix_normals``
        (hex SHA-256). Raises OSError if the file cannot be read."""
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


def default_store() -> MeshStore | None:
    """The store of the environment's cache directory (``$ADBSAT_ROS_CACHE_DIR/meshes``, read
    now; one per directory in a process), or None if the stores are off."""
    return shared_store(MeshStore)
