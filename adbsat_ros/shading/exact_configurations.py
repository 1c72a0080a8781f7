"""Shading of an articulated body at its exact joint positions and flow direction: no grid.

The configuration grid (:mod:`~adbsat_ros.shading.configurations`) pays off when joints come
back to configurations it keeps: arrays tracking the Sun, fins held or swept periodically.
Joints that move to new positions with every message (fins commanded at every control step)
meet a new grid configuration at nearly every message, and its interpolated direction cells
cost three shadings of the posed body. :class:`ExactShading` shades the body posed at each
message's own joint positions for the message's own flow direction instead: one shading per
message, and neither the grid's nor the direction cells' error (the lighting is the shader's,
:mod:`~adbsat_ros.shading.shader`).

It keeps two things, each bounded to the latest one: the posed body's shader (key: the joint
positions, exactly; counted in :attr:`ExactShading.configuration_hits` and
:attr:`~ExactShading.configuration_misses`), so that messages between two joint states only
shade; and the latest lighting (key: the positions and the flow direction's components,
exactly; counted in :attr:`~ExactShading.hits` and :attr:`~ExactShading.misses`), so that a
message repeated gets the same answer without shading again.
"""

from __future__ import annotations

from typing import Callable, Mapping

from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.lru import LruStore
from adbsat_ros.shading.lighting import PanelLighting
from adbsat_ros.shading.shader import Shader


class ExactShading:
    """Lighting of an articulated body for a flow direction and joint positions, exactly.

    The interface of :class:`~adbsat_ros.shading.configurations.ConfigurationShadingCache`
    (what the estimator reads), without its grid.

    Parameters
    ----------
    body : ArticulatedBody
    make_shader : callable
        ``make_shader(positions)``: the :class:`Shader` of ``body.mesh(positions)`` (every
        moving joint's position in the dict).

    Attributes
    ----------
    hits, misses : int
        Lightings answered from the latest one (the same positions and flow direction again),
        and lightings shaded.
    last_keys : tuple
        ``(key,)`` of the latest query: its positions and flow direction.
    """

    def __init__(self, body: ArticulatedBody, make_shader: Callable[[dict], Shader]):
        self.body = body
        self._make_shader = make_shader
        self._shaders = LruStore(1)  # joint positions -> the posed body's shader
        self._lightings = LruStore(1)  # (joint positions, flow direction) -> its lighting
        self.last_keys: tuple = ()

    @property
    def hits(self) -> int:
        """Lightings answered from the latest one."""
        return self._lightings.hits

    @property
    def misses(self) -> int:
        """Lightings shaded."""
        return self._lightings.misses

    @property
    def configuration_hits(self) -> int:
        """Shadings at the positions of the shader kept."""
        return self._shaders.hits

    @property
    def configuration_misses(self) -> int:
        """Shadings at new positions: the body posed and its shader made."""
        return self._shaders.misses

    def vertices(self, positions: Mapping[str, float]) -> None:
        """No grid configurations (the grid cache's :meth:`vertices`): None."""
        return None

    def lighting(self, u_G, positions: Mapping[str, float], vertices=None) -> PanelLighting:
        """The lighting of the body posed at checked joint ``positions`` (every moving joint
        named) for unit flow direction ``u_G`` (three floats or an array, body frame)
        (``vertices``: ignored, as :meth:`vertices` gives none)."""
        configuration = tuple(float(positions[name]) for name in self.body.joints)
        x, y, z = (float(c) for c in u_G)
        key = (configuration, (x, y, z))
        self.last_keys = (key,)

        def shade() -> PanelLighting:
            shader = self._shaders.get(configuration, lambda: self._make_shader(dict(positions)))
            return shader.lighting((x, y, z))

        return self._lightings.get(key, shade)

    def __len__(self) -> int:
        return len(self._shaders)

    def info(self) -> dict:
        """Counters, for diagnostics."""
        return {
            "configurations": len(self._shaders),
            "configuration_hits": self.configuration_hits,
            "configuration_misses": self.configuration_misses,
            "hits": self.hits,
            "misses": self.misses,
        }
