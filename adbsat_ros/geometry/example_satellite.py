"""The bundled example satellite ``example``: a 1.2 m x 0.5 m x 0.5 m box, two 1.0 m x 0.5 m x
0.03 m wings off +-y at the rear (edge-on at zero angles); materials ``body``, ``solar_array``.
"""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry.mesh import PanelMesh, panels_from_arrays

#: Name that stands for this mesh wherever a mesh file is expected.
EXAMPLE_MESH_NAME = "example"

BODY_SIZE = (1.2, 0.5, 0.5)
WING_SIZE = (0.5, 1.0, 0.03)
WING_GAP = 0.05
WING_X_CENTRE = -0.3


def _refined_box(extents, centre, max_edge):
    """Vertices and faces [m] of a box of ``extents`` at ``centre``, edges <= ``max_edge``."""
    import trimesh  # (when a body is built: not at start-up, docs/benchmarks.md)

    box = trimesh.creation.box(extents=extents)
    vertices, faces = trimesh.remesh.subdivide_to_size(box.vertices, box.faces, max_edge=max_edge)
    return np.asarray(vertices) + np.asarray(centre), np.asarray(faces)


def example_satellite(max_edge: float = 0.09) -> PanelMesh:
    """The example satellite, metres, mesh frame = body frame.

    ``max_edge``: longest triangle edge [m]; 0.09 m gives about 5,000 panels.
    """
    parts = [
        ("body", _refined_box(BODY_SIZE, (0.0, 0.0, 0.0), max_edge)),
    ]
    y_wing = BODY_SIZE[1] / 2 + WING_GAP + WING_SIZE[1] / 2
    for sign in (1.0, -1.0):
        parts.append(
            ("solar_array", _refined_box(WING_SIZE, (WING_X_CENTRE, sign * y_wing, 0.0), max_edge))
        )
    return combine(
        [part for _, part in parts],
        source="example satellite (body + two solar wings)",
        part_materials=[name for name, _ in parts],
        material_names=["body", "solar_array"],
    )


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
