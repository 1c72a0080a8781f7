"""The exact shadows of closed convex parts: what of each panel behind them stays lit. Projected
normal to the flow, each part is a convex polygon and the panel a triangle, clipped exactly
(docs/shading.md). Units: metres; 2-D points in the plane normal to the flow."""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.shading.clipping import lit_parts

#: Most convex parts whose shadows on one panel are joined exactly (their union is summed by
#: inclusion-exclusion over 2^n - 1 intersections).
MAX_OCCLUDERS = 3
#: A part the panel's plane cuts is cut through the segments between each pair of its corners
#: on the two sides; beyond this many corners (a finely divided cylinder) its panels are left
#: to the rays.
MAX_CUT_CORNERS = 64
#: The cut is made once per plane. Panels on more planes than this behind the same parts (the
#: facets of a curved surface) are left to their rays.
MAX_CUT_PLANES = 32
#: A convex part counts as wholly in front of a panel if each of its hull corners is at least
#: this fraction of the mesh's bounding-box diagonal in front of the panel's plane (and as
#: wholly behind if none is).
FRONT_TOL_FRACTION = 1e-9
#: An outline whose area is below this fraction of the square of its extent spans no area (a
#: part seen edge-on): its panels are left to the rays; nor is a corner one whose triangle with
#: its two neighbours has an area below it (it lies on their line up to rounding).
FLAT_OUTLINE = 1e-12
#: Panels share a plane if their unit normals and their planes' offsets (as fractions of the
#: bounding-box diagonal) agree to this many decimals: the rounding of a mesh's vertices
#: (float32 in a binary STL, nine digits in an OBJ) tilts the panels of one flat face by up to
#: about 1e-7, and a plane a millionth of the body's size off moves a shadow by as much.
PLANE_DIGITS = 6


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

    def corners(self, component: int) -> np.ndarray:
        """The corners of a component's convex hull [m], G (made when first asked)."""
        corners = self._corners.get(component)
        if corners is None:
            corners = hull_corners(self.mesh.vertices[self.filter.component == component])
            self._corners[component] = corners
        return corners

    def lighting(self, boxes, panels: np.ndarray) -> tuple:
        """The panels among ``panels`` (K,) that convex parts alone can shade, lit exactly.

        Returns done (K,) bool, fraction and centroid [m, G] of the done panels.
        """
        flt, mesh = self.filter, self.mesh
        occluders = flt.occluders(boxes, panels)
        count = occluders.sum(axis=1)
        facing = mesh.normals[panels] @ boxes.basis[:, 2] > self.graze_tol
        convex = ~(occluders & ~flt.convex[None, :]).any(axis=1)
        done = facing & flt.on_hull[panels] & convex & (count >= 1) & (count <= MAX_OCCLUDERS)
        fraction = np.ones(panels.size)
        centroid = mesh.barycentres[panels].copy()
        outlines: dict = {}  # component -> its projected outline, for this direction
        groups: dict = {}  # the outlines' sizes -> [(panels, rows, their outlines), ...]
        sets, which = _distinct_rows(occluders[done])
        rows_done = np.flatnonzero(done)
        for s, parts in enumerate(sets):  # (a loop over the sets of parts in front, few)
            rows = rows_done[which == s]
            j = panels[rows]
            normals = mesh.normals[j]
            level = np.einsum("kj,kj->k", normals, mesh.vertices[j, 0])
            members = np.flatnonzero(parts).tolist()
            in_front = np.ones(rows.size, dtype=bool)
            for part in members:
                in_front &= (normals @ self.corners(part).T).min(axis=1) - level > self.tolerance
            # the panels with every part wholly in front of them: the parts' whole outlines
            for part in members:
                if part not in outlines:
                    outlines[part] = convex_outline(self.corners(part) @ boxes.basis[:, :2])
            shapes = [outlines[part] for part in members]
            if any(shape is None for shape in shapes):
                done[rows] = False
                continue
            if in_front.any():
                groups.setdefault(_sizes(shapes), []).append((j[in_front], rows[in_front], shapes))
            # the others, one plane (a flat face) at a time: the parts' outlines in front of it
            cut = np.flatnonzero(~in_front)
            if cut.size == 0:
                continue
            planes, plane_of = _distinct_rows(
                np.round(np.column_stack([normals[cut], level[cut] / self.diagonal]), PLANE_DIGITS)
            )
            if len(planes) > MAX_CUT_PLANES:  # (a curved surface: its rays cost less)
                done[rows[cut]] = False
                continue
            for k in range(len(planes)):
                on_plane = cut[plane_of == k]
                first = on_plane[0]
                shapes = self._shadows(members, normals[first], level[first], boxes, outlines)
                if shapes is None:  # (a part projects to no area: left to the rays)
                    done[rows[on_plane]] = False
                elif shapes:  # (no shapes: every part behind the plane, all lit)
                    groups.setdefault(_sizes(shapes), []).append(
                        (j[on_plane], rows[on_plane], shapes)
                    )
        for same in groups.values():  # (one clipping per set of polygon sizes)
            j = np.concatenate([g[0] for g in same])
            rows = np.concatenate([g[1] for g in same])
            polygons = _per_panel_outlines([(g[0].size, g[2]) for g in same])
            self._clip_panels(boxes, j, rows, polygons, fraction, centroid)
        return done, fraction[done], centroid[done]

    def _shadows(self, members, normal, level: float, boxes, outlines: dict) -> list | None:
        """Outlines of the parts ``members`` in front of the plane n . x = level (None if
        degenerate)."""
        shapes = []
        for part in members:
            corners = self.corners(part)
            height = corners @ normal - level
            if height.min() > self.tolerance:  # wholly in front
                outline = outlines[part]
            elif height.max() <= self.tolerance:  # wholly behind: no shadow on this plane
                continue
            elif len(corners) > MAX_CUT_CORNERS:
                return None
            else:
                front, back = height > 0.0, height < 0.0
                a, b = corners[front], corners[back]
                ha, hb = height[front], height[back]
                t = (ha[:, None] / (ha[:, None] - hb[None, :]))[..., None]
                cut = a[:, None, :] + t * (b[None, :, :] - a[:, None, :])
                points = np.concatenate([corners[~back], cut.reshape(-1, 3)])
                outline = convex_outline(points @ boxes.basis[:, :2])
            if outline is None:
                return None
            shapes.append(outline)
        return shapes

    def _clip_panels(self, boxes, j, rows, shapes, fraction, centroid) -> None:
        """Set ``fraction[rows]``, ``centroid[rows]`` of panels ``j`` from polygons ``shapes``."""
        x, y, _ = boxes.coords
        triangles = np.stack([x[j], y[j]], axis=-1)  # (R, 3, 2)
        f, c2 = lit_parts(triangles, shapes)
        fraction[rows] = f
        # the lit centroid back on the panel, through its triangle coordinates
        # (a, b) with c2 = t0 + a (t1 - t0) + b (t2 - t0), by Cramer's rule
        (ux, uy), (vx, vy) = (
            (triangles[:, 1] - triangles[:, 0]).T,
            (triangles[:, 2] - triangles[:, 0]).T,
        )
        rx, ry = (c2 - triangles[:, 0]).T
        det = ux * vy - vx * uy
        a, b = (rx * vy - vx * ry) / det, (ux * ry - rx * uy) / det
        v = self.mesh.vertices[j]
        centroid[rows] = (
            v[:, 0] + a[:, None] * (v[:, 1] - v[:, 0]) + b[:, None] * (v[:, 2] - v[:, 0])
        )


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


