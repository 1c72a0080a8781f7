"""The exact shadows of convex parts: the triangles' lit parts against convex polygons, against
areas and centroids worked out by hand."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from scipy.spatial import ConvexHull

from adbsat_ros.shading.clipping import lit_parts_of_edges
from adbsat_ros.shading.convex_shadow import hull_edges

#: A right triangle with legs 4 along x and y: area 8, centroid (4/3, 4/3).
TRIANGLE = np.array([[[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]]])


def lit_parts(triangles, outlines):
    """The lit fraction and centroid of triangles (K, 3, 2) outside convex polygons, each (m, 2)
    or one per triangle (K, m, 2), counter-clockwise: their edges made the half-plane table."""
    tri = np.asarray(triangles, dtype=float)
    k, n = len(tri), len(outlines)
    shaped = [np.broadcast_to(np.asarray(o, float), (k, np.shape(o)[-2], 2)) for o in outlines]
    table = np.zeros((4, max([p.shape[1] for p in shaped], default=1), n * k + 1))
    for i, p in enumerate(shaped):
        x, y = p[:, :, 0].T, p[:, :, 1].T
        columns = slice(i * k, (i + 1) * k)
        table[:, :, columns] = np.stack([x[-1], y[-1]] * 2)[:, None]  # (past its edges: a = b)
        table[:, : len(x), columns] = np.stack([x, y, np.roll(x, -1, 0), np.roll(y, -1, 0)])
    index = np.arange(n * k).reshape(n, k).T
    return lit_parts_of_edges(tri[:, :, 0].T, tri[:, :, 1].T, table, index)


def square(x0, y0, side):
    """A counter-clockwise square with lower-left corner (x0, y0)."""
    return np.array([[x0, y0], [x0 + side, y0], [x0 + side, y0 + side], [x0, y0 + side]])


def lit_centroid(parts):
    """Area and centroid of the triangle less some disjoint covered parts [(area, centroid)]."""
    area = 8.0 - sum(a for a, _ in parts)
    moment = 8.0 * np.array([4 / 3, 4 / 3]) - sum(a * np.asarray(c) for a, c in parts)
    return area / 8.0, moment / area


@pytest.mark.parametrize(
    "squares, covered",
    [
        # one wholly inside: its own area is covered
        ([(0.5, 0.5, 1.0)], [(1.0, (1.0, 1.0))]),
        # two apart: their intersection within the triangle is empty (its clipped polygon has
        # no area, and must add nothing, not an undefined centroid, to the covered moment)
        ([(0.25, 0.25, 1.0), (2.0, 0.25, 0.5)], [(1.0, (0.75, 0.75)), (0.25, (2.25, 0.5))]),
        # two overlapping, [0.5, 1.5]^2 and [1, 2] x [0.5, 1.5]: their union [0.5, 2] x
        # [0.5, 1.5], wholly inside the triangle (x + y <= 3.5 < 4)
        ([(0.5, 0.5, 1.0), (1.0, 0.5, 1.0)], [(1.5, (1.25, 1.0))]),
        # [3, 5] x [0, 2] meets the triangle in (3, 0), (4, 0), (3, 1): area 1/2, centroid
        # (10/3, 1/3); the other square lies beyond the hypotenuse and covers nothing
        ([(3.0, 0.0, 2.0), (3.0, 3.0, 1.0)], [(0.5, (10 / 3, 1 / 3))]),
    ],
    ids=["inside", "apart", "overlapping", "across-and-outside"],
)
def test_the_lit_part_is_the_triangle_less_the_union(squares, covered):
    fraction, centroid = lit_parts(TRIANGLE, [square(*sq) for sq in squares])
    want_f, want_c = lit_centroid(covered)
    assert fraction[0] == pytest.approx(want_f, rel=1e-14)
    np.testing.assert_allclose(centroid[0], want_c, rtol=1e-13)


def test_a_triangle_wholly_covered_or_wholly_clear():
    triangles = np.concatenate([TRIANGLE, TRIANGLE + 10.0])
    fraction, centroid = lit_parts(triangles, [square(-1.0, -1.0, 6.0)])
    assert fraction.tolist() == [0.0, 1.0]
    np.testing.assert_allclose(centroid[1], [10 + 4 / 3, 10 + 4 / 3], rtol=1e-14)
    assert np.isfinite(centroid).all()


def flat(points) -> bool:
    """Whether points (P, 2) span no area, by :func:`hull_edges`."""
    return bool(hull_edges(np.asarray(points, dtype=float)[None])[1][0])


def test_points_without_area_have_no_outline():
    assert flat([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]])


def test_each_triangle_with_its_own_polygons():
    # The four hand-worked cases above at once, each triangle with its own two polygons (a
    # (K, m, 2) array per slot): the same fractions and centroids as one at a time.
    cases = [
        ([(0.25, 0.25, 1.0), (2.0, 0.25, 0.5)], [(1.0, (0.75, 0.75)), (0.25, (2.25, 0.5))]),
        ([(0.5, 0.5, 1.0), (1.0, 0.5, 1.0)], [(1.5, (1.25, 1.0))]),
        ([(3.0, 0.0, 2.0), (3.0, 3.0, 1.0)], [(0.5, (10 / 3, 1 / 3))]),
        ([(5.0, 5.0, 1.0), (0.5, 0.5, 1.0)], [(1.0, (1.0, 1.0))]),
    ]
    triangles = np.concatenate([TRIANGLE] * len(cases))
    slots = [np.stack([square(*squares[k]) for squares, _ in cases]) for k in range(2)]
    fraction, centroid = lit_parts(triangles, slots)
    for i, (_, covered) in enumerate(cases):
        want_f, want_c = lit_centroid(covered)
        assert fraction[i] == pytest.approx(want_f, rel=1e-14)
        np.testing.assert_allclose(centroid[i], want_c, rtol=1e-13)


def test_triangles_crossing_different_numbers_of_a_polygons_edges_at_once():
    # A regular hexagon (circumradius 1, apothem a = sqrt(3)/2) and, in one batch, six narrow
    # triangles each poking through one of its sides (apex a depth h inside, base a height H
    # from the apex, half-width w there), one triangle clear of it and one holding it whole.
    # A poking triangle's covered part is the tip cut off by the side: area w h^2 / H, its
    # centroid on the axis 2h/3 from the apex; the holding triangle's is the hexagon.
    hexagon = np.array([[np.cos(t), np.sin(t)] for t in np.radians(np.arange(0, 360, 60))])
    a, h, H, w = np.sqrt(3) / 2, 0.2, 0.7, 0.25
    triangles, want = [], []
    for k in range(6):
        axis = np.array([np.cos(np.radians(60 * k + 30)), np.sin(np.radians(60 * k + 30))])
        side = np.array([-axis[1], axis[0]])
        apex = (a - h) * axis
        base = (a - h + H) * axis
        triangles.append([apex, base + w * side, base - w * side])
        area_t, area_c = w * H, w * h * h / H
        lit_at = (area_t * (a - h + 2 * H / 3) - area_c * (a - h + 2 * h / 3)) / (area_t - area_c)
        want.append((1 - area_c / area_t, lit_at * axis))
    triangles.append([[3.0, 3.0], [4.0, 3.0], [3.0, 4.0]])
    want.append((1.0, np.array([10 / 3, 10 / 3])))
    big = np.array([[-4.0, -2.0], [4.0, -2.0], [0.0, 4.0]])  # area 24, centroid (0, 0)
    triangles.append(big)
    want.append((1 - (3 * np.sqrt(3) / 2) / 24.0, np.zeros(2)))
    fraction, centroid = lit_parts(np.array(triangles), [hexagon])
    for i, (want_f, want_c) in enumerate(want):
        assert fraction[i] == pytest.approx(want_f, rel=1e-13)
        np.testing.assert_allclose(centroid[i], want_c, rtol=1e-12, atol=1e-13)


# A triangle with a corner on a corner of the polygon (found by a randomised search): rounding
# put the clipped polygon's corners on both sides of a side's line at once, one corner more
# than the clipping's buffer holds (IndexError).
CORNER_ON_CORNER = [
    (
        [
            [0.5116993974802456, -2.0265816501067624],
            [0.762952402851434, 0.92011438569096],
            [-0.8016963688648513, -0.5612326559391406],
        ],
        [
            [0.06453367409367051, 1.2216494303299912],
            [-0.19911269819847338, 1.3091781608950455],
            [0.5116993974802456, -2.0265816501067624],
            [0.5565965973569775, -1.3383666409920691],
        ],
    ),
    (
        [
            [-0.07831474578877105, -1.619071229323576],
            [1.0838756025936405, -0.6757849483597046],
            [-4.735056242210552, -0.8793363181464668],
        ],
        [
            [-0.7373577625720553, -1.0860347034352849],
            [-0.07831474578877105, -1.619071229323576],
            [-0.7190977859551962, -0.5320148935194625],
        ],
    ),
    (
        [
            [-0.029617179674001126, -0.5576471688015437],
            [-0.13028518185226234, -0.2959370149153701],
            [-6.086842383269245, -5.132119868826887],
        ],
        [
            [-0.9692993102092242, -0.9886436780224251],
            [-0.029617179674001126, -0.5576471688015437],
            [-0.8422392318341243, 0.555064007931584],
        ],
    ),
]


def exact_clip(polygon, outline):
    """The polygon clipped by the convex outline's sides, in exact rational arithmetic."""
    for a, b in zip(outline, outline[1:] + outline[:1]):
        side = [(b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]) for p in polygon]
        out = []
        for i, p in enumerate(polygon):
            j = (i + 1) % len(polygon)
            q, sp, sq = polygon[j], side[i], side[j]
            if sp * sq < 0:
                t = sp / (sp - sq)
                out.append((p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])))
            if sq >= 0:
                out.append(q)
        polygon = out
    return polygon


