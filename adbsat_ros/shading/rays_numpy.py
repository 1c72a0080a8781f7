"""Ray casting in numpy (float64): the reference backend, and the fallback without Embree.
Moeller-Trumbore on pairs from a grid normal to the rays, in chunks. Units: metres, mesh frame G."""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.shading.flow_plane import MAX_PAIRS, coordinates, grid_pairs, max3, min3, perp_basis

#: Tolerance of the inclusive barycentric test: shared edges count as inside both triangles.
EDGE_TOLERANCE = 1e-12


def any_hit(origins, d, tri_vertices, max_pairs=MAX_PAIRS) -> np.ndarray:
    """Whether each ray origins[r] + t d, t > 0, meets any of the triangles, (R,) bool.

    origins (R, 3) [m], unit d (3,), tri_vertices (T, 3, 3) [m] none parallel to d, G; edges count.
    """
    origins = np.asarray(origins, dtype=float)
    hit = np.zeros(len(origins), dtype=bool)
    for ray, _, _ in _hits_along(origins, d, tri_vertices, max_pairs):
        hit[ray] = True
    return hit


def first_along(origins, d, tri_vertices, max_pairs=MAX_PAIRS) -> np.ndarray:
    """The nearest triangle (R,) each ray meets (lower index at equal t; -1 for none)."""
    origins = np.asarray(origins, dtype=float)
    n_rays = len(origins)
    face = np.full(n_rays, -1, dtype=np.int64)
    nearest = np.full(n_rays, np.inf)
    for ray, tri, t in _hits_along(origins, d, tri_vertices, max_pairs):
        order = np.lexsort((tri, t, ray))  # by ray, then t, then triangle
        ray, tri, t = ray[order], tri[order], t[order]
        first = np.ones(ray.size, dtype=bool)
        first[1:] = ray[1:] != ray[:-1]
        ray, tri, t = ray[first], tri[first], t[first]
        better = (t < nearest[ray]) | ((t == nearest[ray]) & (tri < face[ray]))
        nearest[ray[better]] = t[better]
        face[ray[better]] = tri[better]
    return face


def _hits_along(origins, d, tri_vertices, max_pairs):
    """Chunks ``(ray, triangle, t)`` of the pairs that meet at t > 0."""
    if len(origins) == 0 or len(tri_vertices) == 0:
        return
    basis = perp_basis(d)
    rx, ry, rs = coordinates(origins, basis)
    tx, ty, ts = coordinates(tri_vertices, basis)  # (T, 3) each
    txmin, txmax, tymin, tymax = min3(tx), max3(tx), min3(ty), max3(ty)
    rlo = np.array([rx.min(), ry.min()])
    rhi = np.array([rx.max(), ry.max()])
    span = float(max(np.max(rhi - rlo), np.max(txmax - txmin), np.max(tymax - tymin), 1e-300))
    margin = 1e-9 * span
    keep = (
        (max3(ts) > rs.min())
        & (txmax >= rlo[0] - margin)
        & (tymax >= rlo[1] - margin)
        & (txmin <= rhi[0] + margin)
        & (tymin <= rhi[1] + margin)
    )
    if not keep.any():
        return
    kept = np.flatnonzero(keep)
    tri = tri_vertices[keep]
    tmin = np.stack([txmin[keep], tymin[keep]], axis=1) - margin
    tmax = np.stack([txmax[keep], tymax[keep]], axis=1) + margin

    # Per-triangle Moeller-Trumbore terms with d fixed: u = o.P - cu, v = o.Q - cv,
    # t = o.M - ct (t is the distance along d from o to the triangle's plane).
    v0 = tri[:, 0]
    e1 = tri[:, 1] - v0
    e2 = tri[:, 2] - v0
    pvec = np.cross(d, e2)
    inv = 1.0 / np.einsum("ij,ij->i", e1, pvec)
    P = pvec * inv[:, None]
    Q = np.cross(e1, d) * inv[:, None]
    M = np.cross(e1, e2) * inv[:, None]
    coef = [np.ascontiguousarray(a[:, k]) for a in (P, Q, M) for k in range(3)]
    const = [np.einsum("ij,ij->i", v0, a) for a in (P, Q, M)]

    ox_all, oy_all, oz_all = (np.ascontiguousarray(origins[:, k]) for k in range(3))
    eps = EDGE_TOLERANCE
    for r_rep, t_idx in grid_pairs(rx, ry, tmin, tmax, max_pairs):
        ox, oy, oz = ox_all[r_rep], oy_all[r_rep], oz_all[r_rep]
        u = ox * coef[0][t_idx] + oy * coef[1][t_idx] + oz * coef[2][t_idx] - const[0][t_idx]
        v = ox * coef[3][t_idx] + oy * coef[4][t_idx] + oz * coef[5][t_idx] - const[1][t_idx]
        ok = (u >= -eps) & (v >= -eps) & (u + v <= 1.0 + eps)
        t = ox * coef[6][t_idx] + oy * coef[7][t_idx] + oz * coef[8][t_idx] - const[2][t_idx]
        ok &= t > 0.0
        yield r_rep[ok], kept[t_idx[ok]], t[ok]


