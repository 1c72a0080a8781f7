"""The cache of shading: lightings keyed by the quantised flow direction, bounded, counted.

Shading depends only on the flow direction u in the mesh frame G, and changes little when u
moves a little, so a simulation that calls the panel method at slowly varying attitudes can
reuse results. :class:`ShadingCache` sits in front of a :class:`~adbsat_ros.shading.shader.Shader`:

* **Key.** u is mapped to a cell of an *equi-angular cube map*: the face of the cube that u
  points through (largest |component|), and the two angles alpha = atan(u_a / |u_k|),
  beta = atan(u_b / |u_k|) in [-45, 45] deg, each cut into n equal steps of
  h = 90 deg / n <= resolution_deg, n the smallest odd number >= 90 / resolution_deg (odd, so
  that the axis directions are cell centres, see :func:`cells_per_edge`). The cube map has no
  pole: every cell has the same shape class and size within a factor ~1.4 on the whole sphere.
* **Value.** The lighting of the cell *centre* u_c (computed once, whatever direction first
  hit the cell), so answers do not depend on the order of the queries.
* **Interpolation** (``interpolate=True``). The answer for u is then the blend of the lightings
  of the three cell centres around u, weighted by u's barycentric coordinates in their triangle
  (:mod:`~adbsat_ros.shading.cell_triangles`; a
  :class:`~adbsat_ros.shading.lighting.LightingBlend`): continuous in u, so coefficients have
  no steps at cell borders, and exact where the lighting varies linearly with u. The three
  centres lie within 2 h of u (measured at most 1.58 h).
* **Quantisation bound.** angle(u, u_c) <= h <= resolution_deg for every u, poles and cube
  edges included. Proof: on a face the unit vector (tan alpha, tan beta, 1)/|.| moves at an
  angular rate sec^2(alpha) sec(beta) / (sec^2(alpha) + tan^2(beta)) <= 1 when alpha varies
  (the inequality reduces to sec^2(alpha) <= 1 + sec(beta), true on the face), and likewise
  for beta; the path alpha -> alpha_c then beta -> beta_c has length <= h/2 + h/2.
  (Measured maximum: about 0.79 h.)
* **Bound.** Least recently used entries beyond ``max_entries`` are evicted (an
  :class:`~adbsat_ros.lru.LruStore` keeps them); hits, misses and
  evictions are counted (:meth:`ShadingCache.info`); :meth:`ShadingCache.precompute` fills
  cells of given directions or of the whole sphere. Entries are the
  :class:`~adbsat_ros.shading.lighting.PanelLighting` objects themselves, which are sparse
  (panels with lit fraction < 1 only) and read-only: memory grows with the shaded area, not
  with the mesh size, and a hit hands out the stored object as it is.

Error bound of a cached answer
------------------------------
Let L_c be the cached lighting (exact shading at u_c) and L the exact shading at u, both used
with the panel incidences at u (as ``PanelMethod`` does). The lit projected area moved,

    E(u) = sum_i |f_i(L_c) - f_i(L)| A_i max(cos delta_i(u), 0)     [m^2],

bounds the error of the lit projected area (AreaProj) and of every panel-force sum weighted by
it. :meth:`ShadingCache.area_error_bound` returns

    E_max = theta (D P + A_g) + 2 delta_s A_p

where theta <= h is the quantisation angle, D the bounding-box diagonal (the longest distance a
shadow can be thrown), P a bound on the length of the shadow-casting silhouette edges (for a
convex component pi x its bounding-box diagonal: its projection is a planar convex set of no
larger diameter, whose perimeter is at most pi x diameter; for any other component the total
length of its non-flat and open edges, which contain every silhouette edge), A_g the area of the
panels within theta of grazing at u (they may change from backward to forward) and A_p the
projected area of the panels partly lit in the cached answer; delta_s = 0.05 is the per-panel
sampling error allowance of the ray-cast estimate (measured 1-sigma 0.014 with 256 refinement
rays). The geometric part holds because turning the flow by theta moves the image of a
silhouette point thrown a distance d by at most theta d in the plane normal to the flow, so each
silhouette edge of projected length l sweeps at most l d theta of projected area. The bound is
conservative (often 10-50x the observed E); the tests check it on a cube in front of a plate.
"""

