"""Triangles clipped by convex polygons in the plane: the part of each triangle outside them, by
inclusion-exclusion over sets of polygons, each set's intersection clipped Sutherland-Hodgman by
the half-planes left of the polygons' edges, vectorised over triangles. Units: any length, the
same for every point."""

from __future__ import annotations

import numpy as np

#: A polygon's corner is on the line it is clipped by if its side, the cross product of the
#: line's direction with the corner's offset from the line, is within this fraction of their
#: magnitudes' product (rounding of the points and of the product, with room).
SIDE_TOLERANCE = 16.0 * np.finfo(float).eps


def lit_parts_of_edges(tx, ty, table: np.ndarray, index: np.ndarray) -> tuple:
    """The part of triangles ``tx``, ``ty`` (3, K) outside convex polygons given as half-planes:
    ``table`` (4, E, R + 1) holds the edges a -> b, ``(ax, ay, bx, by)``, of R polygons, each
    left of its edges (an edge with a = b bounds nothing; the last column none), and ``index``
    (K, n) says which polygons each triangle has (R: none in that slot)."""
    tx, ty = np.ascontiguousarray(tx, dtype=float), np.ascontiguousarray(ty, dtype=float)
    k, n = tx.shape[1], index.shape[1]
    area_t, cx_t, cy_t = _area_centroid(tx, ty, 3)
    centroid_t = np.stack([cx_t, cy_t], axis=1)
    if n == 0 or k == 0:  # nothing covers them
        return np.ones(k), centroid_t
    # the 2^n - 1 non-empty sets of polygons (n is a few), one row each, and their pieces: a
    # triangle and a set of polygons it has, clipped by the set's edges (the others' none)
    none = table.shape[2] - 1
    sets = np.array([[s >> i & 1 for i in range(n)] for s in range(1, 1 << n)], dtype=bool)
    s, c = np.nonzero(((index[None, :, :] < none) | ~sets[:, None, :]).all(axis=2))
    if c.size == 0:
        return np.ones(k), centroid_t
    rows = np.where(sets[s], index[c], none).T  # (n, P)
    edges = np.concatenate([table[:2], table[2:] - table[:2]])  # (ax, ay, ex, ey): e = b - a
    edges = edges[:, :, rows].reshape(4, -1, c.size)  # (4, E n, P)
    area, cx, cy = _covered(tx[:, c], ty[:, c], area_t[c], cx_t[c], cy_t[c], edges)
    sign = np.where(sets.sum(axis=1) % 2, 1.0, -1.0)[s] * area
    area_u = np.bincount(c, sign, minlength=k)
    mx, my = np.bincount(c, sign * cx, minlength=k), np.bincount(c, sign * cy, minlength=k)
    area_u = np.clip(area_u, 0.0, area_t)
    lit = area_t - area_u
    fraction = lit / area_t
    with np.errstate(invalid="ignore", divide="ignore"):
        centroid = np.stack([area_t * cx_t - mx, area_t * cy_t - my], axis=1) / lit[:, None]
    centroid = np.where((area_u > 0.0)[:, None], centroid, centroid_t)
    return fraction, np.where(np.isfinite(centroid), centroid, centroid_t)


