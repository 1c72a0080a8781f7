"""Bundled concave bodies (test-particle cases): closed, metres, frame G, gas from +x at zero.

``grooved-cylinder``: r 0.5 m, length 1 m, axis x, four grooves 0.05 m wide, 0.4 m deep in its
front, ADBSat's validation case (Sinpetru et al., Computer Physics Communications 275 (2022)
108327); ``cylinder`` without; ``intake-box``: 2 x 1 x 1 m, a 0.6 x 0.6 m intake 1.5 m deep.
"""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry.mesh import PanelMesh, panels_from_arrays

RADIUS = 0.5
LENGTH = 1.0
#: (inner, outer) radius [m] of each groove of ``grooved-cylinder``.
GROOVES = ((0.10, 0.15), (0.20, 0.25), (0.30, 0.35), (0.40, 0.45))
GROOVE_DEPTH = 0.4
#: Sections around the cylinders' axis.
SECTIONS = 96


def _revolved(profile, source: str) -> PanelMesh:
    """The closed body of revolution of a (radius, height) profile, axis x, centred."""
    import trimesh  # (when a body is built: not at start-up, docs/benchmarks.md)

    tm = trimesh.creation.revolve(np.asarray(profile, dtype=float), sections=SECTIONS)
    tm.merge_vertices()
    turn = trimesh.transformations.rotation_matrix(np.pi / 2.0, [0.0, 1.0, 0.0])  # z -> x
    tm.apply_transform(turn)
    tm.apply_translation([-0.5 * LENGTH, 0.0, 0.0])
    return panels_from_arrays(tm.vertices, tm.faces, source=source)


def grooved_cylinder() -> PanelMesh:
    """The cylinder with four deep annular grooves in its front face (module docstring)."""
    profile = [(0.0, 0.0), (RADIUS, 0.0), (RADIUS, LENGTH)]
    for inner, outer in reversed(GROOVES):
        profile += [
            (outer, LENGTH),
            (outer, LENGTH - GROOVE_DEPTH),
            (inner, LENGTH - GROOVE_DEPTH),
            (inner, LENGTH),
        ]
    profile.append((0.0, LENGTH))
    return _revolved(profile, "grooved-cylinder")


def plain_cylinder() -> PanelMesh:
    """The same cylinder without grooves."""
    return _revolved([(0.0, 0.0), (RADIUS, 0.0), (RADIUS, LENGTH), (0.0, LENGTH)], "cylinder")


def _grid(corner, e1, e2, n1, n2, normal):
    """Rectangle corner + [0, 1] e1 + [0, 1] e2 as n1 x n2 cells of triangles facing ``normal``."""
    corner, e1, e2 = (np.asarray(v, dtype=float) for v in (corner, e1, e2))
    if np.dot(np.cross(e1, e2), normal) < 0.0:
        e1, e2, n1, n2 = e2, e1, n2, n1
    a, b = np.meshgrid(np.linspace(0.0, 1.0, n1 + 1), np.linspace(0.0, 1.0, n2 + 1), indexing="ij")
    vertices = corner + a.reshape(-1, 1) * e1 + b.reshape(-1, 1) * e2
    i, j = np.meshgrid(np.arange(n1), np.arange(n2), indexing="ij")
    v00 = (i * (n2 + 1) + j).ravel()
    v10, v01 = v00 + n2 + 1, v00 + 1
    v11 = v10 + 1
    faces = np.vstack([np.column_stack([v00, v10, v11]), np.column_stack([v00, v11, v01])])
    return vertices, faces


def intake_box(cell: float = 0.1) -> PanelMesh:
    """The box with a deep blind intake (module docstring), faces as grids of ``cell`` [m]."""
    import trimesh  # (when a body is built: not at start-up, docs/benchmarks.md)

    x0, x1, half, inner, bottom = -1.0, 1.0, 0.5, 0.3, -0.5

    def n(length):
        return max(1, round(length / cell))

    ex, ey, ez = np.eye(3)
    rects = [
        ((x0, -half, -half), 2 * half * ey, 2 * half * ez, -ex),  # back
        ((x0, -half, -half), (x1 - x0) * ex, 2 * half * ez, -ey),  # outer sides
        ((x0, half, -half), (x1 - x0) * ex, 2 * half * ez, ey),
        ((x0, -half, -half), (x1 - x0) * ex, 2 * half * ey, -ez),
        ((x0, -half, half), (x1 - x0) * ex, 2 * half * ey, ez),
        ((x1, -half, inner), 2 * half * ey, (half - inner) * ez, ex),  # front ring
        ((x1, -half, -half), 2 * half * ey, (half - inner) * ez, ex),
        ((x1, -half, -inner), (half - inner) * ey, 2 * inner * ez, ex),
        ((x1, inner, -inner), (half - inner) * ey, 2 * inner * ez, ex),
        ((bottom, -inner, -inner), (x1 - bottom) * ex, 2 * inner * ez, ey),  # intake walls
        ((bottom, inner, -inner), (x1 - bottom) * ex, 2 * inner * ez, -ey),
        ((bottom, -inner, -inner), (x1 - bottom) * ex, 2 * inner * ey, ez),
        ((bottom, -inner, inner), (x1 - bottom) * ex, 2 * inner * ey, -ez),
        ((bottom, -inner, -inner), 2 * inner * ey, 2 * inner * ez, ex),  # intake bottom
    ]
    vertices, faces, offset = [], [], 0
    for corner, e1, e2, normal in rects:
        v, f = _grid(corner, e1, e2, n(np.linalg.norm(e1)), n(np.linalg.norm(e2)), normal)
        vertices.append(v)
        faces.append(f + offset)
        offset += len(v)
    tm = trimesh.Trimesh(np.vstack(vertices), np.vstack(faces), process=False)
    tm.merge_vertices()
    return panels_from_arrays(tm.vertices, tm.faces, source="intake-box")


#: The bundled concave bodies by name.
CONCAVE_BODIES = {
    "grooved-cylinder": grooved_cylinder,
    "cylinder": plain_cylinder,
    "intake-box": intake_box,
}
