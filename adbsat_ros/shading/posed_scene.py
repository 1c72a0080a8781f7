"""What ray-cast shading needs of an articulated body, made once for every configuration.

Shading a configuration needs a ray scene of the posed body's panels and the candidate filter's
topology (edge neighbours, connected components, hull faces). Both come from the links, which
are rigid: :class:`LinkScenes` merges each link's vertices and finds its topology once, in the
link's own frame. For a configuration it poses the merged vertices (a rotation and a shift per
link) and builds the ray scene from them, with no vertex merging, and joins the links'
topologies, which moving a link does not change. The panels, their order and every rule of the
ray cast are those of :func:`~adbsat_ros.shading.rays.ray_scene` on
:meth:`~adbsat_ros.geometry.articulated.ArticulatedBody.mesh`; the scene is built when the
first ray is cast (:class:`DeferredScene`).

Two links are never one component here, so the panels of two links that touch are not edge
neighbours (the shader's probe of a partly lit panel's neighbours stays within its link).

Units: metres, body frame G.
"""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.shading.candidates import CandidateFilter, MeshTopology
from adbsat_ros.shading.convex_shadow import hull_corners
from adbsat_ros.shading.rays import RayScene, ray_scene, resolve_backend


class LinkScenes:
    """Every link's merged vertices and filter topology, made once; the scene and the
    candidate filter of the body at any configuration.

    Parameters
    ----------
    body : ArticulatedBody
    backend : {"auto", "embree", "numpy"}
        Ray engine (:func:`~adbsat_ros.shading.rays.resolve_backend`).

    Attributes
    ----------
    backend : str
        ``"embree"`` or ``"numpy"``.
    topology : MeshTopology
        The candidate filter's topology of the body's panels (in the order of ``body.mesh``).
    """

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
            mesh = body.link_mesh(link)
            tm = mesh.to_trimesh()
            vertices = np.asarray(tm.vertices, dtype=float)
            link_faces = np.asarray(tm.faces, dtype=np.int64)
            self._vertices.append(vertices)
            faces.append(link_faces + first)
            first += len(vertices)
            topology = MeshTopology.of(mesh, diagonal, (tm.vertices, tm.faces))
            topologies.append(topology)
            n_components = int(topology.component.max()) + 1 if topology.component.size else 0
            for c in range(n_components):
                own = np.unique(link_faces[topology.component == c])
                self._hulls.append((k, components + c, hull_corners(vertices[own])))
            components += n_components
        self._faces = np.concatenate(faces)
        self.topology = MeshTopology.joined(topologies)

    def scene(self, mesh: PanelMesh, link_poses: np.ndarray) -> "DeferredScene":
        """The ray scene of the body's panels ``mesh`` at the configuration where its links
        have ``link_poses`` ((L, 4, 4) link-to-G poses of every link, as
        :meth:`ArticulatedBody.link_poses` gives them), built when a ray is first cast."""
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
        """The corners of every component's convex hull [m] at the configuration where the
        links have ``link_poses`` (as :meth:`scene`): component of the body's panels -> (h, 3),
        G (the links' hulls made once, posed here)."""
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
    """A ray scene built when a ray is first cast through it (:class:`RayScene`'s methods).

    Building an Embree scene of a posed body costs time at each new configuration, and the exact
    shadows of convex parts often leave no ray to cast for a configuration (none for the
    bundled articulated examples at the benchmarks' attitudes), so a configuration's scene
    waits for its first ray.

    Parameters
    ----------
    backend : str
        ``"embree"`` or ``"numpy"``.
    build : callable
        ``build()`` makes the scene.

    """

    def __init__(self, backend: str, build):
        self.backend = backend
        self._build = build
        self._scene: RayScene | None = None

    @property
    def built(self) -> bool:
        """Whether the scene has been built."""
        return self._scene is not None

    def _ready(self) -> RayScene:
        if self._scene is None:
            self._scene = self._build()
        return self._scene

    def any_hit(self, origins, direction, occluder=None) -> np.ndarray:
        """:meth:`RayScene.any_hit`."""
        return self._ready().any_hit(origins, direction, occluder)

    def first_face(self, origins, direction, occluder=None) -> np.ndarray:
        """:meth:`RayScene.first_face`."""
        return self._ready().first_face(origins, direction, occluder)

    def first_hit(self, origins, directions) -> tuple:
        """:meth:`RayScene.first_hit`."""
        return self._ready().first_hit(origins, directions)
