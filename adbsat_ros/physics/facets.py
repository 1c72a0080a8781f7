"""Coplanar panels of one material grouped into facets: the gas-surface model runs once per facet.

Coplanar panels share everything the models see (the incidence, and the surface when they share a
material): sum_i f_i A_i phi_i = W_g phi_g with W_g = sum f_i A_i, and sum_i f_i A_i r_i x phi_g =
Q_g x phi_g with Q_g = sum f_i A_i r_i (lit centroids included). A CAD satellite of flat faces
meshed into 10k triangles has a few hundred facets; a sphere has one per panel and is evaluated
panel by panel.

Shading changes the sums: W_g and Q_g are made from the lit fractions and shifts of a lighting
in one pass over the panels (np.bincount, in panel order; :meth:`Facets.lit_sums_of`, a pure
function of the lighting), and a blend's are the weighted sum of its parts' (:func:`blend_sums`).
:class:`LitSumsCache` keeps the sums of the latest lightings under their content fingerprint.

Units: metres and square metres, mesh frame G.
"""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from adbsat_ros.geometry.frames import cross
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.physics.surface import SURFACE_PARAMETERS, PanelSurface
from adbsat_ros.shading.lighting import LightingBlend, PanelLighting

#: Columns of the facet sums: W, W n (3), Q (3), Q x n (3).
N_SUMS = 10


def facet_rows(c, cp, shear) -> np.ndarray:
    """The (3, G) rows (q, k, max(c, 0)) that weight the facet sums.

    Parameters
    ----------
    c, cp, shear : ndarray, shape (G,)
        cos(delta), c_p and q = c_tau / sin(delta) of every facet.

    Returns
    -------
    ndarray, shape (3, G)
        q, k = q c - c_p, and max(c, 0): facet g carries the force W_g (q_g u + k_g n_g), the
        moment q_g (Q_g x u) + k_g (Q_g x n_g) and the projected area max(c_g, 0) W_g.
    """
    rows = np.empty((3, c.size))
    rows[0] = shear
    np.multiply(shear, c, out=rows[1])
    rows[1] -= cp
    np.maximum(c, 0.0, out=rows[2])
    return rows


def shear_per_sine(ctau, sigma) -> np.ndarray:
    """c_tau / sin(delta), 0 where sin(delta) = 0.

    The shear direction is undefined there, and every model's c_tau is 0.
    """
    return np.divide(ctau, sigma, out=np.zeros_like(ctau), where=sigma > 0.0)


def vector_sums(index, vectors, n: int) -> np.ndarray:
    """The (n, 3) sums of the rows of ``vectors`` (K, 3) by facet ``index`` (K,), each facet's
    rows summed in their order (np.bincount)."""
    return np.stack(
        [np.bincount(index, weights=vectors[:, k], minlength=n) for k in range(3)], axis=-1
    )


def sum_columns(weights, moments, normals) -> np.ndarray:
    """Columns W, W n, Q, Q x n (shape (G, 10)) of weights W (G,), moments Q (G, 3), normals n."""
    return np.column_stack([weights, weights[:, None] * normals, moments, cross(moments, normals)])


def blend_sums(parts) -> np.ndarray:
    """The weighted sum of the (G, 10) sums of a blend's parts, ``parts`` [(w, sums), ...] in
    part order: s = w_0 s_0, then s += w_k s_k (the sums are linear in the lit fractions and
    shifts)."""
    (w, first), *rest = parts
    sums = w * first
    for w, part in rest:
        sums += w * part
    return sums


