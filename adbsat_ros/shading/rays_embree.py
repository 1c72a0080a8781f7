"""Ray casting with Embree through embreex (float32), :mod:`adbsat_ros.shading.rays`' interface.
Units: metres, mesh frame G."""

from __future__ import annotations

import numpy as np
from embreex import rtcore_scene
from embreex.mesh_construction import TriangleMesh

from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.shading.rays_numpy import any_hit, first_along

#: The scene's coordinates are rescaled so that the largest extent of the mesh is this long,
#: which keeps float32 rounding relative to the mesh size whatever its units.
SCENE_EXTENT = 100.0


class EmbreeScene:
    """The panels of a mesh (face i is panel i) as an Embree scene, float32, rescaled."""

    backend = "embree"

    def __init__(self, mesh: PanelMesh, indexed: tuple | None = None):
        if indexed is None:
            tm = mesh.to_trimesh()
            indexed = (tm.vertices, tm.faces)
        vertices = np.asarray(indexed[0], dtype=np.float64)
        faces = np.asarray(indexed[1])
        if faces.shape != (mesh.n_panels, 3):
            raise ValueError(
                f"indexed faces of shape {faces.shape} for a mesh of {mesh.n_panels} panels"
            )
        self.triangles = mesh.vertices
        self.origin = vertices.min(axis=0)
        extent = float(np.max(vertices.max(axis=0) - self.origin))
        self.scale = SCENE_EXTENT / extent if extent > 0 else 1.0
        self.scene = rtcore_scene.EmbreeScene()
        TriangleMesh(
            scene=self.scene,
            vertices=((vertices - self.origin) * self.scale).astype(np.float32),
            indices=np.asarray(faces, dtype=np.int32),
        )

    def _run(self, origins: np.ndarray, d: np.ndarray, query: str) -> np.ndarray:
        o = ((origins - self.origin) * self.scale).astype(np.float32)
        dirs = np.broadcast_to(d.astype(np.float32), o.shape).copy()
        return self.scene.run(o, dirs, query=query)

    def first_hit(self, origins, directions) -> tuple:
        """``RayScene.first_hit``, t to float32 rounding of the scene."""
        origins = np.asarray(origins, dtype=float)
        if origins.shape[0] == 0:
            return np.zeros(0, dtype=np.int64), np.zeros(0)
        o = ((origins - self.origin) * self.scale).astype(np.float32)
        out = self.scene.run(
            o, np.asarray(directions, dtype=np.float32), query="INTERSECT", output=1
        )
        face = out["primID"].astype(np.int64)
        distance = np.where(face >= 0, out["tfar"].astype(np.float64) / self.scale, np.inf)
        return face, distance

    def any_hit(self, origins, direction, occluder=None) -> np.ndarray:
        """``RayScene.any_hit``; a ray first hitting a non-occluder is cast again in float64."""
        origins = np.asarray(origins, dtype=float)
        if origins.shape[0] == 0:
            return np.zeros(0, dtype=bool)
        d = np.asarray(direction, dtype=float)
        if occluder is None:
            return self._run(origins, d, "OCCLUDED") != -1
        first = self._run(origins, d, "INTERSECT")
        blocked = first != -1
        redo = np.flatnonzero(blocked & ~occluder[np.maximum(first, 0)])
        if redo.size:
            blocked[redo] = any_hit(origins[redo], d, self.triangles[occluder])
        return blocked

    def first_face(self, origins, direction, occluder=None) -> np.ndarray:
        """The first occluding panel each ray meets, -1 for none (as :meth:`any_hit`)."""
        origins = np.asarray(origins, dtype=float)
        if origins.shape[0] == 0:
            return np.zeros(0, dtype=np.int64)
        d = np.asarray(direction, dtype=float)
        face = self._run(origins, d, "INTERSECT").astype(np.int64)
        if occluder is not None:
            redo = np.flatnonzero((face >= 0) & ~occluder[np.maximum(face, 0)])
            if redo.size:
                index = np.flatnonzero(occluder)
                again = first_along(origins[redo], d, self.triangles[index])
                face[redo] = np.where(again >= 0, index[np.maximum(again, 0)], -1)
        return face
