"""Meshes the tests build and write: boxes of regular face grids, OBJ files with materials."""

from __future__ import annotations

import numpy as np


def grid_box(center, size, divisions):
    """Vertices [m] and outward faces of a closed box of ``size`` [m] at ``center``, gridded."""
    center = np.asarray(center, float)
    size = np.asarray(size, float)
    verts, faces, off = [], [], 0
    for axis in range(3):
        a1, a2 = (axis + 1) % 3, (axis + 2) % 3
        n1, n2 = divisions[a1], divisions[a2]
        g1, g2 = np.meshgrid(
            np.linspace(-0.5, 0.5, n1 + 1) * size[a1],
            np.linspace(-0.5, 0.5, n2 + 1) * size[a2],
            indexing="ij",
        )
        for sign in (1.0, -1.0):
            p = np.zeros((n1 + 1, n2 + 1, 3))
            p[..., axis] = sign * 0.5 * size[axis]
            p[..., a1], p[..., a2] = g1, g2
            verts.append(p.reshape(-1, 3) + center)
            idx = np.arange((n1 + 1) * (n2 + 1)).reshape(n1 + 1, n2 + 1) + off
            q00, q10, q11, q01 = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
            f = np.concatenate(
                [
                    np.stack([q00, q10, q11], -1).reshape(-1, 3),
                    np.stack([q00, q11, q01], -1).reshape(-1, 3),
                ]
            )
            faces.append(f if sign > 0 else f[:, ::-1])
            off += (n1 + 1) * (n2 + 1)
    return np.concatenate(verts), np.concatenate(faces)


def write_obj(mesh, path, digits: int = 9) -> None:
    """Write a PanelMesh as OBJ with ``usemtl`` groups and ``digits`` (1 to 17) significant digits.

    17 reads back the same panels; fewer can tilt a flat face's panels out of one facet.
    """
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(f"# {mesh.source}\n# {mesh.n_panels} triangles, units: metres\n")
        for v in mesh.vertices.reshape(-1, 3):
            fh.write(f"v {v[0]:.{digits}g} {v[1]:.{digits}g} {v[2]:.{digits}g}\n")
        current = None
        for i, m in enumerate(mesh.material_index):
            if m != current:
                fh.write(f"usemtl {mesh.material_names[m]}\n")
                current = m
            fh.write(f"f {3 * i + 1} {3 * i + 2} {3 * i + 3}\n")
