"""The ray-cast shader's topology of a mesh kept on disk (``$ADBSAT_ROS_CACHE_DIR/topology``, 64
entries), keyed by the SHA-256 of the panels' vertices, the diagonal, format and code."""

from __future__ import annotations

import hashlib

import numpy as np

from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.npz_store import NpzStore
from adbsat_ros.shading.candidates import MeshTopology

_ARRAYS = ("vertices", "faces", *MeshTopology._fields)


class TopologyStore(NpzStore):
    """The shader's topology of meshes on disk, by the panels' content (an ``NpzStore``)."""

    KIND = "topology"
    MAKERS = ("adbsat_ros.geometry.mesh", "adbsat_ros.shading.candidates")
    PACKAGES = ("trimesh", "scipy")

    @classmethod
    def key(cls, mesh: PanelMesh, diagonal: float) -> str:
        """The key of ``mesh``'s panels with the hull tolerance of ``diagonal`` [m]."""
        vertices = np.ascontiguousarray(mesh.vertices, dtype=float)
        return cls.finish_key(hashlib.sha256(vertices.tobytes()), float(diagonal))

    def get(self, key: str) -> tuple | None:
        """``(indexed, topology)`` kept for ``key`` (merged vertices, faces, topology), or None."""
        data = self.read(key, _ARRAYS)
        if data is None:
            return None
        return (data["vertices"], data["faces"]), MeshTopology(*(data[a] for a in _ARRAYS[2:]))

    def put(self, key: str, indexed: tuple, topology: MeshTopology) -> None:
        """Keep the merged vertices and faces ``indexed`` and the ``topology`` for ``key``."""
        vertices, faces = np.asarray(indexed[0], dtype=float), np.asarray(indexed[1], np.int64)
        self.write(key, dict(zip(_ARRAYS, (vertices, faces, *topology))))


def indexed_topology(mesh: PanelMesh, diagonal: float, store: TopologyStore | None) -> tuple:
    """``(indexed, topology)`` of ``mesh``: read back from ``store``, or made and kept there."""
    key = None if store is None else store.key(mesh, diagonal)
    found = None if key is None else store.get(key)
    if found is not None:
        return found
    tm = mesh.to_trimesh()
    indexed = (np.asarray(tm.vertices, dtype=float), np.asarray(tm.faces, dtype=np.int64))
    topology = MeshTopology.of(mesh, diagonal, indexed)
    if key is not None:
        store.put(key, indexed, topology)
    return indexed, topology
