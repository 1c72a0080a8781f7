"""Boxes of regular face grids, and parts joined into one checked mesh [m, frame G]."""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry.mesh import PanelMesh, panels_from_arrays


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


def combine(parts, source: str = "scene", part_materials=None, material_names=None) -> PanelMesh:
    """One checked PanelMesh of (vertices [m], faces) ``parts``, with their materials."""
    parts = list(parts)
    if part_materials is None:
        part_materials = ["default"] * len(parts)
    names = (
        list(material_names) if material_names is not None else list(dict.fromkeys(part_materials))
    )
    vertices, faces, material = [], [], []
    offset = 0
    for (v, f), name in zip(parts, part_materials):
        vertices.append(np.asarray(v, dtype=float))
        faces.append(np.asarray(f) + offset)
        material.append(np.full(len(f), names.index(name)))
        offset += len(v)
    return panels_from_arrays(
        np.vstack(vertices), np.vstack(faces), np.concatenate(material), names, source=source
    )
