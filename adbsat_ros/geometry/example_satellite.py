"""The bundled example satellite ``example``: a 1.2 m x 0.5 m x 0.5 m box, two 1.0 m x 0.5 m x
0.03 m wings off +-y at the rear (edge-on at zero angles); materials ``body``, ``solar_array``.
"""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.geometry.shapes import combine

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


def write_obj(mesh: PanelMesh, path, digits: int = 9) -> None:
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
