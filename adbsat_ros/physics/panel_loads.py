"""Each panel's share of the load: its force and the point it acts at, summing to the totals.

Formulas: docs/physics.md, section 2, "Panel load and totals". Units: q A_ref, m, frame G.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from adbsat_ros.physics.coefficients import AeroCoefficients
from adbsat_ros.physics.incidence import sine_of_incidence


@dataclass(frozen=True)
class PanelLoads:
    """Force coefficient of every panel, F_i / (q A_ref) (N, 3) in G, and the ``point`` (N, 3) [m]
    where it acts; ``reference_length`` [m], ``moment_point`` [m]."""

    force: np.ndarray
    point: np.ndarray
    reference_length: float
    moment_point: np.ndarray

    def moments(self, about=None) -> np.ndarray:
        """Moment coefficients (r_i - about) x F_i / L_ref, (N, 3); ``about`` defaults to the moment
        point."""
        origin = self.moment_point if about is None else np.asarray(about, dtype=float)
        return np.cross(self.point - origin, self.force) / self.reference_length


def panel_loads(mesh, result: AeroCoefficients) -> PanelLoads:
    """The per-panel loads of a panel-method ``result`` for the mesh it was computed on.

    ValueError: the result is not of this mesh (another panel count).
    """
    if result.cp.shape != (mesh.n_panels,):
        raise ValueError(
            f"the result has {result.cp.shape[0]} panels, the mesh has {mesh.n_panels}"
        )
    u = result.flow_direction
    c = result.cos_delta
    normals = mesh.normals
    sigma = sine_of_incidence(u, normals, c)
    area = mesh.areas * result.lit_fraction
    ctau = result.ctau
    w_t = np.divide(area * ctau, sigma, out=np.zeros_like(ctau), where=sigma > 0.0)
    g = w_t * c - area * result.cp
    ref = result.reference
    force = (w_t[:, None] * u + g[:, None] * normals) / ref.area
    point = mesh.barycentres.copy()
    lighting = result.lighting
    if lighting is not None and lighting.shift_index.size:
        point[lighting.shift_index] += lighting.shift
    return PanelLoads(force, point, float(ref.length), np.asarray(ref.moment_point, dtype=float))
