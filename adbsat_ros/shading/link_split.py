"""A body's lighting split by link, each part in its link's frame, cached.

An articulated body is evaluated link by link in the links' own frames
(:class:`~adbsat_ros.physics.articulated_method.ArticulatedMethod`), so the lighting of the posed
body (one per flow-direction cell of the shading cache) is cut into the links' panel ranges and
its lit-centroid shifts turned into each link's frame (:func:`~.lighting.panel_range`). The same
cell lightings come back message after message, so :class:`LinkSplitCache` keeps their splits.
"""

from __future__ import annotations

from adbsat_ros.lru import LruStore
from adbsat_ros.shading.lighting import LightingBlend, PanelLighting, panel_range


class LinkSplitCache:
    """Per-link parts of lightings, for a body whose links' panels are consecutive.

    Parameters
    ----------
    spans : sequence of (int, int)
        Each evaluated link's panel range [start, stop), in evaluation order.
    max_entries : int
        Splits kept.

    Notes
    -----
    Key: (the lighting's content key, the configuration's key). Value: one lighting (or None,
    all lit) per link. Bound: ``max_entries``. Counters: :attr:`store`'s ``hits`` and
    ``misses``.
    """

    def __init__(self, spans, max_entries: int = 256):
        self.spans = tuple((int(a), int(b)) for a, b in spans)
        self.store = LruStore(max_entries)
        self._all_lit = [PanelLighting.all_lit(b - a) for a, b in self.spans]

    def split(self, lighting, rotations, configuration: tuple) -> list:
        """One lighting per link (None: nothing shaded there), shifts in the link's frame.

        Parameters
        ----------
        lighting : PanelLighting, LightingBlend or None
            The posed body's lighting.
        rotations : sequence of ndarray (3, 3)
            Each link's rotation into the body frame, in the order of ``spans``.
        configuration : tuple
            A key of the joint positions the rotations are of.
        """
        if lighting is None:
            return [None] * len(self.spans)
        if isinstance(lighting, LightingBlend):
            parts = [self._split(part, rotations, configuration) for _, part in lighting.parts]
            out = []
            for k in range(len(self.spans)):
                pieces = [p[k] for p in parts]
                if all(piece is None for piece in pieces):
                    out.append(None)
                    continue
                lit = self._all_lit[k]
                out.append(
                    LightingBlend(
                        [
                            (w, lit if piece is None else piece)
                            for (w, _), piece in zip(lighting.parts, pieces)
                        ]
                    )
                )
            return out
        return self._split(lighting, rotations, configuration)

    def _split(self, lighting: PanelLighting, rotations, configuration: tuple) -> list:
        return self.store.get(
            (lighting.key, configuration),
            lambda: [
                panel_range(lighting, start, stop, rotation.T)
                for (start, stop), rotation in zip(self.spans, rotations)
            ],
        )
