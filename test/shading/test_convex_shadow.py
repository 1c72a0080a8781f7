"""The exact shadows of convex parts: the triangles' lit parts against convex polygons, against
areas and centroids worked out by hand."""

from __future__ import annotations

import numpy as np
import pytest

from adbsat_ros.shading.convex_shadow import convex_outline, lit_parts

#: A right triangle with legs 4 along x and y: area 8, centroid (4/3, 4/3).
TRIANGLE = np.array([[[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]]])


def square(x0, y0, side):
    """A counter-clockwise square with lower-left corner (x0, y0)."""
    corners = np.array([[x0, y0], [x0 + side, y0], [x0 + side, y0 + side], [x0, y0 + side]])
    outline = convex_outline(corners)
    assert outline is not None
    return outline


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


def test_points_without_area_have_no_outline():
    assert convex_outline(np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]])) is None


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
    hexagon = convex_outline(
        np.array([[np.cos(t), np.sin(t)] for t in np.radians(np.arange(0, 360, 60))])
    )
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
