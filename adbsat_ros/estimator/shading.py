"""Lighting of the panels for a flow direction (and joint positions), through the shading cache
(or none)."""

from __future__ import annotations

import math

from adbsat_ros.estimator.parameters import SHADING_PARAMETERS
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.shading.cache import ShadingCache
from adbsat_ros.shading.configurations import ConfigurationShadingCache
from adbsat_ros.shading.exact_configurations import ExactShading
from adbsat_ros.shading.posed_scene import LinkScenes
from adbsat_ros.shading.shader import make_shader


class ShadingSource:
    """The estimator's shading: a :class:`ShadingCache` of the settings' shader, or nothing.

    For an articulated body, a :class:`ConfigurationShadingCache` of such caches, one per grid
    configuration, sharing the ``shading_cache_size`` bound; with ``joint_shading_exact`` an
    :class:`ExactShading` of the body posed at each message's positions.

    Parameters
    ----------
    mesh : PanelMesh
        The body's panels (mesh frame = body frame).
    settings : WrenchSettings
        The ``shading*`` and ``joint_shading*`` settings.
    body : ArticulatedBody, optional
        The articulated body whose (zero-configuration) panels ``mesh`` are.
    """

    def __init__(self, mesh: PanelMesh, settings: WrenchSettings, body=None):
        self.key = self.key_of(settings)
        self.cache = None
        if settings.shading == "none":
            return

        def shader_of(panels: PanelMesh, **made):
            return make_shader(
                panels, mode=settings.shading, samples=settings.shading_samples, **made
            )

        def cache_of(shader, max_entries: int) -> ShadingCache:
            return ShadingCache(
                shader,
                resolution_deg=settings.shading_cache_resolution_deg,
                max_entries=max_entries,
                interpolate=settings.shading_interpolation,
            )

        if isinstance(body, ArticulatedBody):
            # the links' ray scenes and filter topology, made once for every configuration
            scenes = LinkScenes(body) if settings.shading == "raycast" else None

            def posed_shader(positions: dict):
                poses = body.link_poses(positions)
                panels = body.posed_mesh(poses)
                if scenes is None:
                    return shader_of(panels)
                return shader_of(
                    panels,
                    scene=scenes.scene(panels, poses),
                    candidate_filter=scenes.candidate_filter(panels),
                    hull_corners=scenes.hull_corners(poses),
                )

            if settings.joint_shading_exact:
                self.cache = ExactShading(body, posed_shader)
                return
            # the configurations share the bound on the lightings kept: each keeps at most
            # shading_cache_size // joint_shading_cache_size flow directions (at least one)
            cells = max(1, settings.shading_cache_size // settings.joint_shading_cache_size)

            def configuration_cache(positions: dict) -> ShadingCache:
                return cache_of(posed_shader(positions), cells)

            self.cache = ConfigurationShadingCache(
                body,
                configuration_cache,
                math.radians(settings.joint_shading_resolution_deg),
                settings.joint_shading_resolution_m,
                settings.joint_shading_cache_size,
                interpolate=settings.joint_shading_interpolation,
            )
        else:
            self.cache = cache_of(shader_of(mesh), settings.shading_cache_size)

    @staticmethod
    def key_of(settings: WrenchSettings) -> tuple:
        """The settings a shading source is made of (another value needs another source)."""
        return tuple(getattr(settings, name) for name in SHADING_PARAMETERS)

    def vertices(self, positions: dict) -> list | None:
        """The grid configurations and weights for joint ``positions``, None without shading."""
        return None if self.cache is None else self.cache.vertices(positions)

    def lighting(self, flow_direction, positions=None, vertices=None) -> tuple:
        """``(lighting, hit)`` for a unit flow direction (body frame) and joint ``positions``.

        Returns
        -------
        lighting : PanelLighting, LightingBlend or None
            None without shading.
        hit : bool or None
            Whether the cache had every cell it read (None without shading).
        """
        if self.cache is None:
            return None, None
        misses = self.cache.misses
        if positions is None:
            lighting = self.cache.lighting(flow_direction)
        else:
            lighting = self.cache.lighting(flow_direction, positions, vertices)
        return lighting, self.cache.misses == misses

    @property
    def hits(self) -> int:
        """Shading-cache hits so far (0 without shading)."""
        return 0 if self.cache is None else self.cache.hits

    @property
    def misses(self) -> int:
        """Shading-cache misses so far (0 without shading)."""
        return 0 if self.cache is None else self.cache.misses
