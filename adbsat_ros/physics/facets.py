"""Coplanar panels of one material grouped into facets: the gas-surface model runs once per facet.

The sums regroup exactly: sum_i f_i A_i phi_i = W_g phi_g with W_g = sum f_i A_i, and the moments
with Q_g = sum f_i A_i r_i; docs/physics.md, section 1. Units: m, m^2, mesh frame G.
"""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry.frames import cross
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.physics.surface import SURFACE_PARAMETERS, PanelSurface
from adbsat_ros.shading.lighting import LightingBlend, PanelLighting

#: Columns of the facet sums: W, W n (3), Q (3), Q x n (3).
N_SUMS = 10


def facet_rows(c, cp, shear) -> np.ndarray:
    """The (3, G) rows q = c_tau / sin(delta), k = q c - c_p and max(c, 0) of facets."""
    rows = np.empty((3, c.size))
    rows[0] = shear
    np.multiply(shear, c, out=rows[1])
    rows[1] -= cp
    np.maximum(c, 0.0, out=rows[2])
    return rows


def shear_per_sine(ctau, sigma) -> np.ndarray:
    """c_tau / sin(delta), 0 where sin(delta) = 0 (there every model's c_tau is 0)."""
    return np.divide(ctau, sigma, out=np.zeros_like(ctau), where=sigma > 0.0)


def vector_sums(index, vectors, n: int) -> np.ndarray:
    """The (n, 3) sums of the rows of ``vectors`` (K, 3) by facet ``index`` (K,), in order."""
    return np.stack(
        [np.bincount(index, weights=vectors[:, k], minlength=n) for k in range(3)], axis=-1
    )


def sum_columns(weights, moments, normals) -> np.ndarray:
    """Columns W, W n, Q, Q x n (shape (G, 10)) of weights W (G,), moments Q (G, 3), normals n."""
    return np.column_stack([weights, weights[:, None] * normals, moments, cross(moments, normals)])


def blend_sums(parts) -> np.ndarray:
    """The weighted sum of a blend's (G, 10) sums, ``parts`` [(w, sums), ...], in part order."""
    (w, first), *rest = parts
    sums = w * first
    for w, part in rest:
        sums += w * part
    return sums


class Facets:
    """Coplanar panels of one material grouped into facets.

    index: facet of every panel, (N,); first: one member panel of every facet, (G,).
    all_lit: facet sums with every panel lit, (G, 10): W_g [m^2], W_g n_g, Q_g [m^3], Q_g x n_g.
    """

    #: Normals equal to this many decimals (of a unit vector) make panels coplanar-facing.
    NORMAL_DECIMALS = 12
    #: Group only when it divides the work by at least this much.
    MIN_PANELS_PER_FACET = 2.0

    def __init__(self, mesh: PanelMesh, index: np.ndarray, first: np.ndarray, surface):
        self.mesh = mesh
        self.index = index
        self.first = first
        self.n = len(first)
        self.normals = np.ascontiguousarray(mesh.normals[first])
        self.inward_normals_T = np.ascontiguousarray(-self.normals.T)
        self._areas = mesh.areas
        #: A_i r_i of every panel [m^3].
        self.weighted_barycentres = mesh.areas[:, None] * mesh.barycentres
        self.all_lit = self.sums_of(mesh.areas, self.weighted_barycentres)
        self._surface = surface
        self._facet_surface = self._facet_values(surface)

    @classmethod
    def of(cls, mesh: PanelMesh, surface) -> "Facets | None":
        """The facets of ``mesh``, or None if grouping would not save work (e.g. a sphere)."""
        key = np.column_stack(
            [np.round(mesh.normals, cls.NORMAL_DECIMALS) + 0.0, mesh.material_index]
        )
        _, first, index = np.unique(key, axis=0, return_index=True, return_inverse=True)
        if len(first) * cls.MIN_PANELS_PER_FACET > mesh.n_panels:
            return None
        return cls(mesh, index.reshape(-1), first, surface)

    def sums_of(self, weights, weighted_points) -> np.ndarray:
        """Read-only (G, 10) facet sums of panel weights w_i [m^2] and moments (N, 3) [m^3]."""
        W = np.bincount(self.index, weights=weights, minlength=self.n)
        sums = sum_columns(W, vector_sums(self.index, weighted_points, self.n), self.normals)
        sums.setflags(write=False)
        return sums

    def lit_sums_of(self, lighting: PanelLighting | None) -> np.ndarray:
        """Read-only (G, 10) facet sums of ``lighting`` (:attr:`all_lit` for None)."""
        if lighting is None:
            return self.all_lit
        f = lighting.lit_fraction
        w = self._areas * f
        wr = f[:, None] * self.weighted_barycentres
        i = lighting.shift_index
        if i.size:
            wr[i] += w[i, None] * lighting.shift
        return self.sums_of(w, wr)

    def lit_sums(self, lighting) -> np.ndarray:
        """:meth:`lit_sums_of` ``lighting``, or a :class:`LightingBlend`'s parts' sums blended."""
        if isinstance(lighting, LightingBlend):
            return blend_sums([(w, self.lit_sums_of(part)) for w, part in lighting.parts])
        return self.lit_sums_of(lighting)

    def surface_of(self, surface) -> PanelSurface | None:
        """Facet values of a per-panel surface, or None if some parameter varies within a facet."""
        return self._facet_surface if surface is self._surface else self._facet_values(surface)

    def _facet_values(self, surface) -> PanelSurface | None:
        values = {}
        for name in SURFACE_PARAMETERS:
            value = getattr(surface, name)
            if isinstance(value, float) or np.ndim(value) == 0:
                values[name] = value
                continue
            if surface is not self._surface and value is getattr(self._surface, name):
                # the materials' own array (e.g. a surface_with() that changed only alpha)
                values[name] = getattr(self._facet_surface, name)
                continue
            value = np.asarray(value)
            facet_value = value[self.first]
            if not np.array_equal(facet_value[self.index], value):
                return None
            values[name] = facet_value
        return PanelSurface(**values)