def _covered(tx, ty, area_t, cx_t, cy_t, edges) -> tuple:
    """Area and centroid x, y (P,) of each triangle's part left of its edges a -> a + e,
    ``(ax, ay, ex, ey)`` (E, P) each."""
    ax, ay, ex, ey = edges
    # (E, P) each: the corner beyond the edge
    c0, c1, c2 = (ex * (ty[j] - ay) - ey * (tx[j] - ax) < 0.0 for j in range(3))
    cut = c0 | c1 | c2  # some corner beyond the edge
    inside = ~cut.any(axis=0)
    outside = (c0 & c1 & c2).any(axis=0)  # every corner beyond one edge
    area = np.where(inside & ~outside, area_t, 0.0)
    cx, cy = cx_t.copy(), cy_t.copy()
    c = np.flatnonzero(~inside & ~outside)
    if c.size:
        # Sutherland-Hodgman: clip the triangles by the half-planes left of the edges that cut
        needed = cut[:, c]  # (E, C)
        passes = needed.sum(axis=0)
        order = np.argsort(~needed, axis=0, kind="stable")  # each column's cutting edges first
        ax, ay, ex, ey = ax[:, c], ay[:, c], ex[:, c], ey[:, c]
        most = int(passes.max())
        px, py = np.zeros((3 + most, c.size)), np.zeros((3 + most, c.size))
        px[:3], py[:3] = tx[:, c], ty[:, c]
        count = np.full(c.size, 3)
        for p in range(most):
            cols = np.flatnonzero(p < passes)  # (the triangles with an edge left to clip by)
            e = order[p, cols]
            px[:, cols], py[:, cols], count[cols] = _clip(
                px[:, cols],
                py[:, cols],
                count[cols],
                (ax[e, cols], ay[e, cols]),
                (ex[e, cols], ey[e, cols]),
            )
        area_cut, cx_cut, cy_cut = _area_centroid(px, py, count)
        cut_lit = area_cut > 0.0
        area[c] = area_cut
        cx[c] = np.where(cut_lit, cx_cut, cx_t[c])
        cy[c] = np.where(cut_lit, cy_cut, cy_t[c])
    return np.clip(area, 0.0, area_t), cx, cy


def _clip(px, py, count, a, e) -> tuple:
    """Polygons ``px``, ``py`` (capacity, R) clipped left of the lines a -> a + e."""
    capacity, r = px.shape
    valid, qx, qy, last = _edges(px, py, count)
    (ax, ay), (ex, ey) = a, e
    side_p = ex * (py - ay) - ey * (px - ax)
    # A corner within rounding of the line is on it: a corner of the panel on a corner of the
    # outline otherwise gives sides like (-, +, -1e-16, -0.0), four crossings where a convex
    # polygon has at most two, and one corner more than the buffer holds.
    offset = np.where(valid, np.maximum(np.abs(px - ax), np.abs(py - ay)), 0.0).max(axis=0)
    reach = np.maximum(np.abs(ex), np.abs(ey)) * offset
    side_p = np.where(np.abs(side_p) <= SIDE_TOLERANCE * reach, 0.0, side_p)
    side_q = _successors(side_p, last)
    crossing = valid & (side_p * side_q < 0.0)  # (strictly on the two sides)
    t = np.divide(side_p, side_p - side_q, out=np.zeros((capacity, r)), where=crossing)
    cut_x, cut_y = px + t * (qx - px), py + t * (qy - py)
    # per edge p -> q: the crossing point (if it crosses), then q (if q is inside)
    emit_q = valid & (side_q >= 0.0)
    n_out = crossing.astype(int) + emit_q.astype(int)
    start = np.cumsum(n_out, axis=0) - n_out
    out_x, out_y = np.zeros((capacity, r)), np.zeros((capacity, r))
    slot, column = np.nonzero(crossing)
    at = start[slot, column], column
    out_x[at], out_y[at] = cut_x[slot, column], cut_y[slot, column]
    slot, column = np.nonzero(emit_q)
    at = start[slot, column] + crossing[slot, column], column
    out_x[at], out_y[at] = qx[slot, column], qy[slot, column]
    return out_x, out_y, np.minimum(n_out.sum(axis=0), capacity)


def _area_centroid(px, py, count) -> tuple:
    """Area (absolute) and centroid x, y of polygons (capacity, K) (shoelace)."""
    valid, qx, qy, _ = _edges(px, py, count)
    cross = np.where(valid, px * qy - qx * py, 0.0)
    twice = cross.sum(axis=0)
    cx = ((px + qx) * cross).sum(axis=0)
    cy = ((py + qy) * cross).sum(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.abs(0.5 * twice), cx / (3.0 * twice), cy / (3.0 * twice)


def _edges(px, py, count) -> tuple:
    """Edges p -> q of polygons (capacity, K): corner slots, successors, last slots."""
    capacity, k = px.shape
    valid = np.arange(capacity)[:, None] < count
    last = np.maximum(count - 1, 0), np.arange(k)
    return valid, _successors(px, last), _successors(py, last), last


def _successors(values, last) -> np.ndarray:
    """Each corner's value at its successor (the first after the polygon's ``last``)."""
    q = np.roll(values, -1, axis=0)
    q[last] = values[0]
    return q
