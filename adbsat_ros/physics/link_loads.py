"""The loads of an articulated body's links and the efforts on its joints, from the facet rows and
the posed facet sums, computed when first read. Units: metres, body frame G; coefficients per
A_ref (forces) and A_ref L_ref (moments)."""

from __future__ import annotations

import functools

import numpy as np

from adbsat_ros.geometry.frames import cross
from adbsat_ros.physics.facets import N_SUMS


class EffortColumns:
    """The joints' effort terms as columns of the posed facet sums.

    Joint j (unit axis a through o): a . (M - o x F) if it turns, a . F if it slides; ``carries``
    (J, L): 1 where joint j carries evaluated link l; ``area`` A_ref [m^2], ``length`` L_ref [m].
    """

    def __init__(self, carries, prismatic, area: float, length: float):
        self.carries = np.asarray(carries, dtype=float)
        self.prismatic = np.asarray(prismatic, dtype=bool)
        self.scale = np.where(self.prismatic, 1.0 / area, 1.0 / (area * length))

    def per_joint(self, poses) -> list:
        """Each joint's ``(f, m)``: its effort of loads F, M (about G's origin) is f . F + m . M."""
        k = self.scale[:, None]
        axes = np.asarray(poses.joint_axes, dtype=float).reshape(-1, 3)
        origins = np.asarray(poses.joint_origins, dtype=float).reshape(-1, 3)
        slides = self.prismatic[:, None]
        f = np.where(slides, k * axes, -k * cross(axes, origins))
        m = np.where(slides, 0.0, k * axes)
        return [(tuple(fj), tuple(mj)) for fj, mj in zip(f.tolist(), m.tolist())]

    def matrix(self, poses) -> np.ndarray:
        """The (10, 4 J) matrix from a facet's posed sums to V = W f + m x Q, s = f . (W n) + m . (Q
        x n)."""
        rows = [[] for _ in range(N_SUMS)]
        for (fx, fy, fz), (mx, my, mz) in self.per_joint(poses):
            block = [(fx, fy, fz, 0.0), (0, 0, 0, fx), (0, 0, 0, fy), (0, 0, 0, fz)]
            block += [(0, mz, -my, 0), (-mz, 0, mx, 0), (my, -mx, 0, 0)]  # Q_k's part of m x Q
            block += [(0, 0, 0, mx), (0, 0, 0, my), (0, 0, 0, mz)]
            for row, values in zip(rows, block):
                row.extend(values)
        return np.array(rows, dtype=float)

    @staticmethod
    def efforts(rows: np.ndarray, columns: np.ndarray, u) -> np.ndarray:
        """Effort coefficients (J,) of (3, G) facet rows, (G, 4 J) posed columns, flow direction."""
        terms = (rows[:2] @ columns).reshape(2, -1, 4)
        return terms[0, :, :3] @ u + terms[1, :, 3]


class LinkLoads:
    """Every link's force and moment and every joint's effort coefficient, computed when first read.

    ``configuration.load_map`` (R, 7 E) takes the E evaluated links' ``loads`` to every output.
    """

    def __init__(self, configuration, forces, moments, efforts, n_links, loads=None, facets=None):
        if (loads is None) == (facets is None):
            raise ValueError("give exactly one of loads and facets")
        self.configuration = configuration
        self.forces, self.moments, self.efforts = forces, moments, efforts
        self.n_links = int(n_links)
        self._loads = loads
        self._facets = facets

    @functools.cached_property
    def values(self) -> tuple:
        """``(link_force, link_moment)``, (L, 3) each, body frame, about the moment point."""
        out = self._outputs
        return (
            out[self.forces].reshape(self.n_links, 3),
            out[self.moments].reshape(self.n_links, 3),
        )

    @functools.cached_property
    def effort_coefficients(self) -> np.ndarray:
        """The joints' effort coefficients (J,)."""
        if self._facets is not None:
            rows, sums, _, u = self._facets
            return EffortColumns.efforts(rows, sums.columns, u)
        return self._outputs[self.efforts]

    @functools.cached_property
    def _outputs(self) -> np.ndarray:
        """Every output of the load map from the evaluated links' loads."""
        loads = self._loads
        if loads is None:
            rows, sums, starts, u = self._facets
            weighted = sums.ten[:, :, None] * rows.T[:, None, :]  # (G, 10, 3)
            per_link = np.add.reduceat(weighted, starts, axis=0).reshape(len(starts), -1)
            loads = (per_link @ sums_to_loads(u)).ravel()
        return self.configuration.load_map @ loads


#: Loads of a link: force (3), moment about G's origin (3), lit projected area.
LINK_LOADS = 7


def sums_to_loads(u) -> np.ndarray:
    """The (30, 7) matrix from a link's weighted facet sums to F = (q W) u + (k W n),
    M = (q Q) x u + (k Q x n), S = max(c, 0) W."""
    ux, uy, uz = u.tolist()
    out = _SUMS_TO_LOADS.copy()
    # q W -> F: u; q Q -> M: (a x u) = a @ [[0, -uz, uy], [uz, 0, -ux], [-uy, ux, 0]]
    out.flat[_FLOW_ENTRIES] = (ux, uy, uz, -uz, uy, uz, -ux, -uy, ux)
    return out


_SUMS_TO_LOADS = np.zeros((3 * N_SUMS, LINK_LOADS))
_SUMS_TO_LOADS[[4, 7, 10], [0, 1, 2]] = 1.0  # k W n -> F
_SUMS_TO_LOADS[[22, 25, 28], [3, 4, 5]] = 1.0  # k Q x n -> M
_SUMS_TO_LOADS[2, 6] = 1.0  # max(c, 0) W -> S
_SUMS_TO_LOADS.setflags(write=False)
#: Where the flow direction's components go in it (flat indices, in the order set there).
_FLOW_ENTRIES = np.ravel_multi_index(
    ([0, 0, 0, 12, 12, 15, 15, 18, 18], [0, 1, 2, 4, 5, 3, 5, 3, 4]), _SUMS_TO_LOADS.shape
)