from __future__ import annotations

import math

import numpy as np

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.lru import LruStore
from adbsat_ros.shading.cell_triangles import CellTriangulation
from adbsat_ros.shading.cube_map import cells_per_edge, direction_key, direction_keys, key_centres
from adbsat_ros.shading.lighting import LightingBlend, PanelLighting
from adbsat_ros.shading.shader import Shader

#: Per-panel sampling error allowance of the ray-cast lit fraction (see module docstring).
SAMPLING_ERROR = 0.05


class ShadingCache:
    """The cache of shading: lightings by cube-map cell of the flow direction, LRU-bounded.

    Parameters
    ----------
    shader : Shader
        The shading of one mesh (any mode).
    resolution_deg : float
        Largest angle [deg] between a query direction and the direction its answer was
        computed for (the cube-map step h = 90 / n <= resolution_deg, :func:`cells_per_edge`).
    max_entries : int or None
        Largest number of stored cells (least recently used evicted first); None for no
        limit.
    interpolate : bool
        Answer with the blend of the three cell centres around the query (continuous in the
        direction) instead of the lighting of the query's own cell.

    Attributes
    ----------
    hits, misses, evictions : int
        Counters since construction (or :meth:`clear`): queries answered from the store,
        queries that shaded their cell, entries dropped to stay within ``max_entries``.
    n : int
        Cube-map steps per face edge (6 n^2 cells in all).
    step : float
        Cell size h [rad]; also the proven bound on the quantisation angle.
    last_keys : tuple of int
        Cell keys read by the latest :meth:`lighting` query (one, or three when interpolating;
        empty before the first).

    Notes
    -----
    Key: :meth:`key` (the cube-map cell). Value: the lighting of the cell centre. Bound:
    ``max_entries``. Error bound of a cached answer: see the module docstring and
    :meth:`area_error_bound`.
    """

    def __init__(
        self,
        shader: Shader,
        resolution_deg: float = 1.0,
        max_entries: int | None = 4096,
        interpolate: bool = False,
    ):
        if max_entries is not None and int(max_entries) < 1:
            raise ValueError(f"max_entries must be >= 1 or None, got {max_entries!r}")
        self.shader = shader
        self.mesh = shader.mesh
        self.resolution_deg = float(resolution_deg)
        self.n = cells_per_edge(resolution_deg)
        self.step = 0.5 * math.pi / self.n
        self.max_entries = None if max_entries is None else int(max_entries)
        self._store = LruStore(self.max_entries)  # key -> PanelLighting
        self.interpolate = bool(interpolate)
        self.triangulation = CellTriangulation.of(self.n) if self.interpolate else None
        self.last_keys: tuple = ()
        self._perimeter = None

    # ------------------------------------------------------------------------------ keys
    @property
    def max_angle(self) -> float:
        """Proven bound [rad] on the angle between a query and its cell centre (= step)."""
        return self.step

    @property
    def n_cells(self) -> int:
        """Number of cells on the sphere, 6 n^2."""
        return 6 * self.n * self.n

    def key(self, u_G) -> int:
        """Cell key of flow direction ``u_G`` (G frame); same as :func:`direction_keys`.

        Raises
        ------
        ValueError
            If ``u_G`` is not a finite non-zero 3-vector.
        """
        return direction_key(*frames.direction_components(u_G), self.n)

    def centre(self, key: int) -> np.ndarray:
        """Unit flow direction (G) at the centre of cell ``key``: the direction shaded."""
        return key_centres(int(key), self.n)

    def grid_directions(self) -> np.ndarray:
        """Centres of all 6 n^2 cells, shape (6 n^2, 3)."""
        return key_centres(np.arange(self.n_cells), self.n)

    # ------------------------------------------------------------------------------ storage
    @property
    def hits(self) -> int:
        """Queries of a cell stored (its lighting reused)."""
        return self._store.hits

    @property
    def misses(self) -> int:
        """Queries that shaded their cell."""
        return self._store.misses

    @property
    def evictions(self) -> int:
        """Entries dropped to stay within ``max_entries``."""
        return self._store.evictions

    def __len__(self) -> int:
        return len(self._store)

    def __contains__(self, key) -> bool:
        return int(key) in self._store

    def clear(self):
        """Drop every entry and reset the counters."""
        self._store = LruStore(self.max_entries)
        self.last_keys = ()

    def info(self) -> dict:
        """Counters and sizes: hits, misses, evictions, size, max_entries, n, step_deg."""
        return {
            "hits": self.hits,
            "misses": self.misses,
            "evictions": self.evictions,
            "size": len(self._store),
            "max_entries": self.max_entries,
            "n": self.n,
            "step_deg": math.degrees(self.step),
        }

    # ------------------------------------------------------------------------------ queries
    def lighting(self, u_G) -> PanelLighting | LightingBlend:
        """Shading for flow direction ``u_G`` (G), from the cache or computed at cell centres.

        Returns
        -------
        PanelLighting or LightingBlend
            Without interpolation, the exact shading of the cell centre u_c,
            angle(u_G, u_c) <= :attr:`max_angle`: the stored object itself (read-only), the
            same for every query in one cell. With it, the blend of the three centres around
            ``u_G`` (a stored lighting where one weight is 1).
        """
        x, y, z = frames.direction_components(u_G)
        if self.triangulation is None:
            key = direction_key(x, y, z, self.n)
            self.last_keys = (key,)
            return self.cell_lighting(key)
        parts = [(w, key) for key, w in zip(*self.triangulation.locate(x, y, z)) if w > 0.0]
        self.last_keys = tuple(key for _, key in parts)
        return LightingBlend.of([(w, self.cell_lighting(key)) for w, key in parts])

    def _cells_of(self, u_G) -> list:
        """(weight, key) of the cells an answer for ``u_G`` is made of (no counting)."""
        x, y, z = frames.direction_components(u_G)
        if self.triangulation is None:
            return [(1.0, direction_key(x, y, z, self.n))]
        return [(w, key) for key, w in zip(*self.triangulation.locate(x, y, z)) if w > 0.0]

    def cell_lighting(self, key: int) -> PanelLighting:
        """The lighting of the centre of cell ``key``: stored (a hit), or shaded and stored (a
        miss)."""
        return self._store.get(key, lambda: self.shader.lighting(self.centre(key)))

    __call__ = lighting

    def lighting_angles(self, aoa: float, aos: float) -> PanelLighting:
        """:meth:`lighting` for angle of attack and sideslip [rad] (frames module)."""
        return self.lighting(frames.flow_direction(aoa, aos))

    def precompute(self, directions=None) -> int:
        """Fill the cache for the cells of ``directions`` (default: every cell of the sphere).

        Parameters
        ----------
        directions : array_like, shape (M, 3), optional
            Flow directions in G (e.g. ``frames.flow_direction`` of an (aoa, aos) grid).

        Returns
        -------
        int
            Number of cells computed (cells already stored are skipped; counters unchanged).
            With more cells than ``max_entries`` only the last ``max_entries`` stay.
        """
        if directions is None:
            keys = np.arange(self.n_cells)
        else:
            d = np.atleast_2d(np.asarray(directions, dtype=float))
            if d.ndim != 2 or d.shape[1] != 3 or not np.all(np.isfinite(d)):
                raise ValueError("directions must be finite, shape (M, 3)")
            if np.any(np.linalg.norm(d, axis=1) == 0.0):
                raise ValueError("directions must be non-zero")
            keys = np.unique(direction_keys(d, self.n))
            if self.triangulation is not None:  # and the cells each answer is blended from
                keys = np.unique([key for u in d for _, key in self._cells_of(u)])
        computed = 0
        for key in keys.tolist():  # one shading per cell; the work inside is vectorised
            computed += key not in self._store
            self._store.get(key, lambda: self.shader.lighting(self.centre(key)), count=False)
        return computed

    # ------------------------------------------------------------------------------ error
    def shadow_perimeter(self) -> float:
        """P [m]: bound on the total length of shadow-casting silhouette edges (see module)."""
        if self._perimeter is None:
            self._perimeter = _silhouette_length_bound(self.mesh)
        return self._perimeter

    def area_error_bound(self, u_G, lighting: PanelLighting | None = None) -> float:
        """Bound E_max [m^2] on the lit projected area moved by using the cached answer at u_G.

        Parameters
        ----------
        u_G : array_like, shape (3,)
            Query flow direction (G).
        lighting : PanelLighting or LightingBlend, optional
            The cached answer for ``u_G`` (looked up, without touching the counters, if not
            given; computed if absent).

        Returns
        -------
        float
            theta (D P + A_g) + 2 delta_s A_p (module docstring), theta = angle(u_G, u_c); for
            a blend (which moves each panel's lit fraction by at most the weighted mean of its
            parts' errors) the largest angle to the centres blended.
        """
        u = frames.unit_vector(u_G)
        cells = self._cells_of(u)
        centres = key_centres(np.array([key for _, key in cells]), self.n)
        theta = float(np.arccos(np.clip(centres @ u, -1.0, 1.0)).max())
        if lighting is None:
            parts = []
            for w, key in cells:
                stored = self._store.get(key)
                parts.append(
                    (w, stored if stored is not None else self.shader.lighting(self.centre(key)))
                )
            lighting = LightingBlend.of(parts)
        mesh = self.mesh
        lo, hi = mesh.bounds
        diag = float(np.linalg.norm(hi - lo))
        c = -(mesh.normals @ u)
        grazing_area = float(mesh.areas[np.abs(c) <= math.sin(theta) + 1e-12].sum())
        part = lighting.partly_lit
        partial_area = float((mesh.areas[part] * np.maximum(c[part], 0.0)).sum())
        return (
            theta * (diag * self.shadow_perimeter() + grazing_area)
            + 2.0 * SAMPLING_ERROR * partial_area
        )


