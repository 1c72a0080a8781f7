"""Coplanar panels of one material grouped into facets, so the gas-surface model runs once per facet.

Coplanar panels share everything the models see (the incidence, and the surface when they share a
material): sum_i f_i A_i phi_i = W_g phi_g with W_g = sum f_i A_i, and sum_i f_i A_i r_i x phi_g =
Q_g x phi_g with Q_g = sum f_i A_i r_i (lit centroids included). A CAD satellite of flat faces
meshed into 10k triangles has a few hundred facets; a sphere has one per panel and is evaluated
panel by panel."""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.physics.incidence import _cross


def _facet_rows(c, cp, shear):
    """The (3, n) rows (q, k, max(c, 0)) of :meth:`PanelMethod._facet_totals` for facet values
    of shape (n,), q = c_tau / sin(delta) (``shear``) and k = q c - cp: elementwise, so the values
    of several directions laid end to end give each direction's own rows, bit for bit."""
    rows = np.empty((3, c.size))
    rows[0] = shear
    np.multiply(shear, c, out=rows[1])
    rows[1] -= cp
    np.maximum(c, 0.0, out=rows[2])
    return rows


def _shear_per_sine(ctau, sigma) -> np.ndarray:
    """c_tau / sin(delta), 0 where sin(delta) = 0 (the shear direction is undefined there, and
    every model's c_tau is 0)."""
    return np.divide(ctau, sigma, out=np.zeros_like(ctau), where=sigma > 0.0)


def _stacked(values, g: int) -> np.ndarray:
    """Per-direction model parameters (floats, or (G,) arrays) laid out as the (M G,) facet values
    of M directions, each direction's G values in a row."""
    if all(isinstance(v, float) for v in values):  # (np.float64 is a float)
        return np.repeat(np.array(values, dtype=float), g)
    return np.concatenate([np.broadcast_to(np.asarray(v, dtype=float), (g,)) for v in values])


class _Facets:
    """Coplanar panels of one material grouped into facets (see the module docstring).

    Attributes
    ----------
    index : ndarray of int, shape (N,)
        Facet of every panel.
    first : ndarray of int, shape (G,)
        One member panel of every facet (its normal and surface are the facet's).
    normals : ndarray, shape (G, 3)
        Outward unit normal of every facet (of its first member; members agree to 1e-12).
    inward_normals_T : ndarray, shape (3, G)
        ``-normals.T``, so that ``u @ inward_normals_T`` is every facet's cos(delta).
    """

    #: Normals equal to this many decimals (of a unit vector) make panels coplanar-facing.
    NORMAL_DECIMALS = 12
    #: Group only when it divides the work by at least this much.
    MIN_PANELS_PER_FACET = 2.0
    #: Read-only lightings (the shading cache's) whose facet sums are kept, oldest dropped first;
    #: as many as the cache keeps unpacked (shading_cache.RECENT_CELLS).
    MEMO_SIZE = 8

    def __init__(self, mesh: PanelMesh, index: np.ndarray, first: np.ndarray, surface):
        self.mesh = mesh
        self.index = index
        self.first = first
        self.n = len(first)
        self.normals = np.ascontiguousarray(mesh.normals[first])
        self.inward_normals_T = np.ascontiguousarray(-self.normals.T)
        self._areas = mesh.areas
        self._weighted_bary = mesh.areas[:, None] * mesh.barycentres
        self._all_lit = self._sums(mesh.areas, self._weighted_bary)
        self._surface = None
        self._facet_surface = self._facet_values(surface)
        self._surface = surface
        self._memo = {}  # id(lighting) -> (lighting, sums) of the MEMO_SIZE latest read-only lightings

    @classmethod
    def of(cls, mesh: PanelMesh, surface) -> "_Facets | None":
        """The facets of ``mesh``, or None if grouping would not save work (e.g. a sphere)."""
        key = np.column_stack(
            [np.round(mesh.normals, cls.NORMAL_DECIMALS) + 0.0, mesh.material_index]
        )
        _, first, index = np.unique(key, axis=0, return_index=True, return_inverse=True)
        if len(first) * cls.MIN_PANELS_PER_FACET > mesh.n_panels:
            return None
        return cls(mesh, index.reshape(-1), first, surface)

    def _sums(self, weights, weighted_bary):
        """Facet sums for panel weights w_i = f_i A_i and w_i (r_i + shift_i), as one (G, 10) matrix
        of columns W_g, W_g n_g, Q_g and Q_g x n_g (W = sum w_i, Q = sum w_i (r_i + shift_i))."""
        W = np.bincount(self.index, weights=weights, minlength=self.n)
        Q = np.stack(
            [
                np.bincount(self.index, weights=weighted_bary[:, k], minlength=self.n)
                for k in range(3)
            ],
            axis=-1,
        )
        sums = np.column_stack([W, W[:, None] * self.normals, Q, _cross(Q, self.normals)])
        sums.setflags(write=False)
        return sums

    def lit_sums(self, lighting):
        """The (G, 10) facet sums of :meth:`_sums` for a lighting (None: everything lit).

        Results for the latest :attr:`MEMO_SIZE` read-only lightings (what the shading cache hands
        out) are kept for later calls with the same objects.
        """
        if lighting is None:
            return self._all_lit
        kept = self._memo.get(id(lighting))
        if kept is not None and kept[0] is lighting:
            return kept[1]
        w = self._areas * lighting.lit_fraction
        wr = lighting.lit_fraction[:, None] * self._weighted_bary
        if lighting.shift_index.size:
            i = lighting.shift_index
            wr[i] += w[i, None] * lighting.shift
        sums = self._sums(w, wr)
        if not lighting.lit_fraction.flags.writeable:
            # kept with the lighting itself, so its id cannot be reused while the entry lives
            self._memo[id(lighting)] = (lighting, sums)
            if len(self._memo) > self.MEMO_SIZE:
                del self._memo[next(iter(self._memo))]
        return sums

    def surface_of(self, surface):
        """Facet values of a per-panel surface, or None if some parameter varies within a facet."""
        return self._facet_surface if surface is self._surface else self._facet_values(surface)

    def _facet_values(self, surface):
        from adbsat_ros.physics.surface import SURFACE_PARAMETERS, PanelSurface

        values = {}
        for name in SURFACE_PARAMETERS:
            value = getattr(surface, name)
            if (
                type(value) is float or np.ndim(value) == 0
            ):  # (the type test first: np.ndim costs ~1 us)
                values[name] = value
                continue
            if self._surface is not None and value is getattr(self._surface, name):
                # the materials' own array (e.g. a surface_with() that changed only alpha)
                values[name] = getattr(self._facet_surface, name)
                continue
            value = np.asarray(value)
            facet_value = value[self.first]
            if not np.array_equal(facet_value[self.index], value):
                return None
            values[name] = facet_value
        return PanelSurface(**values)