class LitSumsCache:
    """The facet sums of the latest lightings: the panel method's one cache.

    Key: the lighting's content fingerprint (:attr:`PanelLighting.key`), so the same shading
    gives the same sums whichever object carries it. Value: the (G, 10) facet sums.
    Bound: the ``max_entries`` most recently used. Counters: hits, misses.

    Why it exists: on a shading-cache hit, the node's usual message, the lighting is that of the
    previous message, and summing it again over the panels is most of the panel method
    (docs/benchmarks.md). The all-lit sums plus a sparse correction over the panels not fully lit
    would cost less than summing, but their rounding, unlike the sums here, is not that of the
    per-panel sums: it moved a small side-force coefficient of the golden outputs by 1.5e-12 of its
    size.

    Parameters
    ----------
    max_entries : int
        Number of lightings whose sums are kept (>= 1).

    Attributes
    ----------
    hits, misses : int
        Lookups answered from the cache, and lookups that summed the lighting.
    """

    def __init__(self, max_entries: int = 8):
        if int(max_entries) < 1:
            raise ValueError(f"max_entries must be >= 1, got {max_entries!r}")
        self.max_entries = int(max_entries)
        self._store: OrderedDict = OrderedDict()
        self.hits = 0
        self.misses = 0

    def get(self, lighting: PanelLighting, compute) -> np.ndarray:
        """The sums of ``lighting``: stored ones, or ``compute(lighting)`` (then stored)."""
        key = lighting.key
        sums = self._store.get(key)
        if sums is not None:
            self._store.move_to_end(key)
            self.hits += 1
            return sums
        self.misses += 1
        sums = self._store[key] = compute(lighting)
        if len(self._store) > self.max_entries:
            self._store.popitem(last=False)
        return sums

    def __len__(self) -> int:
        return len(self._store)

    def info(self) -> dict:
        """Counters and sizes: hits, misses, size, max_entries."""
        return {
            "hits": self.hits,
            "misses": self.misses,
            "size": len(self._store),
            "max_entries": self.max_entries,
        }


class Facets:
    """Coplanar panels of one material grouped into facets (see the module docstring).

    Parameters
    ----------
    mesh : PanelMesh
        The panels.
    index : ndarray of int, shape (N,)
        Facet of every panel.
    first : ndarray of int, shape (G,)
        One member panel of every facet.
    surface : PanelSurface
        The materials' per-panel surface (its facet values are made once).

    Attributes
    ----------
    index : ndarray of int, shape (N,)
        Facet of every panel.
    first : ndarray of int, shape (G,)
        One member panel of every facet (its normal and surface are the facet's).
    n : int
        Number of facets G.
    normals : ndarray, shape (G, 3)
        Outward unit normal of every facet (of its first member; members agree to 1e-12).
    inward_normals_T : ndarray, shape (3, G)
        ``-normals.T``, so that ``u @ inward_normals_T`` is every facet's cos(delta).
    all_lit : ndarray, shape (G, 10)
        Facet sums with every panel lit: columns W_g [m^2], W_g n_g, Q_g [m^3], Q_g x n_g.
    lit_sums_cache : LitSumsCache
        The sums of the latest lightings.
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
        self.lit_sums_cache = LitSumsCache()
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
        """Read-only (G, 10) facet sums of panel weights w_i [m^2] and moments
        w_i (r_i + shift_i) [m^3] (shape (N, 3))."""
        W = np.bincount(self.index, weights=weights, minlength=self.n)
        sums = sum_columns(W, self.vector_sums(weighted_points), self.normals)
        sums.setflags(write=False)
        return sums

    def vector_sums(self, vectors, panels=None) -> np.ndarray:
        """The (G, 3) sums over each facet's members of per-panel ``vectors`` (shape (N, 3), or
        one row per panel of ``panels``, an index array: the other panels count as zero)."""
        return vector_sums(self.index if panels is None else self.index[panels], vectors, self.n)

    def lit_sums_of(self, lighting: PanelLighting | None) -> np.ndarray:
        """The read-only (G, 10) facet sums with the lit fractions and shifts of ``lighting``
        (:attr:`all_lit` for None), summed anew: columns W_g = sum f_i A_i [m^2], W_g n_g,
        Q_g = sum f_i A_i (r_i + shift_i) [m^3] and Q_g x n_g over the members i of each facet g.
        """
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
        """:meth:`lit_sums_of` ``lighting`` (a PanelLighting, a :class:`LightingBlend` or None),
        the latest lightings' from :attr:`lit_sums_cache`, a blend's by :func:`blend_sums`."""
        if lighting is None:
            return self.all_lit
        if isinstance(lighting, LightingBlend):
            return blend_sums([(w, self.lit_sums(part)) for w, part in lighting.parts])
        return self.lit_sums_cache.get(lighting, self.lit_sums_of)

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