def moved_lit_area(mesh: PanelMesh, u_G, cached: PanelLighting, exact: PanelLighting) -> float:
    """E(u) [m^2]: sum_i |f_i(cached) - f_i(exact)| A_i max(cos delta_i(u), 0) (module doc)."""
    u = frames.unit_vector(u_G)
    c = np.maximum(-(mesh.normals @ u), 0.0)
    return float((np.abs(cached.lit_fraction - exact.lit_fraction) * mesh.areas * c).sum())


def _silhouette_length_bound(mesh: PanelMesh) -> float:
    """Sum over connected components of pi x diameter (convex) or non-flat edge length (other)."""
    import trimesh  # (for the error bound only: not at start-up)

    tm = mesh.to_trimesh()
    faces = np.asarray(tm.faces)
    verts = np.asarray(tm.vertices)
    labels = trimesh.graph.connected_component_labels(tm.face_adjacency, node_count=len(faces))
    total = 0.0
    for comp in np.unique(labels):  # loop over bodies (few)
        sel = np.flatnonzero(labels == comp)
        part = trimesh.Trimesh(vertices=verts, faces=faces[sel], process=False)
        part.remove_unreferenced_vertices()
        pts = np.asarray(part.vertices)
        if part.is_watertight and part.is_convex:
            # diameter <= bounding-box diagonal
            total += math.pi * float(np.linalg.norm(np.ptp(pts, axis=0)))
            continue
        # Every silhouette edge is an edge between non-coplanar faces or an open edge.
        adj = part.face_adjacency
        n = part.face_normals
        sharp = np.einsum("ij,ij->i", n[adj[:, 0]], n[adj[:, 1]]) < 1.0 - 1e-9
        edges = part.face_adjacency_edges[sharp]
        length = float(np.linalg.norm(pts[edges[:, 0]] - pts[edges[:, 1]], axis=1).sum())
        boundary = part.edges_sorted[
            trimesh.grouping.group_rows(part.edges_sorted, require_count=1)
        ]
        if len(boundary):
            length += float(np.linalg.norm(pts[boundary[:, 0]] - pts[boundary[:, 1]], axis=1).sum())
        total += length
    return total
