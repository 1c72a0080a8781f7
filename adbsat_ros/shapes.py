"""Closed shapes with regular face grids, for validation scenes (cube before a plate, fins, pits).

Used by the shading tests and benchmarks; handy to build simple satellites by code.
"""

from __future__ import annotations

import numpy as np


def grid_box(center, size, divisions):
    """Vertices and faces of a closed box whose faces are regular grids (outward winding).

    Parameters
    ----------
    center : array_like, shape (3,)
        Box centre [m].
    size : array_like, shape (3,)
        Edge lengths along x, y, z [m].
    divisions : sequence of 3 int
        Grid cells along x, y, z; each cell is two triangles.

    Returns
    -------
    vertices : ndarray, shape (V, 3)
    faces : ndarray of int, shape (F, 3)
    """
    center = np.asarray(center, float)
    size = np.asarray(size, float)
    verts, faces, off = [], [], 0
    for axis in range(3):
        a1, a2 = (axis + 1) % 3, (axis + 2) % 3
        n1, n2 = divisions[a1], divisions[a2]
        g1, g2 = np.meshgrid(
            np.linspace(-0.5, 0.5, n1 + 1) * size[a1], np.linspace(-0.5, 0.5, n2 + 1) * size[a2], indexing="ij"
        )
        for sign in (1.0, -1.0):
            p = np.zeros((n1 + 1, n2 + 1, 3))
            p[..., axis] = sign * 0.5 * size[axis]
            p[..., a1], p[..., a2] = g1, g2
            verts.append(p.reshape(-1, 3) + center)
            idx = np.arange((n1 + 1) * (n2 + 1)).reshape(n1 + 1, n2 + 1) + off
            q00, q10, q11, q01 = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
            f = np.concatenate([np.stack([q00, q10, q11], -1).reshape(-1, 3), np.stack([q00, q11, q01], -1).reshape(-1, 3)])
            faces.append(f if sign > 0 else f[:, ::-1])
            off += (n1 + 1) * (n2 + 1)
    return np.concatenate(verts), np.concatenate(faces)
