"""The exact shadows of closed convex parts: what of each panel behind them stays lit. Projected
normal to the flow, each part is a convex polygon and the panel a triangle, clipped exactly
(docs/shading.md). Units: metres; 2-D points in the plane normal to the flow."""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.shading.candidates import grazing_forward
from adbsat_ros.shading.clipping import lit_parts_of_edges
from adbsat_ros.shading.flow_plane import MAX_PAIRS, perp_bases

#: Most convex parts whose shadows on one panel are joined exactly (by inclusion-exclusion).
MAX_OCCLUDERS = 3
#: A part the panel's plane cuts, of more corners than this (a finely divided cylinder), and
#: panels on more planes than ``MAX_CUT_PLANES`` behind the same parts, are left to the rays.
MAX_CUT_CORNERS = 64
MAX_CUT_PLANES = 32
#: A part is wholly in front of a panel's plane if each hull corner is at least this fraction
#: of the bounding-box diagonal in front of it (wholly behind if none is).
FRONT_TOL_FRACTION = 1e-9
#: An outline of an area below this fraction of its extent squared spans none (a part seen
#: edge-on: its panels are left to the rays).
FLAT_OUTLINE = 1e-12
#: Panels share a plane if their unit normals and offsets (fractions of the diagonal) agree to
#: this many decimals: a mesh's rounding (float32 STL, 9-digit OBJ) tilts a flat face's panels.
PLANE_DIGITS = 6
#: A part's shadow body for a panel: behind the panel's plane (no shadow), left to the rays,
#: not yet made.
BEHIND, REFUSED, UNKNOWN = -1, -2, -3


