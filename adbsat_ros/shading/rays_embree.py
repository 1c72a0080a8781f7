"""Ray casting with Embree (through embreex, the engine behind trimesh's RayMeshIntersector): float32, fast."""

from __future__ import annotations

import numpy as np
import trimesh


# ---------------------------------------------------------------------------------- embree
class _EmbreeScene:
    """An Embree scene of the whole mesh (float32, coordinates rescaled to ~100 units)."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray):
        from embreex import rtcore_scene
        from embreex.mesh_construction import TriangleMesh

        vertices = np.asarray(vertices, dtype=np.float64)
        self.origin = vertices.min(axis=0)
        extent = float(np.max(vertices.max(axis=0) - self.origin))
        self.scale = 100.0 / extent if extent > 0 else 1.0
        self.scene = rtcore_scene.EmbreeScene()
        TriangleMesh(
            scene=self.scene,
            vertices=((vertices - self.origin) * self.scale).astype(np.float32),
            indices=np.asarray(faces, dtype=np.int32),
        )

    def run(self, origins: np.ndarray, d: np.ndarray, query: str) -> np.ndarray:
        o = ((origins - self.origin) * self.scale).astype(np.float32)
        dirs = np.broadcast_to(d.astype(np.float32), o.shape).copy()
        return self.scene.run(o, dirs, query=query)


def embree_available() -> bool:
    """True if trimesh can use Embree (embreex importable)."""
    return bool(getattr(trimesh.ray, "has_embree", False))
