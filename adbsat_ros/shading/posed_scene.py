"""What ray-cast shading needs of an articulated body, made once per link for every configuration;
equal to :func:`~adbsat_ros.shading.rays.ray_scene` on the posed body's mesh. Units: m, frame G."""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.shading.candidates import CandidateFilter, MeshTopology
from adbsat_ros.shading.convex_shadow import hull_corners
from adbsat_ros.shading.rays import RayScene, ray_scene, resolve_backend
from adbsat_ros.shading.topology_store import indexed_topology


class LinkScenes:
    """Every link's merged vertices and topology, made once; the scene and filter per pose."""

    def __init__(self, body: ArticulatedBody, backend: str = "auto"):
        self.backend = resolve_backend(backend)
        spans = sorted(body.link_spans.items(), key=lambda item: item[1][0])
        lo, hi = body.mesh().bounds
        diagonal = float(np.linalg.norm(hi - lo)) or 1.0
        self._links = [int(link) for link, _ in spans]
        self._vertices, faces, topologies = [], [], []  # every link's, in its own frame
        self._hulls = []  # (link, component of the body, its hull corners in the link's frame)
        first = components = 0
        for k, link in enumerate(self._links):
            (vertices, indices), topology = indexed_topology(body.link_mesh(link), diagonal, None)
            self._vertices.append(vertices)
            faces.append(indices + first)
            first += len(vertices)
            topologies.append(topology)
            n_components = int(topology.component.max()) + 1 if topology.component.size else 0
            for c in range(n_components):
                own = np.unique(indices[topology.component == c])
                self._hulls.append((k, components + c, hull_corners(vertices[own])))
            components += n_components
        self._faces = np.concatenate(faces)
        self.topology = MeshTopology.joined(topologies)

    def scene(self, mesh: PanelMesh, link_poses: np.ndarray) -> "DeferredScene":
        """The ray scene of ``mesh`` with links at ``link_poses`` ((L, 4, 4), link to G)."""
        poses = np.array(link_poses, dtype=float)

        def build() -> RayScene:
            posed = np.concatenate(  # (as the body poses its panels' corners: the same numbers)
                [
                    v @ poses[link, :3, :3].T + poses[link, :3, 3]
                    for link, v in zip(self._links, self._vertices)
                ]
            )
            return ray_scene(mesh, self.backend, indexed=(posed, self._faces))

        return DeferredScene(self.backend, build)

    def hull_corners(self, link_poses: np.ndarray) -> dict:
        """Component -> its hull corners (h, 3) [m], G, at ``link_poses`` (links' hulls posed)."""
        poses = np.asarray(link_poses, dtype=float)
        out = {}
        for k, component, corners in self._hulls:
            pose = poses[self._links[k]]
            out[component] = corners @ pose[:3, :3].T + pose[:3, 3]
        return out

    def candidate_filter(self, mesh: PanelMesh) -> CandidateFilter:
        """The candidate filter of the body's panels ``mesh`` (at any configuration)."""
        return CandidateFilter(mesh, topology=self.topology)


class DeferredScene:
    """A ray scene that ``build()`` makes when a ray is first cast through it."""

    def __init__(self, backend: str, build):
        self.backend = backend
        self._build = build
        self._scene: RayScene | None = None

    def __getattr__(self, name):
        """The scene's ``any_hit``, ``first_face`` and ``first_hit`` (:class:`RayScene`)."""
        if name.startswith("_"):
            raise AttributeError(name)
        if self._scene is None:
            self._scene = self._build()
        return getattr(self._scene, name)
