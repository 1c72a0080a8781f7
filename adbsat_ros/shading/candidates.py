"""Which panels the ray-cast shader tests: the grazing rule and the filters (docs/shading.md). A
forward panel can be shaded only if it is off its component's convex hull or another component
lies upstream with an overlapping box normal to the flow. Units: metres, mesh frame G."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.shading.flow_plane import MAX_PAIRS, coordinates, max3, min3, perp_basis

#: Faces whose centroid is within this fraction of the bounding-box diagonal of their
#: component's convex hull surface count as hull faces (cannot be shaded by their own
#: component). It covers vertices rounded to float32, as binary STL stores them (6e-8 of the
#: coordinates); a dent shallower than this shades nothing that matters.
HULL_TOL_FRACTION = 1e-6
#: Above this many connected components the inter-component filter is skipped (all forward
#: panels of a multi-component mesh are then tested).
MAX_COMPONENTS_FILTER = 64


def _unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


#: First tie-break direction w of grazing faces (generic, fixed; unitless, G).
TIE_W1 = _unit([0.8164965809277260, 0.4472135954999579, 0.3651483716701107])
_W2 = np.array([-0.2360679774997897, 0.6457513110645906, 0.7071067811865476])
#: Second tie-break direction, for faces normal to the first (orthogonal to it).
TIE_W2 = _unit(_W2 - (_W2 @ TIE_W1) * TIE_W1)


def forward_mask(cos_delta: np.ndarray, normals: np.ndarray, graze_tol: float) -> np.ndarray:
    """Forward panels (N,) by the grazing rule, of c_i = -u . n_i and normals (N, 3) in G."""
    forward = cos_delta > graze_tol
    grazing = np.flatnonzero(np.abs(cos_delta) <= graze_tol)
    forward[grazing] = grazing_forward(normals[grazing])
    return forward


def grazing_forward(normals: np.ndarray) -> np.ndarray:
    """Whether panels of normals (N, 3) count as forward when grazing (the tie-break)."""
    t1, t2 = -(normals @ TIE_W1), -(normals @ TIE_W2)
    return np.where(np.abs(t1) > 1e-12, t1 > 0.0, t2 > 0.0)


class MeshTopology(NamedTuple):
    """Edge neighbours (E, 2), component (N,) and hull faces (N,) of a mesh (unchanged by rigid
    motion)."""

    adjacency: np.ndarray
    component: np.ndarray
    on_hull: np.ndarray

    @classmethod
    def of(cls, mesh: PanelMesh, diagonal: float, indexed: tuple) -> "MeshTopology":
        """The topology of ``mesh`` of merged vertices and faces ``indexed``, hull tolerance
        relative to ``diagonal`` [m]."""
        import trimesh  # (with the first shader that needs it: not at start-up)

        tm = trimesh.Trimesh(vertices=indexed[0], faces=indexed[1], process=False)
        faces = np.asarray(tm.faces, dtype=np.int64)
        adjacency = np.asarray(tm.face_adjacency, dtype=np.int64).reshape(-1, 2)
        labels = trimesh.graph.connected_component_labels(adjacency, node_count=len(faces))
        component = np.asarray(labels, dtype=np.int64)
        vertices = np.asarray(tm.vertices, dtype=float)
        return cls(adjacency, component, _hull_faces(mesh, component, vertices, faces, diagonal))

    @classmethod
    def joined(cls, parts) -> "MeshTopology":
        """The topology of meshes put one after the other (renumbered; no edge joins two)."""
        adjacency, component, on_hull = [], [], []
        panels = components = 0
        for part in parts:
            adjacency.append(part.adjacency + panels)
            component.append(part.component + components)
            on_hull.append(part.on_hull)
            panels += part.component.size
            components += int(part.component.max()) + 1 if part.component.size else 0
        return cls(np.concatenate(adjacency), np.concatenate(component), np.concatenate(on_hull))


def _hull_faces(mesh, component, vertices, faces, diagonal) -> np.ndarray:
    """Faces on their own component's hull, normal out, by centroid distance (rounding tilts
    normals)."""
    from scipy.spatial import ConvexHull, QhullError  # (not at start-up)

    on_hull = np.zeros(mesh.n_panels, dtype=bool)
    tol = HULL_TOL_FRACTION * diagonal
    normals = mesh.normals
    centroids = mesh.barycentres
    order = np.argsort(component, kind="stable")
    counts = np.bincount(component)
    stop = np.cumsum(counts)
    for a, b in zip(stop - counts, stop):  # loop over bodies (few), vectorised over faces
        idx = order[a:b]
        pts = vertices[np.unique(faces[idx])]
        try:
            planes = ConvexHull(pts).equations  # (F, 4): n . x + d <= 0 inside, n outward
        except (QhullError, ValueError):
            planes = None  # flat or degenerate body
        if planes is not None:
            step = max(1, MAX_PAIRS // len(planes))
            for s in range(0, idx.size, step):
                j = idx[s : s + step]
                distance = centroids[j] @ planes[:, :3].T + planes[:, 3]  # (<= 0 inside)
                nearest = distance.argmax(axis=1)
                outward = np.einsum("kj,kj->k", normals[j], planes[nearest, :3]) > 0.0
                on_hull[j] = (distance[np.arange(j.size), nearest] >= -tol) & outward
            continue
        step = max(1, MAX_PAIRS // max(len(pts), 1))
        for s in range(0, idx.size, step):
            j = idx[s : s + step]
            level = np.einsum("ij,ij->i", normals[j], mesh.vertices[j, 0, :])
            on_hull[j] = (normals[j] @ pts.T).max(axis=1) <= level + tol
    return on_hull


class CandidateFilter:
    """Components, hull faces and the filter of panels that could be shaded, from ``mesh``'s
    ``topology``; ``convex`` (n_components,) marks closed convex components."""

    def __init__(self, mesh: PanelMesh, topology: MeshTopology):
        if topology.component.size != mesh.n_panels:
            raise ValueError(
                f"topology of {topology.component.size} panels for a mesh of {mesh.n_panels}"
            )
        self.mesh = mesh
        self.adjacency, self.component, self.on_hull = topology
        self.n_components = int(self.component.max()) + 1 if self.component.size else 0
        # Faces sorted by component, for per-component work and reductions.
        self._order = np.argsort(self.component, kind="stable")
        counts = np.bincount(self.component, minlength=self.n_components)
        self._start = np.cumsum(counts) - counts
        pairs = np.bincount(self.component[self.adjacency[:, 0]], minlength=self.n_components)
        off_hull = np.bincount(self.component[~self.on_hull], minlength=self.n_components)
        self.convex = (2 * pairs == 3 * counts) & (off_hull == 0) & (counts > 0)

    def candidates(self, u: np.ndarray, forward: np.ndarray) -> np.ndarray:
        """Ascending indices (K,) of the ``forward`` panels that could be shaded for unit ``u``:
        those off their hull, and those a component's box normal to the flow overlaps."""
        need = forward & ~self.on_hull
        if self.n_components <= 1:
            return np.flatnonzero(need)
        if self.n_components > MAX_COMPONENTS_FILTER:
            return np.flatnonzero(forward)
        idx = np.flatnonzero(forward & ~need)
        if idx.size:
            coords = coordinates(self.mesh.vertices, perp_basis(-u))  # s grows upstream
            lo, hi = [min3(a) for a in coords], [max3(a) for a in coords]  # (N,) each
            clo = [np.minimum.reduceat(a[self._order], self._start)[:, None] for a in lo]
            chi = [np.maximum.reduceat(a[self._order], self._start)[:, None] for a in hi]
            step = max(1, MAX_PAIRS // self.n_components)
            for s in range(0, idx.size, step):
                j = idx[s : s + step]
                overlap = (  # (C, K): which components could shade each panel
                    (chi[2] > lo[2][j])
                    & (chi[0] >= lo[0][j])
                    & (clo[0] <= hi[0][j])
                    & (chi[1] >= lo[1][j])
                    & (clo[1] <= hi[1][j])
                )
                overlap[self.component[j], np.arange(j.size)] = False
                need[j] = overlap.any(axis=0)
        return np.flatnonzero(need)
