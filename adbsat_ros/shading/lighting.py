"""Which part of each panel the flow (or sunlight) reaches: the output of shading.

A :class:`PanelLighting` is what the panel method needs from a shading analysis: the lit fraction
of every panel (its effective area is A_i times the fraction), and for partly lit panels the shift
of the centre of pressure from the barycentre to the centroid of the lit part.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True, eq=False)
class PanelLighting:
    """Lit fraction and lit-centroid shift of every panel, for one flow direction.

    Attributes
    ----------
    lit_fraction : ndarray, shape (N,)
        Fraction of each panel's area reached by the flow, in [0, 1].
    shift_index : ndarray of int, shape (K,)
        Panels whose lit part has its centroid away from the barycentre (partly lit panels).
    shift : ndarray, shape (K, 3)
        Lit centroid minus barycentre of those panels [m], in the mesh frame G.
    """

    lit_fraction: np.ndarray
    shift_index: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    shift: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))

    @classmethod
    def all_lit(cls, n_panels: int) -> "PanelLighting":
        """Every panel fully lit (no occlusion)."""
        return cls(np.ones(n_panels))

    @property
    def shaded(self) -> np.ndarray:
        """Boolean (N,): panels entirely in shadow."""
        return self.lit_fraction <= 0.0

    @property
    def partly_lit(self) -> np.ndarray:
        """Boolean (N,): panels partly in shadow."""
        return (self.lit_fraction > 0.0) & (self.lit_fraction < 1.0)
