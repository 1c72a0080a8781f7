"""The one cache of shading: lightings, and what a method sums of them, by configuration and
flow-direction cell; bounded and counted. A cell holds the lighting of its centre, so answers do
not depend on the order of the queries. The bounds angle(u, u_c) <= h <= resolution_deg and
:meth:`ShadingCache.area_error_bound` are proven in docs/shading.md ("Cache")."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Callable

import numpy as np

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.lru import LruStore
from adbsat_ros.shading.cell_triangles import CellTriangulation
from adbsat_ros.shading.cube_map import cells_per_edge, direction_key, direction_keys, key_centres
from adbsat_ros.shading.joint_grid import grid_configuration, grid_steps, grid_vertices
from adbsat_ros.shading.lighting import LightingBlend, PanelLighting
from adbsat_ros.shading.shader import Shader

if TYPE_CHECKING:
    from adbsat_ros.geometry.articulated import ArticulatedBody

#: Most directions shaded in one call when cells are filled ahead.
PREPARED = 256
#: Per-panel sampling error allowance of the ray-cast lit fraction (docs/shading.md).
SAMPLING_ERROR = 0.05

_UNMADE = object()


class Cell:
    """A cell's entry: its read-only shared ``lighting`` and :attr:`sums`."""

    __slots__ = ("lighting", "_summarise", "_sums")

    def __init__(self, lighting: PanelLighting, summarise: Callable | None = None):
        self.lighting = lighting
        self._summarise = summarise
        self._sums = _UNMADE

    @property
    def sums(self):
        """``summarise(lighting)``, made once (None without a hook)."""
        if self._sums is _UNMADE:
            self._sums = None if self._summarise is None else self._summarise(self.lighting)
        return self._sums