def exact_area(polygon):
    return (
        abs(sum(p[0] * q[1] - q[0] * p[1] for p, q in zip(polygon, polygon[1:] + polygon[:1]))) / 2
    )


@pytest.mark.parametrize("triangle, outline", CORNER_ON_CORNER)
def test_a_triangle_with_a_corner_on_the_polygons_corner(triangle, outline):
    exact = [[Fraction(x) for x in p] for p in triangle]
    corners = [[Fraction(x) for x in p] for p in outline]
    covered = exact_area(exact_clip(exact, corners))
    want = float(1 - covered / exact_area(exact))
    fraction, centroid = lit_parts(np.array([triangle]), [np.array(outline)])
    assert fraction[0] == pytest.approx(want, rel=1e-12, abs=1e-12)
    assert np.isfinite(centroid).all()


def covered(points) -> float:
    """The area of the polygon left of :func:`hull_edges`' edges of points (P, 2), within a
    right triangle around them."""
    table, _ = hull_edges(np.asarray(points, dtype=float)[None])
    table = np.concatenate([table, np.zeros((4, table.shape[1], 1))], axis=2)
    (x0, y0), (x1, y1) = points.min(axis=0) - 1.0, points.max(axis=0) + 1.0
    w, h = 2.0 * (x1 - x0), 2.0 * (y1 - y0)  # (its hypotenuse through (x1, y1))
    tx, ty = np.array([[x0], [x0 + w], [x0]]), np.array([[y0], [y0], [y0 + h]])
    fraction, _ = lit_parts_of_edges(tx, ty, table, np.zeros((1, 1), dtype=int))
    return (1.0 - fraction[0]) * w * h / 2.0


