"""Shading of an articulated body, cached per joint configuration.

One part of an articulated body shades another depending on the joint positions, so its
lighting depends on the configuration as well as on the flow direction. The cache lays a grid
over the configurations (step h_r in every revolute or continuous joint, h_p in every prismatic
one, grid points clipped to the joints' limits) and keeps, per grid configuration, a
:class:`~adbsat_ros.shading.cache.ShadingCache` of the body posed there (its flow-direction
cells, interpolated or not, as for a rigid body). A slowly turning array therefore costs one
pose and shader per grid step, not a ray cast per message.

Key: the grid indices of a configuration, in the body's joint order. Value: the posed body's
ShadingCache. Bound: ``max_configurations`` (least recently used dropped).

Interpolation (``interpolate=True``). In grid units x_j = q_j / h_j the positions
lie in a cell of the grid, which the Kuhn (Freudenthal) triangulation cuts into simplices: with
b = floor(x), f = x - b and the joints ordered by decreasing f (f_(1) >= ... >= f_(J)), the
simplex's vertices are v_0 = b and v_k = v_(k-1) + e_(k), with the barycentric weights
1 - f_(1), f_(1) - f_(2), ..., f_(J) (in a cell that a joint's limit cuts, f is measured
between the cell's grid positions as clipped to the limit). The lighting is the blend of the
vertices' lightings with those weights (at most J + 1 configurations, only those of positive
weight): continuous in the joint positions, so joint efforts have no steps at grid lines, exact
at grid points and where the lighting varies linearly with the positions. Without it, the
nearest grid configuration's lighting is used.

Error. Turning a part by d moves the shadows it casts, and those cast on it, as turning the flow
by d does for that part, so snapping to the nearest grid point (within h_r / 2) adds an error
of the direction cache's kind (:meth:`ShadingCache.area_error_bound` with theta = h_r / 2). The
blend is exact to first order: its error is of second order in h_r where the shadow edges move
smoothly. Measured on the finned example (8,736 faces, 12 random attitudes and deflections
within +-10 deg, against shading at the exact configuration): the largest errors relative to
the wrench's were, at h_r = 2 deg, 3e-5 (force), 3e-4 (moment) and 9e-4 of the largest joint
effort blended, against 6e-4, 6e-3 and 1e-2 snapped (and 1e-4, 1e-3 and 1.5e-3 snapped at
0.25 deg). The geometry of the wrench itself is exact
(:class:`~adbsat_ros.physics.articulated_method.ArticulatedMethod`).
"""

from __future__ import annotations

from typing import Callable, Mapping

from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.lru import LruStore
from adbsat_ros.shading.cache import ShadingCache
from adbsat_ros.shading.joint_grid import (
    grid_configuration,
    grid_key,
    grid_steps,
    grid_vertices,
)
from adbsat_ros.shading.lighting import LightingBlend


class ConfigurationShadingCache:
    """Lighting of an articulated body for a flow direction and joint positions.

    Parameters
    ----------
    body : ArticulatedBody
    make_cache : callable
        ``make_cache(positions)``: the :class:`ShadingCache` of the body posed at joint
        ``positions`` (a dict of every moving joint's position), of the panels of
        ``body.mesh(positions)``.
    angle_step : float
        Grid step h_r of revolute and continuous joints [rad], > 0.
    length_step : float
        Grid step h_p of prismatic joints [m], > 0.
    max_configurations : int
        Grid configurations kept, >= 1.
    interpolate : bool
        Blend the grid configurations of the simplex around the positions (module docstring)
        instead of taking the nearest one's lighting.

    Attributes
    ----------
    hits, misses : int
        Flow-direction cells read from a configuration's cache, and those that had to be
        shaded (over every configuration, also those dropped since).
    configuration_hits, configuration_misses : int
        Grid configurations read that were kept, and those that had to pose the body and make
        its shader.
    """

    def __init__(
        self,
        body: ArticulatedBody,
        make_cache: Callable[[dict], ShadingCache],
        angle_step: float,
        length_step: float,
        max_configurations: int,
        interpolate: bool = False,
    ):
        steps = grid_steps(body.joints, angle_step, length_step)
        if int(max_configurations) < 1:
            raise ValueError(f"max_configurations must be >= 1, got {max_configurations!r}")
        self.body = body
        self.interpolate = bool(interpolate)
        self._make_cache = make_cache
        self._steps = steps
        self.max_configurations = int(max_configurations)
        self._store = LruStore(self.max_configurations)  # grid key -> ShadingCache
        self.hits = self.misses = 0
        self._last: list = []  # (configuration key, its cache's last_keys) of the latest query

    @property
    def configuration_hits(self) -> int:
        """Grid configurations read that were kept."""
        return self._store.hits

    @property
    def configuration_misses(self) -> int:
        """Grid configurations read that had to be posed and shaded."""
        return self._store.misses

    def key(self, positions: Mapping[str, float]) -> tuple:
        """Grid indices of the grid configuration nearest checked joint ``positions`` (every
        moving joint named)."""
        return grid_key(self.body.joints, self._steps, positions)

    def vertices(self, positions: Mapping[str, float]) -> list:
        """``[(weight, key), ...]``: the grid configurations blended for ``positions`` and
        their weights (positive, summing to 1): the Kuhn simplex around them (module
        docstring), or the nearest configuration alone without interpolation."""
        return grid_vertices(self.body.joints, self._steps, positions, self.interpolate)

    def configuration(self, key: tuple) -> dict:
        """The joint positions of a grid key, clipped to the joints' limits."""
        return grid_configuration(self.body.joints, self._steps, key)

    def cache_at(self, key: tuple) -> ShadingCache:
        """The ShadingCache of the grid configuration ``key`` (posed and made if not kept)."""
        return self._store.get(key, lambda: self._make_cache(self.configuration(key)))

    def cache_of(self, positions: Mapping[str, float]) -> tuple:
        """``(key, ShadingCache)`` of the grid configuration nearest ``positions``."""
        key = self.key(positions)
        return key, self.cache_at(key)

    def lighting(self, u_G, positions: Mapping[str, float], vertices: list | None = None):
        """The lighting of the body at ``positions`` for unit flow direction ``u_G``: a
        PanelLighting or LightingBlend of :meth:`ArticulatedBody.mesh`'s panels
        (``vertices``: :meth:`vertices` of the positions, if made already)."""
        parts, last = [], []
        for weight, key in vertices or self.vertices(positions):
            cache = self.cache_at(key)
            hits, misses = cache.hits, cache.misses
            parts.append((weight, cache.lighting(u_G)))
            self.hits += cache.hits - hits
            self.misses += cache.misses - misses
            last.append((key, cache.last_keys))
        self._last = last
        if len(parts) == 1:  # (one configuration: its own answer)
            return parts[0][1]
        return LightingBlend(  # (the blend of blends, flattened)
            [
                (weight * w, part)
                for weight, lighting in parts
                for w, part in (
                    lighting.parts if isinstance(lighting, LightingBlend) else [(1.0, lighting)]
                )
            ]
        )

    @property
    def last_keys(self) -> tuple:
        """``(configuration key, cell key)`` of each cell the latest query read."""
        return tuple((key, cell) for key, cells in self._last for cell in cells)

    def __len__(self) -> int:
        return len(self._store)

    def info(self) -> dict:
        """Counters and size, for diagnostics."""
        return {
            "configurations": len(self._store),
            "max_configurations": self.max_configurations,
            "configuration_hits": self.configuration_hits,
            "configuration_misses": self.configuration_misses,
            "hits": self.hits,
            "misses": self.misses,
        }
