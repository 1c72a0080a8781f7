"""Lighting of the panels for a flow direction, through the shading cache (or none)."""

from __future__ import annotations

from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.shading.cache import ShadingCache
from adbsat_ros.shading.shader import make_shader


class ShadingSource:
    """The estimator's shading: a :class:`ShadingCache` of the settings' shader, or nothing.

    Parameters
    ----------
    mesh : PanelMesh
        The body's panels (mesh frame = body frame).
    settings : WrenchSettings
        ``shading`` (none, projection, raycast), ``shading_samples``,
        ``shading_cache_resolution_deg``, ``shading_cache_size`` and
        ``shading_interpolation``.
    """

    def __init__(self, mesh: PanelMesh, settings: WrenchSettings):
        self.key = self.key_of(settings)
        self.cache = None
        if settings.shading != "none":
            shader = make_shader(mesh, mode=settings.shading, samples=settings.shading_samples)
            self.cache = ShadingCache(
                shader,
                resolution_deg=settings.shading_cache_resolution_deg,
                max_entries=settings.shading_cache_size,
                interpolate=settings.shading_interpolation,
            )

    @staticmethod
    def key_of(settings: WrenchSettings) -> tuple:
        """The settings a shading source is made of (another value needs another source)."""
        return (
            settings.shading,
            settings.shading_samples,
            settings.shading_cache_resolution_deg,
            settings.shading_cache_size,
            settings.shading_interpolation,
        )

    def lighting(self, flow_direction) -> tuple:
        """``(lighting, hit)`` for a unit flow direction in the body frame.

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
        lighting = self.cache.lighting(flow_direction)
        return lighting, self.cache.misses == misses

    @property
    def hits(self) -> int:
        """Shading-cache hits so far (0 without shading)."""
        return 0 if self.cache is None else self.cache.hits

    @property
    def misses(self) -> int:
        """Shading-cache misses so far (0 without shading)."""
        return 0 if self.cache is None else self.cache.misses
