"""Scenes and exact references shared by the shading tests.

"cube + plate": a 1 m cube centred at x = +2 m and a 3 x 3 x 0.1 m plate centred at the origin
with its large faces normal to x (front face at x = +0.05 m). Flow at aoa = aos = 0 moves along
-x, so the cube is upstream and throws its shadow on the plate.
"""

from __future__ import annotations

import math

import numpy as np
from meshes import grid_box

from adbsat_ros import FreeStream
from adbsat_ros.geometry.example_satellite import combine as join_parts
from adbsat_ros.geometry.mesh import panels_from_arrays


def combine(*parts, source="scene"):
    return join_parts(parts, source=source)


def cube_plate(plate_div=25, cube_div=2):
    """Cube 1 m at x = +2, plate 3 x 3 x 0.1 m at x = 0 (front face x = +0.05)."""
    return combine(
        grid_box((2.0, 0.0, 0.0), (1.0, 1.0, 1.0), (cube_div,) * 3),
        grid_box((0.0, 0.0, 0.0), (0.1, 3.0, 3.0), (1, plate_div, plate_div)),
        source="cube+plate",
    )


def satellite(k=3):
    """Box bus with two thin wings behind it, partly in its shadow for oblique flows."""
    return combine(
        grid_box((0, 0, 0), (1.5, 1, 1), (3 * k, 2 * k, 2 * k)),
        grid_box((-1.2, 1.8, 0), (0.02, 3.0, 0.6), (1, 6 * k, k)),
        grid_box((-1.2, -1.8, 0), (0.02, 3.0, 0.6), (1, 6 * k, k)),
        source="satellite",
    )


def box_with_fin():
    """A 1 m box and a thin fin (1.5 x 0.6 x 0.02 m) in its wake, in the plane z = 0."""
    return combine(
        grid_box((0, 0, 0), (1, 1, 1), (2, 2, 2)),
        grid_box((-1.25, 0, 0), (1.5, 0.6, 0.02), (6, 3, 1)),
        source="box+fin",
    )


def dented_box():
    """One closed, non-convex body: a box whose +x face has a funnel-shaped pit 0.6 m deep."""
    v, f = grid_box((0, 0, 0), (1, 2, 2), (2, 10, 10))
    # push the 7 x 7 inner vertices of the +x face (x = 0.5, |y|, |z| <= 0.6) to x = -0.1
    inner = (np.isclose(v[:, 0], 0.5)) & (np.abs(v[:, 1]) < 0.7) & (np.abs(v[:, 2]) < 0.7)
    v = v.copy()
    v[inner, 0] = -0.1
    return panels_from_arrays(v, f, source="dented box")


FLOW = FreeStream(7700.0, 900.0, mean_mass_amu=16.0)


def front_plate_panels(mesh):
    return np.flatnonzero(
        (mesh.normals[:, 0] > 0.99) & (np.abs(mesh.barycentres[:, 0] - 0.05) < 1e-9)
    )


# ------------------------------------------------------------------------------ exact reference
def _clip(poly, axis, val, keep_less):
    out = []
    for i in range(len(poly)):
        p, q = poly[i], poly[(i + 1) % len(poly)]
        pin = p[axis] <= val if keep_less else p[axis] >= val
        qin = q[axis] <= val if keep_less else q[axis] >= val
        if pin:
            out.append(p)
        if pin != qin:
            out.append(p + (val - p[axis]) / (q[axis] - p[axis]) * (q - p))
    return out


def _area_centroid(poly):
    if len(poly) < 3:
        return 0.0, None
    P = np.array(poly)
    x, y = P[:, 0], P[:, 1]
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    cr = x * y1 - x1 * y
    a = cr.sum() / 2
    if abs(a) < 1e-15:
        return 0.0, None
    return abs(a), np.array([((x + x1) * cr).sum(), ((y + y1) * cr).sum()]) / (6 * a)


def exact_plate_lighting(mesh, aoa):
    """Exact lit fraction and lit centroid (y, z) of each plate front panel at sideslip 0.

    The cube's shadow on the plane x = 0.05 along u = (-cos a, 0, sin a): a cube point q lands
    at z' = q_z + (q_x - 0.05) tan a, y' = q_y, so the shadow is the rectangle
    |y| <= 0.5, -0.5 + 1.45 tan a <= z <= 0.5 + 2.45 tan a (height 1 + tan a).
    """
    t = math.tan(aoa)
    box = (-0.5, 0.5, -0.5 + 1.45 * t, 0.5 + 2.45 * t)
    frac, cen = {}, {}
    for i in front_plate_panels(mesh):
        tri = [np.array(p, float) for p in mesh.vertices[i][:, 1:]]
        a_tri, c_tri = _area_centroid(tri)
        poly = tri
        for axis, val, keep_less in [
            (0, box[0], False),
            (0, box[1], True),
            (1, box[2], False),
            (1, box[3], True),
        ]:
            poly = _clip(poly, axis, val, keep_less)
            if not poly:
                break
        a_sh, c_sh = _area_centroid(poly) if poly else (0.0, None)
        frac[i] = 1.0 - a_sh / a_tri
        cen[i] = (
            c_tri
            if a_sh == 0
            else ((a_tri * c_tri - a_sh * c_sh) / (a_tri - a_sh) if a_tri > a_sh else None)
        )
    return frac, cen
