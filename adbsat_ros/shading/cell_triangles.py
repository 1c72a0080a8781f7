"""Triangles over the centres of the cube-map cells (12 n^2 - 4 of them): the three centres
around a flow direction and their barycentric weights, for the shading cache's interpolation
(docs/shading.md).
"""

from __future__ import annotations

import bisect
import functools
import math

import numpy as np

from adbsat_ros.shading.cube_map import direction_key, direction_keys, face_axes, key_centres

_QUARTER = 0.25 * math.pi


class CellTriangulation:
    """The triangles over the cube-map cell centres of ``n`` >= 1 steps per face edge; only those
    across cube edges and at corners are stored (``border_triangles``), the rest follow the grid."""

    def __init__(self, n: int):
        n = int(n)
        if n < 1:
            raise ValueError(f"n must be >= 1 cube-map steps per face edge, got {n!r}")
        self.n = n
        angles = -_QUARTER + (np.arange(n) + 0.5) * (0.5 * math.pi / n)
        self._tan = np.tan(angles).tolist()  # gnomonic coordinate of the centre rows, ascending

    @functools.cached_property
    def border_triangles(self) -> np.ndarray:
        """Vertex keys (B, 3) of the triangles across cube edges and at corners (made when a
        direction first falls between faces)."""
        return _border_triangles(self.n)

    @functools.cached_property
    def _border_vertices(self) -> np.ndarray:
        """The unit cell centres (B, 3, 3) of :attr:`border_triangles`."""
        return key_centres(self.border_triangles.reshape(-1), self.n).reshape(-1, 3, 3)

    @functools.cached_property
    def _border_of_key(self) -> dict:
        """The border triangles each cell key is a vertex of."""
        border_of_key: dict = {}
        for t, keys in enumerate(self.border_triangles.tolist()):
            for key in keys:
                border_of_key.setdefault(key, []).append(t)
        return border_of_key

    def locate(self, x: float, y: float, z: float) -> tuple:
        """``(keys, weights)``: the three cell keys around the finite non-zero direction (x, y, z)
        and the weights (non-negative, sum 1) of their centres."""
        face, ak, a1, a2 = face_axes(x, y, z)
        gx, gy = a1 / ak, a2 / ak
        tan, n = self._tan, self.n
        if n > 1 and tan[0] <= gx <= tan[-1] and tan[0] <= gy <= tan[-1]:
            return self._inside_face(face, gx, gy)
        return self._across_edges(x, y, z)

    def _inside_face(self, face: int, gx: float, gy: float) -> tuple:
        tan, n = self._tan, self.n
        i = min(max(bisect.bisect_right(tan, gx) - 1, 0), n - 2)
        j = min(max(bisect.bisect_right(tan, gy) - 1, 0), n - 2)
        s = (gx - tan[i]) / (tan[i + 1] - tan[i])
        t = (gy - tan[j]) / (tan[j + 1] - tan[j])
        base = face * n * n
        k00, k11 = base + i * n + j, base + (i + 1) * n + j + 1
        if s >= t:  # triangle (i, j), (i+1, j), (i+1, j+1)
            corners = ((i, j, 1.0 - s), (i + 1, j, s - t), (i + 1, j + 1, t))
            keys = (k00, k00 + n, k11)
        else:  # triangle (i, j), (i+1, j+1), (i, j+1)
            corners = ((i, j, 1.0 - t), (i + 1, j + 1, s), (i, j + 1, t - s))
            keys = (k00, k11, k00 + 1)
        # planar weights mu to the weights of the unit centres: mu_k |v_k'|, normalised
        scaled = [mu * math.sqrt(1.0 + tan[a] ** 2 + tan[b] ** 2) for a, b, mu in corners]
        total = scaled[0] + scaled[1] + scaled[2]
        return keys, (scaled[0] / total, scaled[1] / total, scaled[2] / total)

    def _across_edges(self, x: float, y: float, z: float) -> tuple:
        """Weights in the border triangle near (x, y, z) whose smallest weight is largest."""
        key = direction_key(x, y, z, self.n)
        near = set(self._border_of_key.get(key, ()))
        for t in list(near):  # and one ring further
            for vertex in self.border_triangles[t].tolist():
                near.update(self._border_of_key.get(vertex, ()))
        if not near:  # n = 1: the corner triangles only
            near = set(range(len(self.border_triangles)))
        candidates = np.fromiter(near, dtype=np.int64)
        weights = _barycentric(self._border_vertices[candidates], np.array([x, y, z]))
        best = int(np.argmax(weights.min(axis=1)))
        w = np.clip(weights[best], 0.0, None)
        w /= w.sum()
        return tuple(self.border_triangles[candidates[best]].tolist()), tuple(w.tolist())


def _barycentric(vertices: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Weights (M, 3) of u in M triangles (M, 3, 3), rows summing to 1; -inf where facing away."""
    v1, v2, v3 = vertices[:, 0], vertices[:, 1], vertices[:, 2]
    c23, c31, c12 = np.cross(v2, v3), np.cross(v3, v1), np.cross(v1, v2)
    w = np.stack([c23 @ u, c31 @ u, c12 @ u], axis=1) / np.einsum("ij,ij->i", v1, c23)[:, None]
    total = w.sum(axis=1, keepdims=True)
    # a triangle on the far side of the sphere (total <= 0) holds no weights for u
    return np.divide(w, total, out=np.full_like(w, -np.inf), where=total > 0.0)


def _border_triangles(n: int) -> np.ndarray:
    """Vertex keys of the triangles across the 12 cube edges and at the 8 corners."""
    faces = []
    for face in range(6):
        k = face // 2
        sign = -1.0 if face % 2 else 1.0
        for along_first, at_end in ((True, False), (True, True), (False, False), (False, True)):
            # the edge cells of this face on one cube edge, in order along the edge
            fixed = n - 1 if at_end else 0
            rows = [(fixed, m) if along_first else (m, fixed) for m in range(n)]
            keys = [face * n * n + a * n + b for a, b in rows]
            # the neighbouring face: the axis this edge leans to, with its sign
            axis = (k + 1) % 3 if along_first else (k + 2) % 3
            other = 2 * axis + (0 if at_end else 1)
            normal = np.zeros(3)
            normal[k] = sign
            normal[axis] = -1.0 if at_end else 1.0
            normal /= math.sqrt(2.0)
            faces.append((face, other, keys, normal))
    triangles, corners = [], set()
    for face, other, keys, normal in faces:
        centres = key_centres(np.array(keys), n)
        mirrored = centres - 2.0 * (centres @ normal)[:, None] * normal
        images = direction_keys(mirrored, n).tolist()
        if face < other:  # each cube edge once
            for m in range(n - 1):
                a, b, c, d = keys[m], keys[m + 1], images[m + 1], images[m]
                triangles += [(a, b, c), (a, c, d)]
        for end in (0, n - 1):  # the corner cells of this edge: their triangle, once
            corners.add((keys[end], images[end]))
    return np.array(triangles + _corner_triangles(corners), dtype=np.int64).reshape(-1, 3)


def _corner_triangles(pairs: set) -> list:
    """The 8 corner triangles from the (corner cell, its image across an edge) pairs."""
    neighbours: dict = {}
    for a, b in pairs:
        neighbours.setdefault(a, set()).add(b)
        neighbours.setdefault(b, set()).add(a)
    found = set()
    for a, others in neighbours.items():
        for b in others:
            for c in neighbours[b] & others:
                found.add(tuple(sorted((a, b, c))))
    return sorted(found)
