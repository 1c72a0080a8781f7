"""ADBSat's shading (``shadowAnaly``), vectorised: a forward panel is in shadow, all or nothing, if
its barycentre, projected along the flow, falls inside an upstream back face (docs/physics.md,
section 6). Units: metres, mesh frame G."""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.shading.flow_plane import MAX_PAIRS, grid_pairs

# ADBSat's thresholds (physics.md section 6).
ADBSAT_BACKWARD_DEG = 90.0001
ADBSAT_AXIAL_TOL = 1e-4
ADBSAT_DOWNSTREAM_TOL = 1e-5


def adbsat_shadowed(mesh: PanelMesh, u_G, max_pairs: int = MAX_PAIRS) -> np.ndarray:
    """Panels ADBSat's ``shadowAnaly`` marks as shadowed, (N,) bool, for gas-flow direction ``u_G``
    (G).

    max_pairs: most (forward, backward) candidate pairs held at once.
    """
    u = frames.unit_vector(u_G)
    n = mesh.n_panels
    shadowed = np.zeros(n, dtype=bool)
    if mesh.report.convex:
        return shadowed
    aoa, aos = frames.angles_of_flow(u)
    L = frames.mesh_to_wind(float(aoa), float(aos))  # G -> W, x_W upstream
    vw = mesh.vertices @ L.T  # (N, 3, 3) in W
    bw = mesh.barycentres @ L.T
    c = -(mesh.normals @ u)
    delta = np.degrees(np.arccos(np.clip(c, -1.0, 1.0)))
    back = delta > ADBSAT_BACKWARD_DEG
    front = ~back
    if not back.any() or not front.any():
        return shadowed
    xmin = vw[:, :, 0].min(axis=1)
    xmax = vw[:, :, 0].max(axis=1)
    f_idx = np.flatnonzero(front & (xmin < xmin[back].max() + ADBSAT_AXIAL_TOL))
    b_idx = np.flatnonzero(back & (xmax > xmin[front].min() + ADBSAT_AXIAL_TOL))
    if f_idx.size == 0 or b_idx.size == 0:
        return shadowed

    B = vw[b_idx]  # (nB, 3, 3)
    ymin, ymax = B[:, :, 1].min(axis=1), B[:, :, 1].max(axis=1)
    zmin, zmax = B[:, :, 2].min(axis=1), B[:, :, 2].max(axis=1)
    A_ = B[:, 0, 1:]
    v0 = B[:, 2, 1:] - A_  # C - A
    v1 = B[:, 1, 1:] - A_  # B - A
    dot00 = np.einsum("ij,ij->i", v0, v0)
    dot01 = np.einsum("ij,ij->i", v0, v1)
    dot11 = np.einsum("ij,ij->i", v1, v1)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv_den = 1.0 / (dot00 * dot11 - dot01 * dot01)
    nB = mesh.normals[b_idx]
    aB = mesh.vertices[b_idx, 0, :]
    fy, fz = bw[f_idx, 1], bw[f_idx, 2]
    bmin = np.stack([ymin, zmin], axis=1)
    bmax = np.stack([ymax, zmax], axis=1)
    for fi, bi in grid_pairs(fy, fz, bmin, bmax, max_pairs):
        y, z = fy[fi], fz[fi]
        # "not all strictly one sign" in y and in z after translating by the barycentre
        keep = (ymin[bi] <= y) & (y <= ymax[bi]) & (zmin[bi] <= z) & (z <= zmax[bi])
        fi, bi = fi[keep], bi[keep]
        if fi.size == 0:
            continue
        v2 = np.stack([fy[fi], fz[fi]], axis=1) - A_[bi]
        dot02 = np.einsum("ij,ij->i", v0[bi], v2)
        dot12 = np.einsum("ij,ij->i", v1[bi], v2)
        with np.errstate(invalid="ignore"):
            uu = (dot11[bi] * dot02 - dot01[bi] * dot12) * inv_den[bi]
            vv = (dot00[bi] * dot12 - dot01[bi] * dot02) * inv_den[bi]
            inside = (uu >= 0.0) & (vv >= 0.0) & (uu + vv < 1.0)
        fi, bi = fi[inside], bi[inside]
        f = f_idx[fi]
        down = np.einsum("ij,ij->i", nB[bi], mesh.barycentres[f] - aB[bi]) > ADBSAT_DOWNSTREAM_TOL
        shadowed[f[down]] = True
    return shadowed
