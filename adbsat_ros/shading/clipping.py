"""Triangles clipped by convex polygons in the plane: the part of each triangle outside them.

The covered part of a triangle is the union of its intersections with the polygons; its area
and first moment are summed by inclusion-exclusion over the intersections with every non-empty
set of polygons, each intersection convex: the triangle clipped (Sutherland-Hodgman) by the
half-planes inside the polygons' sides, vectorised over the triangles. Only the sides that have
one of a triangle's corners outside cut it, so each triangle takes only those, in passes as
many as the most any triangle needs. :mod:`adbsat_ros.shading.convex_shadow` uses it for the
exact shadows of convex parts.

Units: any length, the same for every point.
"""

from __future__ import annotations

import numpy as np

#: A polygon's corner is on the line it is clipped by if its side, the cross product of the
#: line's direction with the corner's offset from the line, is within this fraction of their
#: magnitudes' product (rounding of the points and of the product, with room).
SIDE_TOLERANCE = 16.0 * np.finfo(float).eps


def lit_parts(triangles: np.ndarray, outlines) -> tuple:
    """The part of each triangle outside some convex polygons: its area fraction and centroid.

    The covered part is the union of the triangle's intersections with the polygons, its area
    and first moment summed by inclusion-exclusion over the intersections of the triangle with
    every non-empty set of polygons (each one convex: the triangle clipped by each polygon of
    the set in turn).

    Parameters
    ----------
    triangles : ndarray, shape (K, 3, 2)
        Triangles [m] (either orientation, non-degenerate).
    outlines : sequence of ndarray, each of shape (m, 2) or (K, m, 2)
        Convex polygons [m], counter-clockwise
        (:func:`~adbsat_ros.shading.convex_shadow.convex_outline`): one for every
        triangle: (m, 2) shared by all, or (K, m, 2) one per triangle.

    Returns
    -------
    fraction : ndarray, shape (K,)
        Area of the triangle outside the polygons over the triangle's area, in [0, 1].
    centroid : ndarray, shape (K, 2)
        Centroid of that part [m] (the triangle's centroid where none of it is covered; any
        value where all of it is).
    """
    tri = np.asarray(triangles, dtype=float)
    k = tri.shape[0]
    outlines = [np.broadcast_to(o, (k, *np.shape(o)[-2:])) for o in outlines]
    area_t, centroid_t = _triangle_area_centroid(tri)
    n = len(outlines)
    if n == 0:  # nothing covers them
        return np.ones(k), centroid_t
    # the 2^n - 1 non-empty sets of polygons (n is a few), one row each
    sets = np.array([[s >> i & 1 for i in range(n)] for s in range(1, 1 << n)], dtype=bool)
    area, centroid = _covered(tri, area_t, centroid_t, outlines, sets)
    area_u, moment_u = np.zeros(k), np.zeros((k, 2))
    for s, chosen in enumerate(sets):
        sign = 1.0 if chosen.sum() % 2 else -1.0
        area_u += sign * area[s]
        moment_u += sign * area[s, :, None] * centroid[s]  # (finite, also of area 0)
    area_u = np.clip(area_u, 0.0, area_t)
    lit = area_t - area_u
    fraction = lit / area_t
    with np.errstate(invalid="ignore", divide="ignore"):
        centroid = (area_t[:, None] * centroid_t - moment_u) / lit[:, None]
    centroid = np.where((area_u > 0.0)[:, None], centroid, centroid_t)
    return fraction, np.where(np.isfinite(centroid), centroid, centroid_t)