def _sizes(shapes) -> tuple:
    """The corner counts of a panel group's polygons (equal counts clipped together)."""
    return tuple(len(shape) for shape in shapes)


def _per_panel_outlines(groups) -> list:
    """Groups of panels sharing shadows, ``[(count, outlines), ...]``, (K, m, 2) per slot."""
    counts = [count for count, _ in groups]
    return [
        np.repeat(np.stack([outlines[slot] for _, outlines in groups]), counts, axis=0)
        for slot in range(len(groups[0][1]))
    ]


def hull_corners(points: np.ndarray) -> np.ndarray:
    """The corners of the convex hull of 3-D points [m] (all the points if they span no volume)."""
    from scipy.spatial import ConvexHull, QhullError  # (not at start-up)

    points = np.asarray(points, dtype=float).reshape(-1, 3)
    try:
        return points[ConvexHull(points).vertices]
    except (QhullError, ValueError):
        return points


def convex_outline(points: np.ndarray) -> np.ndarray | None:
    """Corners (m, 2), counter-clockwise, of the convex hull of points (P, 2), or None if flat.

    Andrew's monotone chain (A. M. Andrew, Information Processing Letters 9, 216, 1979).
    """
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    if not np.isfinite(points).all():
        return None
    unique = sorted(set(map(tuple, points.tolist())))
    if len(unique) < 3:
        return None
    xs, ys = [x for x, _ in unique], [y for _, y in unique]
    extent = max(xs[-1] - xs[0], max(ys) - min(ys))  # (sorted by x)
    tolerance = 2.0 * FLAT_OUTLINE * extent * extent  # (twice a triangle's area)
    corners = _chain(unique)[:-1] + _chain(unique[::-1])[:-1]
    # corners within the tolerance of the line through their neighbours are dropped (after the
    # hull is made exactly: dropped while making it, a corner could go for a point that is
    # within rounding of it on the other side, the order of near-equal abscissae reversed)
    dropped = True
    while dropped and len(corners) >= 3:
        dropped = False
        for k in range(len(corners)):
            (ox, oy), (ax, ay), (bx, by) = corners[k - 2], corners[k - 1], corners[k]
            if (ax - ox) * (by - oy) - (ay - oy) * (bx - ox) <= tolerance:
                del corners[k - 1]
                dropped = True
                break
    if len(corners) < 3:
        return None
    twice_area = sum(
        x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(corners, corners[1:] + corners[:1])
    )
    return np.array(corners) if twice_area > tolerance else None


def _chain(points: list) -> list:
    """One half of the monotone chain: the corners of sorted ``points`` where it turns left."""
    chain: list = []
    for x, y in points:
        while len(chain) >= 2:
            (ox, oy), (ax, ay) = chain[-2], chain[-1]
            if (ax - ox) * (y - oy) - (ay - oy) * (x - ox) > 0.0:
                break
            chain.pop()
        chain.append((x, y))
    return chain
