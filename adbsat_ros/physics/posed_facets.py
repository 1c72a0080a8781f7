"""An articulated body's facets posed in the body frame: each link's facet rows (W, W n, Q, Q x n,
S) move with the link (rotation R, origin t; docs/physics.md, section 8),

    W' = W,  (W n)' = R (W n),  Q' = R Q + W t + S,  (Q x n)' = R (Q x n) + t x (W n)' + S x n'."""

from __future__ import annotations

import operator
from typing import NamedTuple

import numpy as np

from adbsat_ros.physics.facets import blend_sums, sum_columns, vector_sums
from adbsat_ros.physics.surface import SURFACE_PARAMETERS, PanelSurface
from adbsat_ros.shading.lighting import LightingBlend


class Posing(NamedTuple):
    """Posing at one configuration: ``normals`` (G, 3) in G, ``matrix`` (G, 13, 10) per facet, and
    ``efforts`` (G, 13, 4 J) to the joints' effort columns (None without joints)."""

    normals: np.ndarray
    inward_T: np.ndarray
    matrix: np.ndarray
    efforts: np.ndarray | None


class PosedSums:
    """A lighting's link rows (G, 13) posed at a configuration: ``ten`` (G, 10) and the joints'
    effort :attr:`columns` (G, 4 J), made when first read (posing is linear: a blend's rows
    posed are the blend of its parts' posed rows)."""

    __slots__ = ("ten", "_rows", "_efforts", "_columns")

    def __init__(self, rows: np.ndarray, posing: Posing):
        self.ten = _posed(rows, posing.matrix)
        self._rows, self._efforts, self._columns = rows, posing.efforts, None

    @property
    def columns(self) -> np.ndarray | None:
        """The joints' effort columns (G, 4 J) (:class:`~.link_loads.EffortColumns`), or None."""
        if self._columns is None and self._efforts is not None:
            self._columns = _posed(self._rows, self._efforts)
        return self._columns


def _posed(rows: np.ndarray, matrices: np.ndarray) -> np.ndarray:
    """Each facet's rows (G, 13) through its matrix (G, 13, K): (G, K), read-only."""
    out = np.matmul(rows[:, None, :], matrices)[:, 0, :]
    out.setflags(write=False)
    return out


#: The Levi-Civita symbol: the matrix [v]x of the cross product with v is -(EPSILON . v)
#: (``-np.einsum("ijk,k->ij", EPSILON, v)``), and its transpose EPSILON . v.
EPSILON = np.zeros((3, 3, 3))
EPSILON[[0, 1, 2], [1, 2, 0], [2, 0, 1]] = 1.0
EPSILON[[0, 1, 2], [2, 0, 1], [1, 2, 0]] = -1.0