def _covered(tri, area_t, centroid_t, outlines, sets) -> tuple:
    """Area (S, K) and centroid (S, K, 2) of each triangle's intersection with the polygons of
    each set: ``outlines`` ((K, m, 2) each: the polygons of each triangle), ``sets`` (S, n)
    which of them each set holds (the triangle's own area and centroid where it lies inside
    all of a set, zero where outside one).

    A triangle is clipped only by the edges of the set's polygons that have one of its
    corners outside: the part clipped so far lies in the triangle, so an edge with the whole
    triangle on its inner side cuts nothing. Every set's triangles are clipped together, the
    edges that cut taken row by row: as many passes as the most any row needs (a panel
    crossing one side of a part's outline: one pass, not one per side of the outline)."""
    starts, ends, sides, owner = [], [], [], []
    for i, outline in enumerate(outlines):  # which side of each edge each corner is on
        a, b = outline, np.roll(outline, -1, axis=1)
        edge = (b - a)[:, :, None]
        sides.append(  # (K, m, 3), >= 0: inside
            edge[..., 0] * (tri[:, None, :, 1] - a[:, :, None, 1])
            - edge[..., 1] * (tri[:, None, :, 0] - a[:, :, None, 0])
        )
        starts.append(a)
        ends.append(b)
        owner += [i] * outline.shape[1]
    corner_out = np.concatenate(sides, axis=1) < 0.0  # (K, E, 3): every edge of every outline
    owner = np.array(owner)
    # (the three corners joined elementwise: any/all over the axis of length 3 cost 0.1 ms
    # more, 5 % of clipping 1,518 panels against one outline, in one run)
    c0, c1, c2 = corner_out[..., 0], corner_out[..., 1], corner_out[..., 2]
    cutting = c0 | c1 | c2  # (K, E): some corner beyond the edge
    beyond = c0 & c1 & c2  # (K, E): every corner beyond it
    own = owner[None, :] == np.arange(len(outlines))[:, None]  # (n, E)
    within = ~(cutting[:, None, :] & own).any(axis=2)  # (K, n): inside the polygon
    apart = (beyond[:, None, :] & own).any(axis=2)  # (K, n): outside it
    inside = (within[None] | ~sets[:, None, :]).all(axis=2)  # (S, K)
    outside = (apart[None] & sets[:, None, :]).any(axis=2)
    area = np.where(inside & ~outside, area_t, 0.0)
    centroid = np.repeat(centroid_t[None], len(sets), axis=0)
    s, k = np.nonzero(~inside & ~outside)
    if k.size:
        # Sutherland-Hodgman: clip the triangles by the half-planes left of the edges that cut
        needed = cutting[k] & sets[s][:, owner]  # (C, E)
        passes = needed.sum(axis=1)
        order = np.argsort(~needed, axis=1, kind="stable")  # each row's cutting edges first
        a_all = np.concatenate(starts, axis=1)[k]
        b_all = np.concatenate(ends, axis=1)[k]
        capacity = 3 + int(passes.max())
        poly = np.zeros((k.size, capacity, 2))
        poly[:, :3] = tri[k]
        count = np.full(k.size, 3)
        for p in range(int(passes.max())):
            rows = np.flatnonzero(p < passes)  # (the rows with an edge left to clip by)
            e = order[rows, p]
            poly[rows], count[rows] = _clip(
                poly[rows], count[rows], a_all[rows, e], b_all[rows, e], capacity
            )
        area_cut, centroid_cut = _area_centroid(poly, count)
        area[s, k] = area_cut
        centroid[s, k] = np.where((area_cut > 0.0)[:, None], centroid_cut, centroid_t[k])
    return np.clip(area, 0.0, area_t), centroid


