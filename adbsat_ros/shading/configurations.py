"""Shading of an articulated body, cached per joint configuration.

One part of an articulated body shades another depending on the joint positions, so its
lighting depends on the configuration as well as on the flow direction. The cache snaps the
configuration to a grid (step h_r in every revolute or continuous joint, h_p in every prismatic
one, clipped to the joints' limits) and keeps, per grid configuration, a
:class:`~adbsat_ros.shading.cache.ShadingCache` of the body posed there (its flow-direction
cells, interpolated or not, as for a rigid body). A slowly turning array therefore costs one
pose and shader per grid step, not a ray cast per message.

Key: the grid indices of the joint positions, in the body's joint order. Value: the posed
body's ShadingCache. Bound: ``max_configurations`` (least recently used dropped).

Error bound: the lighting is that of a configuration within h_r / 2 of every revolute joint
(h_p / 2 of every prismatic one). Turning a part by an angle d moves the shadows it casts, and
the shadows cast on it, as turning the flow by d does for that part, so with h_r equal to the
direction cache's resolution the configuration grid adds an error of the direction cache's own
kind and size (:meth:`ShadingCache.area_error_bound`); a prismatic joint moves shadows by at most
h_p / 2. The geometry of the wrench itself is exact
(:class:`~adbsat_ros.physics.articulated_method.ArticulatedMethod`).
"""

from __future__ import annotations

import math
from collections import OrderedDict
from typing import Callable, Mapping

from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.shading.cache import ShadingCache


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

    Attributes
    ----------
    hits, misses : int
        Flow-direction cells read from a configuration's cache, and those that had to be
        shaded (over every configuration, also those dropped since).
    configuration_hits, configuration_misses : int
        Queries whose grid configuration was kept, and those that had to pose the body and
        make its shader.
    last_keys : tuple
        ``(configuration key, cell key)`` of each cell the latest query read.
    """

    def __init__(
        self,
        body: ArticulatedBody,
        make_cache: Callable[[dict], ShadingCache],
        angle_step: float,
        length_step: float,
        max_configurations: int,
    ):
        if not (angle_step > 0.0 and length_step > 0.0):
            raise ValueError(
                f"the configuration grid's steps must be positive, got {angle_step!r} rad and "
                f"{length_step!r} m"
            )
        if int(max_configurations) < 1:
            raise ValueError(f"max_configurations must be >= 1, got {max_configurations!r}")
        self.body = body
        self._make_cache = make_cache
        self._steps = tuple(
            length_step if joint.kind == "prismatic" else angle_step
            for joint in body.joints.values()
        )
        self.max_configurations = int(max_configurations)
        self._store: OrderedDict = OrderedDict()  # key -> ShadingCache, least recent first
        self.hits = self.misses = 0
        self.configuration_hits = self.configuration_misses = 0
        self.last_keys: tuple = ()

    def key(self, positions: Mapping[str, float]) -> tuple:
        """Grid indices of checked joint positions (every moving joint named)."""
        return tuple(
            math.floor(positions[name] / step + 0.5)
            for name, step in zip(self.body.joints, self._steps)
        )

    def configuration(self, key: tuple) -> dict:
        """The joint positions of a grid key, clipped to the joints' limits."""
        out = {}
        for (name, joint), index, step in zip(self.body.joints.items(), key, self._steps):
            out[name] = min(max(index * step, joint.lower), joint.upper)
        return out

    def cache_of(self, positions: Mapping[str, float]) -> tuple:
        """``(key, ShadingCache)`` of the grid configuration nearest ``positions``."""
        key = self.key(positions)
        cache = self._store.get(key)
        if cache is not None:
            self._store.move_to_end(key)
            self.configuration_hits += 1
            return key, cache
        self.configuration_misses += 1
        cache = self._make_cache(self.configuration(key))
        self._store[key] = cache
        if len(self._store) > self.max_configurations:
            self._store.popitem(last=False)
        return key, cache

    def lighting(self, u_G, positions: Mapping[str, float]):
        """The lighting of the body at (nearly) ``positions`` for unit flow direction ``u_G``:
        a PanelLighting or LightingBlend of :meth:`ArticulatedBody.mesh`'s panels."""
        key, cache = self.cache_of(positions)
        hits, misses = cache.hits, cache.misses
        lighting = cache.lighting(u_G)
        self.hits += cache.hits - hits
        self.misses += cache.misses - misses
        self.last_keys = tuple((key, cell) for cell in cache.last_keys)
        return lighting

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