def test_outline_is_the_convex_hull_that_qhull_finds():
    # An independent reference: scipy's ConvexHull (Qhull) of the same points, on random
    # clouds and on points rounded to a grid (many collinear and repeated): the edges start at
    # its corners (and, on the grid, at points on its sides) and bound its area.
    rng = np.random.default_rng(7)
    clouds = [rng.normal(size=(rng.integers(3, 40), 2)) for _ in range(100)]
    grid = [np.round(rng.normal(size=(30, 2)), 1) for _ in range(50)]
    for points in clouds + grid:
        hull = ConvexHull(points)
        (ax, ay, _, _), _ = hull_edges(points[None])
        starts = set(zip(ax[:, 0].tolist(), ay[:, 0].tolist()))
        corners = {tuple(p) for p in points[hull.vertices].tolist()}
        assert corners <= starts
        if any(points is cloud for cloud in clouds):  # (no three on a line: the corners alone)
            assert starts == corners
        assert covered(points) == pytest.approx(hull.volume, rel=1e-12)


def test_outline_ignores_points_within_rounding_of_its_sides():
    # A box's corners and points on its sides off by a few ulp (as a plane's cuts through its
    # edges land), two corners an ulp apart in x: the box's area.
    x = 0.30064126278129333
    points = np.array(
        [
            [-0.3, -0.15],
            [np.nextafter(x, 1.0), -0.15],
            [x, 0.15],
            [-0.3, 0.15],
            [x, -0.0227],  # on the right side, an ulp left of the corner below it
            [0.0, 0.15 + 2e-17],  # on the top side, within rounding
            [-0.3, 0.0],  # on the left side
            [-0.3, -0.15],  # a corner again
        ]
    )
    assert not flat(points)
    assert covered(points) == pytest.approx((x + 0.3) * 0.3, rel=1e-12)


def test_an_edge_on_sliver_has_no_outline():
    # A plate seen edge-on within rounding: its outline spans no area (left to the rays).
    points = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1e-14], [0.0, 1e-14]])
    assert flat(points)
    assert not flat(points * [1.0, 1e6])  # 1e-8 thick: an outline


def test_points_that_are_not_finite_have_no_outline():
    square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    for bad in (np.nan, np.inf):
        assert flat([*square, [bad, 0.5]])
