"""Coordinates in the plane normal to the flow, and a 2-D grid that pairs points with boxes [m]."""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry import frames

#: Cap on the number of (ray, triangle) or (panel, panel) pairs held in memory at once.
MAX_PAIRS = 1 << 21


def perp_basis(d: np.ndarray) -> np.ndarray:
    """Right-handed orthonormal columns (p1, p2, d); p1, p2 span the plane normal to unit ``d``."""
    k = int(np.argmin(np.abs(d)))
    e = np.zeros(3)
    e[k] = 1.0
    p1 = frames.cross(d, e)  # (np.cross's numbers, without its checks)
    p1 /= np.linalg.norm(p1)
    p2 = frames.cross(d, p1)
    return np.stack([p1, p2, d], axis=1)


def perp_bases(d: np.ndarray) -> np.ndarray:
    """:func:`perp_basis` of each unit direction (D, 3): (D, 3, 3)."""
    rows = np.arange(len(d))
    e = np.zeros_like(d)
    e[rows, np.argmin(np.abs(d), axis=1)] = 1.0
    p1 = np.cross(d, e)
    p1 /= np.sqrt(np.einsum("ij,ij->i", p1, p1))[:, None]
    return np.stack([p1, np.cross(d, p1), d], axis=2)


def coordinates(points: np.ndarray, basis: np.ndarray) -> tuple:
    """Coordinates [m] of ``points`` (..., 3) along the columns of ``basis``: three arrays."""
    flat = points.reshape(-1, 3)
    shape = points.shape[:-1]
    return tuple((flat @ basis[:, k]).reshape(shape) for k in range(3))


def min3(a: np.ndarray) -> np.ndarray:
    """Minimum over the last axis of length 3 (e.g. over a triangle's corners)."""
    return np.minimum(np.minimum(a[..., 0], a[..., 1]), a[..., 2])


def max3(a: np.ndarray) -> np.ndarray:
    """Maximum over the last axis of length 3 (e.g. over a triangle's corners)."""
    return np.maximum(np.maximum(a[..., 0], a[..., 1]), a[..., 2])


def grid_pairs(px, py, bmin, bmax, max_pairs=MAX_PAIRS):
    """Chunks ``(point_index, box_index)`` of the pairs whose grid cells match (a superset of the
    hits).

    px, py (R,) and bmin, bmax (T, 2) [m]; at most ``max_pairs`` per chunk.
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
