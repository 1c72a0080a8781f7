"""Ray casting in numpy: do rays along one direction meet any of a set of triangles (float64).

The reference ray backend, and the fallback when Embree is not installed: Moeller-Trumbore with the
direction fixed, candidate (ray, triangle) pairs from a uniform 2-D grid in the plane normal to
the rays, in chunks of bounded memory."""

from __future__ import annotations

import numpy as np

#: Cap on the number of (ray, triangle) or (panel, panel) pairs held in memory at once.
MAX_PAIRS = 1 << 21


def _perp_basis(d: np.ndarray) -> np.ndarray:
    """A right-handed orthonormal basis (p1, p2, d) as the columns of a 3x3 matrix."""
    k = int(np.argmin(np.abs(d)))
    e = np.zeros(3)
    e[k] = 1.0
    p1 = np.cross(d, e)
    p1 /= np.linalg.norm(p1)
    p2 = np.cross(d, p1)
    return np.stack([p1, p2, d], axis=1)


# ---------------------------------------------------------------------------------- numpy rays
def _coords(points: np.ndarray, basis: np.ndarray):
    """Coordinates of points (..., 3) along the three columns of ``basis`` (three arrays)."""
    flat = points.reshape(-1, 3)
    shape = points.shape[:-1]
    return tuple((flat @ basis[:, k]).reshape(shape) for k in range(3))


def _min3(a: np.ndarray) -> np.ndarray:
    """Minimum over the last axis of length 3 (faster than ``min(axis=-1)``)."""
    return np.minimum(np.minimum(a[..., 0], a[..., 1]), a[..., 2])


def _max3(a: np.ndarray) -> np.ndarray:
    """Maximum over the last axis of length 3."""
    return np.maximum(np.maximum(a[..., 0], a[..., 1]), a[..., 2])


