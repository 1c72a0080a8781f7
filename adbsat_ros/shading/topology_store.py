"""The ray-cast shader's topology of a mesh kept on disk, read back instead of made again.

A ray-cast shader of a body that can shade itself needs the panels with their vertices merged
(for the ray scene) and the candidate filter's topology (edge neighbours, connected components,
hull faces: :class:`~adbsat_ros.shading.candidates.MeshTopology`). Making them takes trimesh, whose
import alone takes longer than a one-attitude ``adbsat-ros coeff`` with the stores
(docs/benchmarks.md, command line start-up), and then the merging and the hulls.
:class:`TopologyStore` keeps them by the panels' content, so that the next shader of the same panels
(the next ``adbsat-ros coeff`` on a mesh file, the node started again) reads them back with numpy.

Key: the SHA-256 of the panels' vertex coordinates (exact bytes), the bounding-box diagonal the
hull tolerance is taken from, the store's format and the code that makes the entries (the
source of the topology's modules, the installed trimesh and scipy:
:func:`~adbsat_ros.npz_store.code_fingerprint`). Value: the merged
vertices and faces, the edge neighbours, the components and the hull faces. Bound: the 64 most
recently used entries. Counters: ``hits``, ``misses``, ``writes``. On disk as
:class:`~adbsat_ros.npz_store.NpzStore` keeps them, in ``$ADBSAT_ROS_CACHE_DIR/topology``.
"""

from __future__ import annotations

import hashlib

import numpy as np

from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.npz_store import NpzStore, shared_store
from adbsat_ros.shading.candidates import MeshTopology

_ARRAYS = ("vertices", "faces", "adjacency", "component", "on_hull")


class TopologyStore(NpzStore):
    """The shader's topology of meshes on disk, by the panels' content (an
    :class:`~adbsat_ros.npz_store.NpzStore`: ``directory``, ``max_entries``, counters)."""

    KIND = "topology"
    MAKERS = ("adbsat_ros.geometry.mesh", "adbsat_ros.shading.candidates")
    PACKAGES = ("trimesh", "scipy")

    @classmethod
    def key(cls, mesh: PanelMesh, diagonal: float) -> str:
        """The key of ``mesh``'s panels with the hull tolerance of ``diagonal`` [m]."""
        vertices = np.ascontiguousarray(mesh.vertices, dtype=float)
        return cls.finish_key(hashlib.sha256(vertices.tobytes()), float(diagonal))

    def get(self, key: str) -> tuple | None:
        """``(indexed, topology)`` kept for ``key``: the merged vertices (V, 3) and faces
        (N, 3), and the :class:`MeshTopology`; None if not kept (a miss)."""
        data = self.read(key, _ARRAYS)
        if data is None:
            return None
        indexed = (data["vertices"], data["faces"])
        return indexed, MeshTopology(data["adjacency"], data["component"], data["on_hull"])

    def put(self, key: str, indexed: tuple, topology: MeshTopology) -> None:
        """Keep the merged vertices and faces ``indexed`` and the ``topology`` for ``key``."""
        vertices, faces = indexed
        self.write(
            key,
            {
                "vertices": np.asarray(vertices, dtype=float),
                "faces": np.asarray(faces, dtype=np.int64),
                "adjacency": topology.adjacency,
                "component": topology.component,
                "on_hull": topology.on_hull,
            },
        )


def default_store() -> TopologyStore | None:
    """The store of the environment's cache directory (``$ADBSAT_ROS_CACHE_DIR/topology``, read
    now; one per directory in a process), or None if the stores are off."""
    return shared_store(TopologyStore)


def indexed_topology(mesh: PanelMesh, diagonal: float, store: TopologyStore | None) -> tuple:
    """``(indexed, topology)`` of ``mesh`` (as :meth:`TopologyStore.get` gives them): read back
    from ``store``, or made (the vertices merged by trimesh, :meth:`MeshTopology.of`) and kept
    there."""
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
