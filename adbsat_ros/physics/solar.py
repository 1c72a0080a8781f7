"""Solar radiation pressure coefficients of the panel mesh (Luthcke et al. 1997 flat plate).

F / (P A) = c [(1 - rho_s) u_s - 2 (rho_s c + rho_d / 3) n] (Montenbruck & Gill 2000, eq. 3.75);
the sun direction is its own input and faces with c <= 0 get no force (docs/physics.md, sec. 7).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from adbsat_ros.geometry import frames
from adbsat_ros.physics.facets import facet_rows
from adbsat_ros.physics.incidence import sine_of_incidence
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.shading.lighting import PanelLighting


@dataclass(frozen=True, eq=False)
class SolarCoefficients:
    """Solar radiation pressure coefficients for one sun direction (unit, satellite to sun, G).

    ``Cf_G``, ``Cm_G``: force / (P A_ref) and moment / (P A_ref L_ref) in G; ``Cf_s`` in wind axes,
    ``Cm_S`` in body axes B; ``area_lit``: sunlit area projected normal to the sun [m^2].
    """

    sun_direction: np.ndarray
    Cf_G: np.ndarray
    Cm_G: np.ndarray
    Cf_s: np.ndarray
    Cm_S: np.ndarray
    area_lit: float

    def force(self, solar_pressure: float, area: float) -> np.ndarray:
        """Force [N] in G for solar pressure [Pa] (4.56e-6 at 1 au) and A_ref [m^2]."""
        return solar_pressure * area * self.Cf_G


def solar_coefficients(
    method: PanelMethod,
    sun_direction,
    *,
    aoa: float = 0.0,
    aos: float = 0.0,
    lighting: PanelLighting | None = None,
    sums=None,
) -> SolarCoefficients:
    """Solar radiation pressure coefficients of a mesh with its materials' reflectivities.

    sun_direction: satellite to sun, mesh frame G, any length, (3,).
    aoa, aos: flow angles [rad] of the wind axes of ``Cf_s``.
    sums: the (G, 10) facet sums of ``lighting``, if held.
    """
    s = np.asarray(sun_direction, dtype=float)
    norm = np.linalg.norm(s)
    if s.shape != (3,) or not np.isfinite(norm) or norm == 0.0:
        raise ValueError(f"sun_direction must be a finite non-zero 3-vector, got {sun_direction!r}")
    s = s / norm
    u = -s  # photons travel away from the sun
    facets = method.facets
    surface = None if facets is None else facets.surface_of(method.surface)
    if surface is not None:  # one plate per facet of coplanar panels of one material
        if sums is None:
            sums = facets.lit_sums(lighting)
        c = u @ facets.inward_normals_T
        np.clip(c, -1.0, 1.0, out=c)
        cs, cp = _luthcke(c, surface.specular_reflectivity, surface.diffuse_reflectivity)
        # c_tau / sin(theta) = c_s: the shear along (u + c n) / sin(theta)
        rows = facet_rows(c, cp, cs)
        Cf_G, Cm_G, area_lit = method.totals_of_sums(u, rows, sums, method.reference)
    else:
        c = -(method.mesh.normals @ u)
        np.clip(c, -1.0, 1.0, out=c)
        sigma = sine_of_incidence(u, method.mesh.normals, c)
        surface = method.surface
        cs, cp = _luthcke(c, surface.specular_reflectivity, surface.diffuse_reflectivity)
        Cf_G, Cm_G, area_lit = method.integrate(u, c, sigma, cp, cs * sigma, lighting)
    return SolarCoefficients(
        sun_direction=s,
        Cf_G=Cf_G,
        Cm_G=Cm_G,
        Cf_s=frames.mesh_to_wind(aoa, aos) @ Cf_G,
        Cm_S=frames.L_GB @ Cm_G,
        area_lit=float(area_lit),
    )


def _luthcke(c, rho_s, rho_d) -> tuple:
    """c_s and c_p = c_n + c_s c of plates at cos(theta) = c (0 where c <= 0)."""
    lit = c > 0.0
    cs = np.where(lit, (1.0 - rho_s) * c, 0.0)
    cn = np.where(lit, 2.0 * (rho_d * c / 3.0 + rho_s * c * c), 0.0)
    return cs, cn + cs * c