class ConvexParts:
    """The closed convex components of a mesh, for exact shadows; ``diagonal`` [m] scales
    tolerances;
    ``corners``: hull corners (h, 3) [m], G."""

    def __init__(
        self, mesh: PanelMesh, candidate_filter, diagonal: float, graze_tol: float, corners=None
    ):
        self.mesh = mesh
        self.filter = candidate_filter
        self.diagonal = diagonal
        self.tolerance = FRONT_TOL_FRACTION * diagonal
        self.graze_tol = graze_tol
        self._corners = dict(corners or {})  # component -> its hull corners (h, 3)
        self._table = None  # what does not depend on the flow (:meth:`_panels_and_parts`)
        self._tie = grazing_forward(mesh.normals)
        # [coordinate, corner x panel] (3, 3N), normals (3, N)
        self._vertices = np.ascontiguousarray(mesh.vertices.transpose(2, 1, 0).reshape(3, -1))
        self._normals = np.ascontiguousarray(mesh.normals.T)
        hulls = [self.corners(c) for c in range(candidate_filter.n_components)]
        self._hulls = np.ascontiguousarray(np.concatenate(hulls).T)  # (3, H)
        self._hull_start = np.cumsum([0] + [len(h) for h in hulls[:-1]])

    def corners(self, component: int) -> np.ndarray:
        """The corners of a component's convex hull [m], G (made when first asked)."""
        corners = self._corners.get(component)
        if corners is None:
            corners = hull_corners(self.mesh.vertices[self.filter.component == component])
            self._corners[component] = corners
        return corners

    def lighting_many(self, directions: np.ndarray) -> tuple:
        """Of unit flow directions (D, 3) in G: the forward panels that could be shaded (the
        shader's candidates) (D, N), the count of forward panels (D,), and those candidates lit
        exactly (shaded by convex parts alone) as rows (direction, panel), ascending, with their
        lit fraction and lit centroid [m, G]: ``(candidate, n_forward, d, j, fraction, centroid)``.
        """
        step = max(1, MAX_PAIRS // (self.filter.n_components * self.mesh.n_panels))
        blocks = []
        for s in range(0, len(directions), step):
            blocks.append(self._block(np.asarray(directions[s : s + step], dtype=float)))
            blocks[-1][2] += s
        return tuple(np.concatenate(x) for x in zip(*blocks))

    def _block(self, u: np.ndarray) -> list:
        flt, mesh, tol = self.filter, self.mesh, self.graze_tol
        n_dir, n = len(u), mesh.n_panels
        bases = perp_bases(-u)  # (D, 3, 3): p1, p2, -u
        axes = np.ascontiguousarray(bases.transpose(0, 2, 1))  # (D, 3, 3): p1, p2, -u rows
        coords = (axes @ self._vertices).reshape(n_dir, 3, 3, n)  # [d, axis, corner, panel]
        lo, hi = coords.min(axis=2), coords[:, :2].max(axis=2)  # (D, 3 and 2, N)
        # the components' boxes, from their hulls' corners
        seen = axes @ self._hulls  # (D, 3, H)
        clo = np.minimum.reduceat(seen, self._hull_start, axis=2)[..., None]  # (D, 3, C, 1)
        chi = np.maximum.reduceat(seen, self._hull_start, axis=2)[..., None]
        lo, hi = lo[:, :, None], hi[:, :, None]  # (D, 3, 1, N)
        c = -(u @ self._normals)  # (D, N)
        forward = (c > tol) | ((np.abs(c) <= tol) & self._tie)
        overlap = (  # (D, C, N): which components could shade each panel
            (chi[:, 2] > lo[:, 2])
            & (chi[:, 0] >= lo[:, 0])
            & (clo[:, 0] <= hi[:, 0])
            & (chi[:, 1] >= lo[:, 1])
            & (clo[:, 1] <= hi[:, 1])
        )
        overlap[:, flt.component, np.arange(n)] = False
        candidate = forward & (~flt.on_hull | overlap.any(axis=1))
        count = overlap.sum(axis=1)
        done = candidate & (c > tol) & flt.on_hull & (count >= 1) & (count <= MAX_OCCLUDERS)
        done &= ~(overlap & ~flt.convex[None, :, None]).any(axis=1)
        d, j = np.nonzero(done)
        members = overlap[d, :, j]  # (J, C)
        body, whole, plane = self._bodies(j, members)
        keep = ~(members & (body == REFUSED)).any(axis=1)
        # a set of parts cut by the planes of more than MAX_CUT_PLANES panels (the facets of a
        # curved surface) leaves those panels to the rays
        cut = np.flatnonzero(keep & (members & ~whole).any(axis=1))
        if cut.size:
            key = np.column_stack([d[cut], np.packbits(members[cut], axis=1), plane[j[cut]]])
            triples, which = _distinct_rows(key)
            _, of_triple = _distinct_rows(triples[:, :-1])
            keep[cut[np.bincount(of_triple)[of_triple[which]] > MAX_CUT_PLANES]] = False
        d, j, members, body = d[keep], j[keep], members[keep], body[keep]
        body = np.where(members, body, BEHIND)  # (J, C): the bodies in front (<= 3), or < 0
        body = np.take_along_axis(body, np.argsort(body < 0, axis=1, kind="stable"), axis=1)
        body = body[:, : max(int((body >= 0).sum(axis=1).max(initial=0)), 1)]
        table, index, flat = self._outlines(bases, d, body)
        d, j, index = d[~flat], j[~flat], index[~flat]
        at = (d * 9 + np.arange(3)[:, None]) * n + j  # (3, J): the corners' x, then y
        tx, ty = coords.reshape(-1)[at], coords.reshape(-1)[at + 3 * n]
        fraction, c2 = lit_parts_of_edges(tx, ty, table, index)
        centroid = _on_panel(mesh.vertices[j], tx, ty, c2)
        return [candidate, forward.sum(axis=1), d, j, fraction, centroid]

    def _bodies(self, j: np.ndarray, members: np.ndarray) -> tuple:
        """The shadow body of each part in ``members`` (J, C) for panels ``j``, (J, C) (or
        BEHIND, REFUSED), whether it is the whole part (J, C), and each panel's plane (N,)."""
        if self._table is None:
            mesh = self.mesh
            level = np.einsum("kj,kj->k", mesh.normals, mesh.vertices[:, 0])
            key = np.round(np.column_stack([mesh.normals, level / self.diagonal]), PLANE_DIGITS)
            _, plane = _distinct_rows(key)
            first = np.full(plane.max() + 1 if plane.size else 0, mesh.n_panels)
            np.minimum.at(first, plane, np.arange(mesh.n_panels))
            shape = (mesh.n_panels, self.filter.n_components)
            self._table = (np.full(shape, UNKNOWN), np.zeros(shape, dtype=bool), level, plane)
            self._first, self._made, self._points, self._padded = first, {}, [], ()
        body_of, whole, level, plane = self._table
        need = members & (body_of[j] == UNKNOWN)
        normals = self.mesh.normals
        for part in np.flatnonzero(need.any(axis=0)).tolist():  # (a loop over parts, few)
            panels = np.unique(j[need[:, part]])
            corners = self.corners(part)
            height = normals[panels] @ corners.T - level[panels, None]
            front = height.min(axis=1) > self.tolerance
            body_of[panels[front], part] = self._body(("whole", part), corners)
            whole[panels[front], part] = True
            body_of[panels[height.max(axis=1) <= self.tolerance], part] = BEHIND
            for panel in panels[~front & (height.max(axis=1) > self.tolerance)].tolist():
                body_of[panel, part] = self._cut(plane[panel], part)  # (made once per plane)
        return body_of[j], whole[j], plane

    def _body(self, key, points: np.ndarray) -> int:
        """The index of a shadow body (a convex set of 3-D points [m]), added if new."""
        if key not in self._made:  # (its points sorted: the same outlines whatever their order)
            self._made[key] = len(self._points)
            self._points.append(points[np.lexsort(points.T[::-1])])
        return self._made[key]

    def _cut(self, plane: int, part: int) -> int:
        """The part of a convex part in front of a plane (that of its first panel): its body."""
        if ("cut", plane, part) in self._made:
            return self._made["cut", plane, part]
        first = self._first[plane]
        corners = self.corners(part)
        height = corners @ self.mesh.normals[first] - self._table[2][first]
        if height.min() > self.tolerance:
            return self._body(("whole", part), corners)
        if height.max() <= self.tolerance:
            return BEHIND
        if len(corners) > MAX_CUT_CORNERS:
            return REFUSED
        front, back = height > 0.0, height < 0.0
        a, b = corners[front], corners[back]
        ha, hb = height[front], height[back]
        t = (ha[:, None] / (ha[:, None] - hb[None, :]))[..., None]
        cut = a[:, None, :] + t * (b[None, :, :] - a[:, None, :])
        points = hull_corners(np.concatenate([corners[~back], cut.reshape(-1, 3)]))
        return self._body(("cut", plane, part), points)

    def _outlines(self, bases: np.ndarray, d: np.ndarray, body: np.ndarray) -> tuple:
        """The outlines of shadow bodies ``body`` (J, n) (< 0: none) seen along directions
        ``bases[d]``, as half-planes: ``(ax, ay, bx, by)`` (4, S, M + 1) of M outlines (the
        last none), each job's outlines (J, n) (M: none), and (J,) whether one spans no area
        (a part seen edge-on)."""
        used = body >= 0
        if not used.any():
            return np.zeros((4, 1, 1)), np.zeros(body.shape, dtype=np.int64), ~used[:, 0]
        n_bodies = len(self._points)
        if len(self._padded) != n_bodies:  # (the bodies' points, padded to one count)
            most = max(len(p) for p in self._points)
            self._padded = np.stack(
                [np.concatenate([p, p[:1].repeat(most - len(p), 0)]) for p in self._points]
            )
        pair, which = np.unique((d[:, None] * n_bodies + body)[used], return_inverse=True)
        seen = self._padded[pair % n_bodies] @ bases[pair // n_bodies][:, :, :2]  # (M, q, 2)
        table, flat = hull_edges(seen)
        index = np.full(body.shape, len(pair))
        index[used] = which
        flat = np.append(flat, False)[index].any(axis=1)
        return np.concatenate([table, np.zeros((4, table.shape[1], 1))], axis=2), index, flat


def hull_edges(points: np.ndarray) -> tuple:
    """The edges of the convex hulls of point sets (M, q, 2), counter-clockwise: each pair of
    points with every point left of (or within :data:`FLAT_OUTLINE` of the extent of) the line
    from one to the other. Returns ``(ax, ay, bx, by)`` (4, S, M) (padded with a = b) and (M,)
    whether a hull spans no area."""
    m, q = points.shape[:2]
    step = max(1, MAX_PAIRS // q**3)
    with np.errstate(invalid="ignore", divide="ignore"):  # (points not finite: flat)
        parts = [_hull_edge_mask(points[s : s + step]) for s in range(0, m, step)]
    accept = np.concatenate([a for a, _ in parts]).reshape(m, q * q)
    flat = np.concatenate([f for _, f in parts])
    order = np.argsort(~accept, axis=1, kind="stable")[:, : max(int(accept.sum(axis=1).max()), 1)]
    real = np.take_along_axis(accept, order, axis=1)
    rows = np.arange(m)[:, None]
    a, b = points[rows, order // q], points[rows, order % q]  # (M, S, 2)
    b = np.where(real[..., None], b, a)
    table = np.stack([a[..., 0], a[..., 1], b[..., 0], b[..., 1]])  # (4, M, S)
    return np.ascontiguousarray(table.transpose(0, 2, 1)), flat


def _hull_edge_mask(points: np.ndarray) -> tuple:
    """:func:`hull_edges`' pairs (M, q, q) (i -> k) and flatness (M,) of point sets (M, q, 2)."""
    x, y = points[..., 0], points[..., 1]
    ex, ey = x[:, None, :] - x[:, :, None], y[:, None, :] - y[:, :, None]  # [m, i, k]: k - i
    length = np.hypot(ex, ey)
    span = np.maximum(np.ptp(x, axis=1), np.ptp(y, axis=1))
    scale = np.maximum(span, np.abs(points).max(axis=(1, 2)))
    # [m, i, l, k]: how far left of the line i -> k point l lies, times the length
    cross = ex[:, :, None, :] * ey[..., None] - ey[:, :, None, :] * ex[..., None]
    tolerance = FLAT_OUTLINE * scale[:, None, None]
    accept = (length > 0.0) & (cross.min(axis=2) >= -tolerance * length)
    # one edge from each corner, to the farthest (a side through more corners is one edge),
    # and none from or to a point that repeats one before it
    q = x.shape[1]
    repeat = (np.tril(length <= tolerance, -1)).any(axis=2)  # [m, i]: within reach of k < i
    accept &= ~repeat[:, :, None] & ~repeat[:, None, :]
    farthest = np.where(accept, length, -1.0).argmax(axis=2)
    accept &= np.arange(q) == farthest[..., None]
    width = np.where(accept, cross.max(axis=2) / length, np.inf).min(axis=(1, 2))
    flat = ~(width > 2.0 * FLAT_OUTLINE * span) | ~np.isfinite(points).all(axis=(1, 2))
    return accept, flat


def _on_panel(vertices: np.ndarray, tx: np.ndarray, ty: np.ndarray, c2: np.ndarray) -> np.ndarray:
    """Points ``c2`` (K, 2) in triangles ``tx``, ``ty`` (3, K) put on the panels (K, 3, 3) they
    show [m]: through the triangle coordinates (a, b), c2 = t0 + a (t1 - t0) + b (t2 - t0), by
    Cramer's rule."""
    ux, uy, vx, vy = tx[1] - tx[0], ty[1] - ty[0], tx[2] - tx[0], ty[2] - ty[0]
    rx, ry = c2[:, 0] - tx[0], c2[:, 1] - ty[0]
    det = ux * vy - vx * uy
    a, b = (rx * vy - vx * ry) / det, (ux * ry - rx * uy) / det
    v = vertices
    return v[:, 0] + a[:, None] * (v[:, 1] - v[:, 0]) + b[:, None] * (v[:, 2] - v[:, 0])


def _distinct_rows(keys: np.ndarray) -> tuple:
    """``np.unique(keys, axis=0, return_inverse=True)`` by a lexicographic sort of the columns."""
    if len(keys) == 0:
        return keys[:0], np.zeros(0, dtype=np.int64)
    order = np.lexsort(keys.T[::-1])
    ordered = keys[order]
    first = np.ones(len(keys), dtype=bool)
    first[1:] = (ordered[1:] != ordered[:-1]).any(axis=1)
    which = np.empty(len(keys), dtype=np.int64)
    which[order] = np.cumsum(first) - 1
    return ordered[first], which


def hull_corners(points: np.ndarray) -> np.ndarray:
    """The corners of the convex hull of 3-D points [m] (all the points if they span no volume)."""
    from scipy.spatial import ConvexHull, QhullError  # (not at start-up)

    points = np.asarray(points, dtype=float).reshape(-1, 3)
    try:
        return points[ConvexHull(points).vertices]
    except (QhullError, ValueError):
        return points