class ShadingCache:
    """The cache of shading: :class:`Cell` values by (configuration, flow-direction cell).
    resolution_deg: bound [deg] from a query to its cell centre (cube-map step h = 90 / n).
    angle_step, length_step: the joint grid's steps [rad], [m]. Counters ``hits``, ``misses``,
    ``evictions`` (cells) and ``configuration_hits``/``misses`` (shaders)."""

    def __init__(
        self,
        shader: Shader | None = None,
        resolution_deg: float = 1.0,
        max_entries: int | None = 4096,
        interpolate: bool = False,
        *,
        summarise: Callable | None = None,
        exact: bool = False,
        body: ArticulatedBody | None = None,
        posed_shader: Callable[[dict], Shader] | None = None,
        angle_step: float | None = None,
        length_step: float | None = None,
        joint_interpolate: bool = False,
        max_configurations: int = 1,
    ):
        if max_entries is not None and int(max_entries) < 1:
            raise ValueError(f"max_entries must be >= 1 or None, got {max_entries!r}")
        if int(max_configurations) < 1:
            raise ValueError(f"max_configurations must be >= 1, got {max_configurations!r}")
        if (body is None) != (posed_shader is None) or (body is None) == (shader is None):
            raise ValueError("give a rigid body's shader, or an articulated body and posed_shader")
        if exact and interpolate:
            raise ValueError("exact mode has no cells to interpolate between")
        self.shader, self.body, self.exact = shader, body, bool(exact)
        self.mesh = None if shader is None else shader.mesh
        self.resolution_deg = float(resolution_deg)
        self.n = cells_per_edge(resolution_deg)
        self.step = 0.5 * math.pi / self.n
        self.max_entries = None if max_entries is None else int(max_entries)
        self.interpolate = bool(interpolate)
        self.triangulation = CellTriangulation(self.n) if self.interpolate else None
        self.joint_interpolate = bool(joint_interpolate)
        self.steps = None
        if body is not None and not self.exact:
            if angle_step is None or length_step is None:
                raise ValueError("an articulated body's grid needs angle_step and length_step")
            self.steps = grid_steps(body.joints, angle_step, length_step)
        self.max_configurations = 1 if body is None else int(max_configurations)
        self._summarise = summarise
        self._posed_shader = posed_shader
        self._perimeter = None
        self.clear()

    @classmethod
    def exact_mode(cls, shader=None, *, max_entries=1, **articulated) -> "ShadingCache":
        """A cache of the exact flow direction's (and positions') lighting; keeps the latest."""
        return cls(shader, max_entries=max_entries, exact=True, **articulated)

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
        """Cube-map cell key of flow direction ``u_G`` (G); ValueError unless finite, non-zero."""
        return direction_key(*frames.direction_components(u_G), self.n)

    def centre(self, key: int) -> np.ndarray:
        """Unit flow direction (G) at the centre of cell ``key``: the direction shaded."""
        return key_centres(int(key), self.n)

    def grid_directions(self) -> np.ndarray:
        """Centres of all 6 n^2 cells, shape (6 n^2, 3)."""
        return key_centres(np.arange(self.n_cells), self.n)

    def vertices(self, positions=None) -> list:
        """``[(weight, configuration key), ...]`` of ``positions`` (``[(1.0, ())]``: rigid)."""
        if self.body is None:
            return [(1.0, ())]
        if self.exact:
            return [(1.0, tuple(float(positions[name]) for name in self.body.joints))]
        return grid_vertices(self.body.joints, self.steps, positions, self.joint_interpolate)

    def configuration(self, key: tuple) -> dict:
        """The joint positions of a configuration key (grid points clipped to the limits)."""
        if self.body is None:
            return {}
        if self.exact:
            return dict(zip(self.body.joints, key))
        return grid_configuration(self.body.joints, self.steps, key)

    # ------------------------------------------------------------------------------ storage
    @property
    def hits(self) -> int:
        """Counted cell reads found stored."""
        return self._store.hits

    @property
    def misses(self) -> int:
        """Counted cell reads that shaded their cell."""
        return self._store.misses

    @property
    def evictions(self) -> int:
        """Cells dropped to stay within ``max_entries``."""
        return self._store.evictions

    @property
    def configuration_hits(self) -> int:
        """Counted shader reads found stored (0 for a rigid body)."""
        return self._shaders.hits

    @property
    def configuration_misses(self) -> int:
        """Counted shader reads that posed the body and made its shader."""
        return self._shaders.misses

    def __len__(self) -> int:
        return len(self._store)

    def __contains__(self, key) -> bool:
        """Whether a cell is stored: its cell key for a rigid body, else (configuration, cell)."""
        if self.body is None:
            key = ((), tuple(key) if self.exact else int(key))
        return key in self._store

    def clear(self):
        """Drop every cell and posed shader and reset the counters."""
        self._store = LruStore(self.max_entries)  # (configuration, cell) -> Cell
        self._shaders = LruStore(self.max_configurations)  # configuration -> Shader
        self._ahead: dict = {}  # exact mode: direction -> its lighting, shaded ahead (prepare)
        if self.shader is not None:
            self._shaders.get((), lambda: self.shader, count=False)
        self.last_keys: tuple = ()
        self.last_uncounted: tuple = ()

    def info(self) -> dict:
        """Counters and sizes, of the cells and of the shaders."""
        return {
            "hits": self.hits,
            "misses": self.misses,
            "evictions": self.evictions,
            "size": len(self._store),
            "max_entries": self.max_entries,
            "n": self.n,
            "step_deg": math.degrees(self.step),
            "configurations": len(self._shaders),
            "max_configurations": self.max_configurations,
            "configuration_hits": self.configuration_hits,
            "configuration_misses": self.configuration_misses,
        }

    # ------------------------------------------------------------------------------ queries
    def shader_at(self, configuration: tuple = (), count: bool = True) -> Shader:
        """The shader of the body posed at a configuration key (posed and made if not kept)."""
        if self.body is None:
            return self.shader
        return self._shaders.get(
            configuration, lambda: self._posed_shader(self.configuration(configuration)), count
        )

    def _cells_of(self, u_G) -> list:
        """(weight, cell key) of the cells an answer for ``u_G`` is made of (no counting)."""
        x, y, z = frames.direction_components(u_G)
        if self.exact:
            return [(1.0, (x, y, z))]
        if self.triangulation is None:
            return [(1.0, direction_key(x, y, z, self.n))]
        return [(w, key) for key, w in zip(*self.triangulation.locate(x, y, z)) if w > 0.0]

    def _made(self, configuration: tuple, cell, shader: Shader | None, count: bool) -> Cell:
        if shader is None:
            shader = self.shader_at(configuration, count)
        lighting = self._ahead.pop(cell, None) if self.exact else None
        if lighting is None:
            lighting = shader.lighting(cell if self.exact else self.centre(cell))
        return Cell(lighting, self._summarise)

    def read(self, u_G, vertices=None, count: bool = True) -> list:
        """``[(weight, Cell), ...]`` for direction ``u_G`` (G) and configuration ``vertices``."""
        if vertices is None:
            if self.body is not None:
                raise ValueError("an articulated body's read needs vertices(positions)")
            vertices = ((1.0, ()),)
        cells = self._cells_of(u_G)
        grid = self.body is not None and not self.exact
        out, keys = [], []
        for weight, configuration in vertices:
            shader = self.shader_at(configuration, count) if grid else None
            for w, cell in cells:
                key = (configuration, cell)
                value = self._store.get(
                    key, lambda: self._made(configuration, cell, shader, count), count
                )
                out.append((weight * w, value))
                keys.append(cell if self.body is None else key)
        if count:
            self.last_keys, self.last_uncounted = tuple(keys), ()
        else:
            self.last_uncounted = tuple(keys)
        return out

    def lighting(self, u_G, vertices=None) -> PanelLighting | LightingBlend:
        """Shading for flow direction ``u_G`` (G) (and ``vertices``), counted; read-only, shared."""
        return LightingBlend.of([(w, cell.lighting) for w, cell in self.read(u_G, vertices)])

    def lighting_angles(self, aoa: float, aos: float) -> PanelLighting:
        """:meth:`lighting` for angle of attack and sideslip [rad] (frames module)."""
        return self.lighting(frames.flow_direction(aoa, aos))

    def prepare(self, directions) -> None:
        """Shade a rigid body's directions (M, 3) in G in one call, for the reads to come
        (exact mode: kept until read, the same numbers; else their cells filled)."""
        if self.body is not None:
            return
        if not self.exact:
            self.precompute(directions)
            return
        keys = {frames.direction_components(u) for u in directions}
        keys = [key for key in keys if ((), key) not in self._store]
        self._ahead = dict(zip(keys, self.shader.lighting_many(keys)))

    def precompute(self, directions=None) -> int:
        """Fill a rigid body's cells of ``directions`` (M, 3) in G (default all); count shaded."""
        if self.body is not None or self.exact:
            raise ValueError("precompute fills a rigid body's cube-map cells only")
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
        keys = [key for key in keys.tolist() if ((), key) not in self._store]
        for s in range(0, len(keys), PREPARED):  # (blocks of directions shaded at once)
            block = keys[s : s + PREPARED]
            lightings = self.shader.lighting_many([self.centre(key) for key in block])
            for key, lighting in zip(block, lightings):
                self._store.get(((), key), lambda: Cell(lighting, self._summarise), count=False)
        return len(keys)

    # ------------------------------------------------------------------------------ error
    def shadow_perimeter(self) -> float:
        """P [m]: bound on the total length of shadow-casting silhouette edges."""
        if self._perimeter is None:
            self._perimeter = _silhouette_length_bound(self.mesh)
        return self._perimeter

    def area_error_bound(self, u_G, lighting: PanelLighting | None = None) -> float:
        """Bound E_max [m^2] on the lit projected area moved by a cached answer at ``u_G``:
        theta (D P + A_g) + 2 delta_s A_p (docs/shading.md)."""
        if self.body is not None or self.exact:
            raise ValueError("area_error_bound is the bound of a rigid body's cube-map cells")
        u = frames.unit_vector(u_G)
        cells = self._cells_of(u)
        centres = key_centres(np.array([key for _, key in cells]), self.n)
        theta = float(np.arccos(np.clip(centres @ u, -1.0, 1.0)).max())
        if lighting is None:
            lighting = LightingBlend.of(
                [(w, cell.lighting) for w, cell in self.read(u, None, False)]
            )
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
    """E(u) [m^2]: sum_i |f_i(cached) - f_i(exact)| A_i max(cos delta_i(u), 0) (docs/shading.md)."""
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