def first_hit(origins, directions, tri_vertices, max_pairs=MAX_PAIRS // 4) -> tuple:
    """``(face, t)`` of the first triangle each ray meets (-1, inf for none), every pair tested."""
    origins = np.asarray(origins, dtype=float)
    directions = np.asarray(directions, dtype=float)
    n_rays = len(origins)
    face = np.full(n_rays, -1, dtype=np.int64)
    distance = np.full(n_rays, np.inf)
    if n_rays == 0 or len(tri_vertices) == 0:
        return face, distance
    v0 = tri_vertices[:, 0]
    e1 = tri_vertices[:, 1] - v0
    e2 = tri_vertices[:, 2] - v0
    step = max(1, int(max_pairs) // len(tri_vertices))
    eps = EDGE_TOLERANCE
    for start in range(0, n_rays, step):
        o = origins[start : start + step, None, :]
        d = directions[start : start + step, None, :]
        pvec = np.cross(d, e2)
        det = np.einsum("rtk,tk->rt", pvec, e1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / det
            tvec = o - v0
            u = np.einsum("rtk,rtk->rt", tvec, pvec) * inv
            qvec = np.cross(tvec, e1)
            v = np.einsum("rtk,rtk->rt", d, qvec) * inv
            t = np.einsum("rtk,tk->rt", qvec, e2) * inv
        ok = (det != 0.0) & (u >= -eps) & (v >= -eps) & (u + v <= 1.0 + eps) & (t > 0.0)
        t = np.where(ok, t, np.inf)
        best = np.argmin(t, axis=1)
        best_t = t[np.arange(len(best)), best]
        met = np.isfinite(best_t)
        face[start : start + step] = np.where(met, best, -1)
        distance[start : start + step] = best_t
    return face, distance


class NumpyScene:
    """The panels of a mesh (face i is panel i) as a numpy ray-casting scene (float64)."""

    backend = "numpy"

    def __init__(self, mesh: PanelMesh):
        self.triangles = mesh.vertices

    def first_hit(self, origins, directions) -> tuple:
        """``(face, t)`` of the first panel each ray meets (:func:`first_hit`)."""
        return first_hit(origins, directions, self.triangles)

    def any_hit(self, origins, direction, occluder=None) -> np.ndarray:
        """Whether each ray meets an occluding panel (``RayScene.any_hit``)."""
        triangles = self.triangles if occluder is None else self.triangles[occluder]
        return any_hit(np.asarray(origins, dtype=float), direction, triangles)

    def first_face(self, origins, direction, occluder=None) -> np.ndarray:
        """The first occluding panel each ray meets, -1 for none."""
        if occluder is None:
            return first_along(origins, direction, self.triangles)
        index = np.flatnonzero(occluder)
        face = first_along(origins, direction, self.triangles[index])
        return np.where(face >= 0, index[np.maximum(face, 0)], -1)