class PosedFacets:
    """The facets of every link of an articulated body, posed per configuration (:meth:`of`).
    ``spans``: each link's panels [start, stop) in the posed body; ``panel_index`` (N,): facets."""

    def __init__(self, link_facets, link_index, spans, joints=None, link_surfaces=None):
        self._facets = list(link_facets)
        self._joints = joints
        self._link_index = np.asarray(link_index)
        self._spans = [(int(a), int(b)) for a, b in spans]
        counts = [f.n for f in self._facets]
        self.n = int(sum(counts))
        if min(counts) < 1:
            raise ValueError("every link needs at least one facet")
        self.starts = np.cumsum([0, *counts[:-1]])
        self._all_lit = np.concatenate([f.all_lit for f in self._facets])
        self._link_of_facet = np.repeat(np.arange(len(counts)), counts)  # (evaluated links)
        self._facet_link = self._link_index[self._link_of_facet]  # (the body's links)
        # the posing matrices' entries that no configuration changes (:meth:`posing`)
        self._posing_constants = np.zeros((self.n, 13, 10))
        self._posing_constants[:, 0, 0] = 1.0  # W' = W
        self._posing_constants[:, 10:13, 4:7] = np.eye(3)  # Q' = ... + S
        if joints is not None:  # each joint's four effort columns, where it carries the facet
            self._carried = np.repeat(joints.carries[:, self._link_of_facet].T, 4, axis=1)
        self.panel_index = np.concatenate(
            [f.index + start for f, start in zip(self._facets, self.starts)]
        )
        # every link's panels, link after link, to sum a lighting over all links in one pass
        self._panels = np.concatenate([np.arange(a, b) for a, b in self._spans])
        self._row_of_panel = np.full(max(b for _, b in self._spans), -1)
        self._row_of_panel[self._panels] = np.arange(self._panels.size)
        self._areas = np.concatenate([f.mesh.areas for f in self._facets])
        self._weighted_barycentres = np.concatenate([f.weighted_barycentres for f in self._facets])
        self._normals = np.concatenate([f.normals for f in self._facets])
        self._own = None  # (the links' own values by parameter, the facets' surface of them)
        if link_surfaces is not None:
            own = self._surface_of_links(link_surfaces)
            if own is not None:
                values = {n: [getattr(x, n) for x in link_surfaces] for n in SURFACE_PARAMETERS}
                self._own = (values, own)

    @classmethod
    def of(cls, link_methods, link_index, spans, joints=None) -> "PosedFacets | None":
        """The posed facets of the links' panel methods, or None if a link has no facets."""
        if any(m.facets is None for m in link_methods):
            return None
        return cls(
            [m.facets for m in link_methods],
            link_index,
            spans,
            joints,
            link_surfaces=[m.surface for m in link_methods],
        )

    def surface(self, link_surfaces) -> PanelSurface | None:
        """The facets' surface of the links' per-panel surfaces; None if one varies in a facet."""
        if self._own is not None:
            own_values, own = self._own
            values = {}
            for name in SURFACE_PARAMETERS:
                link_values = [getattr(x, name) for x in link_surfaces]
                first = link_values[0]
                if all(map(operator.is_, link_values, own_values[name])):
                    values[name] = getattr(own, name)
                elif type(first) is float and all(
                    type(v) is float and v == first for v in link_values
                ):
                    values[name] = first
                else:
                    break
            else:
                return PanelSurface(**values)
        return self._surface_of_links(link_surfaces)

    def _surface_of_links(self, link_surfaces) -> PanelSurface | None:
        parts = [f.surface_of(s) for f, s in zip(self._facets, link_surfaces)]
        if any(p is None for p in parts):
            return None
        values = {}
        for name in SURFACE_PARAMETERS:
            link_values = [getattr(p, name) for p in parts]
            if all(np.ndim(v) == 0 for v in link_values) and len(set(link_values)) == 1:
                values[name] = float(link_values[0])
            else:
                values[name] = np.concatenate(
                    [np.broadcast_to(v, (f.n,)) for v, f in zip(link_values, self._facets)]
                )
        return PanelSurface(**values)

    def posing(self, poses) -> Posing:
        """The :class:`Posing` of the facets at ``poses`` (module docstring's formulas)."""
        turned = poses.rotations[self._facet_link].transpose(0, 2, 1)  # (R v)^T = v^T R^T
        origins = poses.origins[self._facet_link]
        normals = np.einsum("gji,gj->gi", turned, self._normals)
        matrix = self._posing_constants.copy()  # W' = W, Q' = ... + S
        matrix[:, 1:4, 1:4] = turned  # (W n)' = R (W n)
        matrix[:, 4:7, 4:7] = turned  # Q' = R Q + W t + S
        matrix[:, 0, 4:7] = origins
        matrix[:, 7:10, 7:10] = turned  # (Q x n)' = R (Q x n) + t x R (W n) + S x n'
        t_cross_T = np.einsum("jlk,gk->gjl", EPSILON, origins)  # [t]x^T
        matrix[:, 1:4, 7:10] = np.einsum("gij,gjl->gil", turned, t_cross_T)
        matrix[:, 10:13, 7:10] = -np.einsum("ijk,gk->gij", EPSILON, normals)
        efforts = None
        if self._joints is not None:  # the effort columns of the posed sums, where carried
            efforts = (matrix.reshape(-1, 10) @ self._joints.matrix(poses)).reshape(self.n, 13, -1)
            efforts *= self._carried[:, None, :]
            efforts.setflags(write=False)
        inward_T = np.ascontiguousarray(-normals.T)
        for a in (normals, inward_T, matrix):
            a.setflags(write=False)
        return Posing(normals, inward_T, matrix, efforts)

    def link_rows(self, lighting) -> np.ndarray:
        """Read-only rows (G, 13) of ``lighting`` (None: lit): link-frame and shift sums S (G)."""
        rows = np.zeros((self.n, 13))
        if lighting is None:
            rows[:, :10] = self._all_lit
        else:  # (every link at once: each facet's panels summed in their order)
            lit = lighting.lit_fraction[self._panels]
            index, n = self.panel_index, self.n
            moments = vector_sums(index, lit[:, None] * self._weighted_barycentres, n)
            rows[:, :10] = sum_columns(
                np.bincount(index, self._areas * lit, minlength=n), moments, self._normals
            )
            if lighting.shift_index.size:
                panels = self._row_of_panel[lighting.shift_index]
                inside = panels >= 0
                panels = panels[inside]
                shift = (self._areas[panels] * lit[panels])[:, None] * lighting.shift[inside]
                rows[:, 10:] = vector_sums(index[panels], shift, n)
        rows.setflags(write=False)
        return rows

    def sums(self, lighting, configuration) -> PosedSums:
        """The link rows of ``lighting`` (a blend, or None: all lit), blended, posed at
        ``configuration``."""
        if isinstance(lighting, LightingBlend):
            rows = blend_sums([(w, self.link_rows(part)) for w, part in lighting.parts])
        else:
            rows = self.link_rows(lighting)
        return PosedSums(rows, configuration.posing)