def _clip(poly, count, a, b, capacity):
    """Polygons (K, capacity, 2) with ``count`` corners each, clipped to the half-plane left of
    the directed line a -> b ((K, 2) each: the inside of a counter-clockwise outline)."""
    k = poly.shape[0]
    valid, nxt, q = _edges(poly, count)
    p = poly
    edge = (b - a)[:, None, :]
    a = a[:, None, :]
    side_p = edge[..., 0] * (p[..., 1] - a[..., 1]) - edge[..., 1] * (p[..., 0] - a[..., 0])
    # A corner within rounding of the line is on it: a corner of the panel on a corner of the
    # outline otherwise gives sides like (-, +, -1e-16, -0.0), four crossings where a convex
    # polygon has at most two, and one corner more than the buffer holds.
    offset = np.where(valid[..., None], np.abs(p - a), 0.0).max(axis=(1, 2))
    reach = np.abs(edge).max(axis=2) * offset[:, None]
    side_p = np.where(np.abs(side_p) <= SIDE_TOLERANCE * reach, 0.0, side_p)
    side_q = np.take_along_axis(side_p, nxt, axis=1)
    in_q = side_q >= 0.0
    crossing = valid & (side_p * side_q < 0.0)  # (strictly on the two sides)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = side_p / (side_p - side_q)
        cut = p + t[..., None] * (q - p)
    # per edge p -> q: the crossing point (if it crosses), then q (if q is inside)
    emit_cut = crossing
    emit_q = valid & in_q
    n_out = emit_cut.astype(int) + emit_q.astype(int)
    start = np.cumsum(n_out, axis=1) - n_out
    out = np.zeros_like(poly)
    rows = np.broadcast_to(np.arange(k)[:, None], (k, capacity))
    out[rows[emit_cut], start[emit_cut]] = cut[emit_cut]
    shift = start + emit_cut
    out[rows[emit_q], shift[emit_q]] = q[emit_q]
    return out, n_out.sum(axis=1).clip(max=capacity)


def _area_centroid(poly, count):
    """Area (absolute) and centroid of polygons (K, capacity, 2) with ``count`` corners each
    (shoelace; zero area and any centroid for fewer than three corners)."""
    valid, _, q = _edges(poly, count)
    p = poly
    cross = np.where(valid, p[..., 0] * q[..., 1] - q[..., 0] * p[..., 1], 0.0)
    twice = cross.sum(axis=1)
    cx = ((p[..., 0] + q[..., 0]) * cross).sum(axis=1)
    cy = ((p[..., 1] + q[..., 1]) * cross).sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        centroid = np.stack([cx, cy], axis=1) / (3.0 * twice[:, None])
    return np.abs(0.5 * twice), centroid


def _triangle_area_centroid(tri):
    """:func:`_area_centroid` of triangles (K, 3, 2): the same operations in the same order,
    on the corners' coordinates as arrays of K (its general form took 0.44 of the 2.4 ms of
    clipping a finned body's panels, one run)."""
    x0, y0, x1, y1, x2, y2 = (tri[:, i, j] for i in range(3) for j in range(2))
    c0, c1, c2 = x0 * y1 - x1 * y0, x1 * y2 - x2 * y1, x2 * y0 - x0 * y2
    twice = c0 + c1 + c2
    cx = (x0 + x1) * c0 + (x1 + x2) * c1 + (x2 + x0) * c2
    cy = (y0 + y1) * c0 + (y1 + y2) * c1 + (y2 + y0) * c2
    with np.errstate(invalid="ignore", divide="ignore"):
        centroid = np.stack([cx, cy], axis=1) / (3.0 * twice[:, None])
    return np.abs(0.5 * twice), centroid


def _edges(poly, count):
    """The edges p -> q of polygons (K, capacity, 2) with ``count`` corners each: which corner
    slots are corners (K, capacity), the index of each corner's successor, and the successors
    (K, capacity, 2; what lies beyond a row's corners is not its successors)."""
    k, capacity = poly.shape[:2]
    index = np.arange(capacity)
    valid = index[None, :] < count[:, None]
    nxt = np.where(index[None, :] + 1 < count[:, None], index[None, :] + 1, 0)
    # each corner's successor: the next slot, and the first corner after a row's last one (the
    # slots beyond a row's corners are read by no caller)
    q = np.roll(poly, -1, axis=1)
    q[np.arange(k), np.maximum(count - 1, 0)] = poly[:, 0]
    return valid, nxt, q