def _grid_pairs(px, py, bmin, bmax, max_pairs=MAX_PAIRS):
    """Chunks of (point, box) index pairs whose grid cells match, for 2-D point-in-box work.

    Parameters
    ----------
    px, py : ndarray, shape (R,)
        Point coordinates in a plane.
    bmin, bmax : ndarray, shape (T, 2)
        Lower and upper corners of the boxes (e.g. projected triangle bounding boxes).
    max_pairs : int
        Largest number of pairs per chunk (memory bound; a point with more boxes in its cell
        than this is still yielded whole).

    Yields
    ------
    point_index, box_index : ndarray of int, shape (P,)
        Every pair (r, t) with point r inside box t is yielded exactly once (plus pairs that
        share a cell without overlapping, which the caller filters).

    Notes
    -----
    A uniform grid covers the points' bounding box with square cells of 0.4 times the median
    box size (coarsened if boxes would cover too many cells); each box is entered in every cell
    its extent touches (clamped to the grid), each point looks up its own cell.
    """
    n_pts, n_box = len(px), len(bmin)
    if n_pts == 0 or n_box == 0:
        return
    lo = np.array([px.min(), py.min()])
    hi = np.array([px.max(), py.max()])
    span = float(max(np.max(hi - lo), np.max(bmax - bmin), 1e-300))
    extent = np.maximum(hi - lo, 1e-12 * span)
    size = float(np.median(np.max(bmax - bmin, axis=1)))
    cell = max(0.4 * size, float(extent.max()) / 2048.0, 1e-12 * span)
    while True:
        gxy = np.maximum(np.ceil(extent / cell).astype(np.int64), 1)
        i0 = np.minimum(np.floor(np.maximum(bmin - lo, 0.0) / cell).astype(np.int64), gxy - 1)
        i1 = np.minimum(np.floor(np.maximum(bmax - lo, 0.0) / cell).astype(np.int64), gxy - 1)
        nxy = i1 - i0 + 1
        counts = nxy[:, 0] * nxy[:, 1]
        total = int(counts.sum())
        if total <= 32 * n_box + int(gxy.prod()) or int(gxy.max()) == 1:
            break
        cell *= 2.0
    gx = int(gxy[0])
    box_rep = np.repeat(np.arange(n_box), counts)
    local = np.arange(total) - np.repeat(np.cumsum(counts) - counts, counts)
    nx = nxy[box_rep, 0]
    entry_cell = (i0[box_rep, 1] + local // nx) * gx + (i0[box_rep, 0] + local % nx)
    order = np.argsort(entry_cell, kind="stable")
    entry_box = box_rep[order]
    cell_count = np.bincount(entry_cell, minlength=int(gxy.prod()))
    cell_start = np.cumsum(cell_count) - cell_count

    cx = np.minimum(np.floor(np.maximum(px - lo[0], 0.0) / cell).astype(np.int64), gxy[0] - 1)
    cy = np.minimum(np.floor(np.maximum(py - lo[1], 0.0) / cell).astype(np.int64), gxy[1] - 1)
    point_cell = cy * gx + cx
    per_point = cell_count[point_cell]
    live = np.flatnonzero(per_point)
    if live.size == 0:
        return
    cum = np.cumsum(per_point[live])
    begin = 0
    while begin < live.size:
        base = cum[begin - 1] if begin else 0
        end = max(int(np.searchsorted(cum, base + max_pairs, side="right")), begin + 1)
        pts = live[begin:end]
        pc = per_point[pts]
        n_pairs = int(pc.sum())
        p_rep = np.repeat(pts, pc)
        off = np.arange(n_pairs) - np.repeat(np.cumsum(pc) - pc, pc)
        yield p_rep, entry_box[np.repeat(cell_start[point_cell[pts]], pc) + off]
        begin = end


def _any_hit_numpy(origins, d, tri_vertices, max_pairs=MAX_PAIRS):
    """Whether each ray origins[r] + t d, t > 0, meets any of the triangles (float64).

    Parameters
    ----------
    origins : ndarray, shape (R, 3)
        Ray origins [m], G.
    d : ndarray, shape (3,)
        Common unit ray direction.
    tri_vertices : ndarray, shape (T, 3, 3)
        Candidate occluders; none may be parallel to d.
    max_pairs : int
        Largest number of (ray, triangle) pairs tested at once (memory bound).

    Returns
    -------
    ndarray of bool, shape (R,)

    Notes
    -----
    Moeller-Trumbore with the direction fixed, so every per-triangle term is precomputed and a
    pair costs three dot products. Pairs come from a uniform grid in the plane normal to d
    (:func:`_grid_pairs`): a ray is tested only against the triangles whose projected
    bounding box touches its cell.
    Edges are inclusive (u, v >= -1e-12, u + v <= 1 + 1e-12).
    """
    n_rays = len(origins)
    hit = np.zeros(n_rays, dtype=bool)
    if n_rays == 0 or len(tri_vertices) == 0:
        return hit
    basis = _perp_basis(d)
    rx, ry, rs = _coords(origins, basis)
    tx, ty, ts = _coords(tri_vertices, basis)  # (T, 3) each
    txmin, txmax, tymin, tymax = _min3(tx), _max3(tx), _min3(ty), _max3(ty)
    rlo = np.array([rx.min(), ry.min()])
    rhi = np.array([rx.max(), ry.max()])
    span = float(max(np.max(rhi - rlo), np.max(txmax - txmin), np.max(tymax - tymin), 1e-300))
    margin = 1e-9 * span
    keep = (
        (_max3(ts) > rs.min())
        & (txmax >= rlo[0] - margin)
        & (tymax >= rlo[1] - margin)
        & (txmin <= rhi[0] + margin)
        & (tymin <= rhi[1] + margin)
    )
    if not keep.any():
        return hit
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
    eps = 1e-12
    for r_rep, t_idx in _grid_pairs(rx, ry, tmin, tmax, max_pairs):
        ox, oy, oz = ox_all[r_rep], oy_all[r_rep], oz_all[r_rep]
        u = ox * coef[0][t_idx] + oy * coef[1][t_idx] + oz * coef[2][t_idx] - const[0][t_idx]
        v = ox * coef[3][t_idx] + oy * coef[4][t_idx] + oz * coef[5][t_idx] - const[1][t_idx]
        ok = (u >= -eps) & (v >= -eps) & (u + v <= 1.0 + eps)
        t = ox * coef[6][t_idx] + oy * coef[7][t_idx] + oz * coef[8][t_idx] - const[2][t_idx]
        ok &= t > 0.0
        hit[r_rep[ok]] = True
    return hit
