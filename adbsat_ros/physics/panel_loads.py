"""Each panel's share of the load: its force and the point it acts at, summing to the totals.

Per unit dynamic pressure and reference area (docs/physics.md, section 2, "Panel load and
totals"): F_i = A_i f_i (-c_p,i n_i + c_tau,i t_i) / A_ref, t_i = (u + c_i n_i) / sin(delta_i),
acting at the barycentre or the lit part's centroid. Sums: F = Cf_G and
(r_i - r_ref) x F_i / L_ref = Cm_G, to rounding. Units: q A_ref, metres, mesh frame G.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from adbsat_ros.physics.coefficients import AeroCoefficients
from adbsat_ros.physics.incidence import sine_of_incidence


@dataclass(frozen=True)
class PanelLoads:
    """Force coefficient of every panel and where it acts.

    Attributes
    ----------
    force : ndarray, shape (N, 3)
        F_i / (q A_ref), mesh frame G.
    point : ndarray, shape (N, 3)
        Where it acts [m]: the barycentre, or the lit part's centroid.
    reference_length : float
        L_ref [m], for moment coefficients.
    moment_point : ndarray, shape (3,)
        The result's moment point [m].
    """

    force: np.ndarray
    point: np.ndarray
    reference_length: float
    moment_point: np.ndarray

    def moments(self, about=None) -> np.ndarray:
        """Moment coefficient of every panel about ``about`` (default the moment point),
        (r_i - about) x F_i / L_ref, shape (N, 3)."""
        origin = self.moment_point if about is None else np.asarray(about, dtype=float)
        return np.cross(self.point - origin, self.force) / self.reference_length


def panel_loads(mesh, result: AeroCoefficients) -> PanelLoads:
    """The per-panel loads of a panel-method ``result`` for the mesh it was computed on.

    Raises
    ------
    ValueError
        If the result is not of this mesh (another panel count).
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
