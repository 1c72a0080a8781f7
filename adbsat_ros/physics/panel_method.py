"""The panel method: flat-plate forces summed over the mesh as force and moment coefficients,
C_F,G = (1/A_ref) sum_i f_i A_i (c_tau,i t_i - c_p,i n_i) and C_M,G about r_ref (ADBSat's
definitions; f_i the lit fraction; docs/physics.md, sections 1 and 2). The model runs once per
facet of coplanar panels of one material. Units: m, mesh frame G."""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.physics.coefficients import AeroCoefficients, Reference
from adbsat_ros.physics.facets import Facets, facet_rows, shear_per_sine
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.gsi_models import (
    SPECIES_MODELS,
    SPLIT_MODELS,
    ModelOptions,
    canonical_model_name,
    get_model,
)
from adbsat_ros.physics.incidence import sine_of_incidence
from adbsat_ros.physics.surface import SURFACE_PARAMETERS, MaterialTable, PanelSurface
from adbsat_ros.shading.lighting import PanelLighting
from adbsat_ros.shading.shader import MODES as SHADING_MODES
from adbsat_ros.shading.shader import make_shader

#: The default of :meth:`PanelMethod.coefficients`' ``lighting``: the method's own shading.
OWN_SHADING = object()


class PanelMethod:
    """A mesh with a gas-surface model and materials, ready to evaluate at any attitude.
    ``model``: a name of :data:`~adbsat_ros.physics.gsi_models.MODELS`; ``materials``: default
    alpha = sigma = 1, T_w = 300 K; ``group_facets``: False evaluates every panel (a test
    reference); ``shading``: ``"raycast"`` (default), ``"projection"`` (ADBSat's) or ``"none"``."""

    def __init__(
        self,
        mesh: PanelMesh,
        model="sentman",
        materials=None,
        options=None,
        reference=None,
        group_facets: bool = True,
        shading: str = "raycast",
    ):
        self.mesh = mesh
        self.model = canonical_model_name(model)
        self._model_fn = get_model(self.model)
        self._split = SPLIT_MODELS.get(self.model)  # (parameters, plate), or None
        self.materials = materials = MaterialTable.of(materials)
        self.options = options or ModelOptions()
        self.reference = (reference or Reference()).resolved(mesh)
        self.surface = materials.expand(mesh.material_names, mesh.material_index)
        self._normals = mesh.normals
        self._inward_normals_T = np.ascontiguousarray(-mesh.normals.T)
        self._areas = mesh.areas
        self._bary = mesh.barycentres
        self._r_cross_n = np.ascontiguousarray(np.cross(mesh.barycentres, mesh.normals))
        self._moment_point = np.asarray(self.reference.moment_point)
        self.facets = Facets.of(mesh, self.surface) if group_facets else None
        if shading not in SHADING_MODES:
            raise ValueError(f"shading must be one of {', '.join(SHADING_MODES)}, got {shading!r}")
        self.shading = shading
        self._shader = None

    @property
    def needs_species(self) -> bool:
        """True if the model needs the gas composition."""
        return self.model in SPECIES_MODELS

    # ------------------------------------------------------------------------------ per panel
    def surface_with(self, **changes):
        """Per-panel surface parameters, some set on every panel (``surface_with(alpha=0.9)``)."""
        values = {name: getattr(self.surface, name) for name in SURFACE_PARAMETERS}
        for name, value in changes.items():
            if name not in values:
                raise ValueError(f"unknown surface parameter {name!r}")
            values[name] = float(value)
        return PanelSurface(**values)

    def panel_coefficients(self, u_G, flow: FreeStream, surface=None):
        """cos_delta, sin_delta, cp, ctau of every panel, (N,) or (M, N), at the unit flow
        direction(s) u_G, G, (3,) or (M, 3)."""
        return self._local_coefficients(u_G, self._inward_normals_T, surface or self.surface, flow)

    def _local_coefficients(self, u_G, inward_normals_T, surface, flow):
        """c, sin(delta), cp and ctau for normals given as (3, N) -n^T."""
        u = np.asarray(u_G, dtype=float)
        c = u @ inward_normals_T
        np.minimum(c, 1.0, out=c)  # |c| <= 1 despite rounding
        np.maximum(c, -1.0, out=c)
        sigma = sine_of_incidence(u, inward_normals_T.T, c)
        cp, ctau = self._model_fn(c, sigma, surface, flow, self.options)
        return c, sigma, np.asarray(cp, dtype=float), np.asarray(ctau, dtype=float)

    def facet_coefficients(self, u, inward_normals_T, facet_surface, flow):
        """c, c_p, c_tau / sin(delta), c_tau (or None) of facets of normals (3, G) at unit ``u``."""
        split = self._split
        parameters = None if split is None else split[0](facet_surface, flow, self.options)
        if parameters is None:
            c, sigma, cp, ctau = self._local_coefficients(u, inward_normals_T, facet_surface, flow)
            return c, cp, shear_per_sine(ctau, sigma), ctau
        c = u @ inward_normals_T
        cp, shear = split[1](c, *parameters)  # (float arrays like c: the plates are elementwise)
        return c, cp, shear, None

    @staticmethod
    def totals_of_sums(u, rows, sums, reference):
        """Cf_G, Cm_G and the lit projected area [m^2] from facet rows and (G, 10) facet sums."""
        # (r W, r W n, r Q, r Q x n) and k's; the lit area (three components each, as floats)
        (
            (r_w, _, _, _, r_qx, r_qy, r_qz, _, _, _),
            (_, k_nx, k_ny, k_nz, _, _, _, k_mx, k_my, k_mz),
            (projected, *_),
        ) = (rows @ sums).tolist()
        ux, uy, uz = u.tolist()
        fx, fy, fz = r_w * ux + k_nx, r_w * uy + k_ny, r_w * uz + k_nz
        px, py, pz = reference.moment_point
        # moment = (sum r Q) x u + sum k (Q x n) - r_ref x force
        mx = r_qy * uz - r_qz * uy + k_mx - (py * fz - pz * fy)
        my = r_qz * ux - r_qx * uz + k_my - (pz * fx - px * fz)
        mz = r_qx * uy - r_qy * ux + k_mz - (px * fy - py * fx)
        area = reference.area
        area_length = area * reference.length
        force = np.array([fx / area, fy / area, fz / area])
        return force, np.array([mx / area_length, my / area_length, mz / area_length]), projected

    # ------------------------------------------------------------------------------ integration
    def integrate(self, u_G, c, sigma, cp, ctau, lighting: PanelLighting | None = None):
        """Cf_G, Cm_G (about the moment point), lit projected area [m^2] at u_G (G, (3,) or (M, 3));
        lighting: single direction only."""
        area = self._areas if lighting is None else self._areas * lighting.lit_fraction
        # Shear along t = (u + c n) / sin(delta): weight w_t multiplies (u + c n).
        w_t = np.divide(area * ctau, sigma, out=np.zeros_like(ctau), where=sigma > 0.0)
        g = w_t * c - area * cp  # coefficient of n_i in the panel force
        sum_w = w_t.sum(axis=-1)
        u = np.asarray(u_G, dtype=float)
        force = sum_w[..., None] * u + g @ self._normals
        moment = frames.cross(w_t @ self._bary, u) + g @ self._r_cross_n
        if lighting is not None and lighting.shift_index.size:
            i, d = lighting.shift_index, lighting.shift
            moment = moment + frames.cross(w_t[i] @ d, u) + g[i] @ frames.cross(d, self._normals[i])
        ref = self.reference
        moment = moment - frames.cross(self._moment_point, force)
        Cf = force / ref.area
        Cm = moment / (ref.area * ref.length)
        area_projected = (area * np.maximum(c, 0.0)).sum(axis=-1)
        return Cf, Cm, area_projected

    # ------------------------------------------------------------------------------ public API
    def lighting_of(self, u_G) -> PanelLighting | None:
        """The method's own ``shading`` of flow direction ``u_G`` (G), None for none."""
        if self.shading == "none":
            return None
        if self._shader is None:
            self._shader = make_shader(self.mesh, mode=self.shading)
        return self._shader.lighting(u_G)

    def coefficients(
        self,
        flow: FreeStream,
        aoa: float | None = None,
        aos: float | None = None,
        *,
        flow_direction=None,
        lighting=OWN_SHADING,
        surface=None,
    ) -> AeroCoefficients:
        """Coefficients at one attitude, given by angles or by the flow direction.
        aoa, aos: angle of attack and sideslip [rad] (frames module conventions).
        flow_direction: gas motion relative to the body in G, (3,), instead of the angles.
        lighting: None: nothing occluded; default the method's ``shading`` (:meth:`lighting_of`)."""
        u, angles = frames.attitude_flow(aoa, aos, flow_direction)
        if lighting is OWN_SHADING:
            lighting = self.lighting_of(u)
        if lighting is not None and lighting.n_panels != self.mesh.n_panels:
            raise ValueError(
                f"lighting has {lighting.n_panels} panels, the mesh has {self.mesh.n_panels}"
            )
        sums = None if self.facets is None else self.facets.lit_sums(lighting)
        return self.coefficients_of_sums(flow, u, angles, sums, lighting, surface)

    def coefficients_of_sums(
        self, flow: FreeStream, u, angles, sums, lighting, surface=None
    ) -> AeroCoefficients:
        """:meth:`coefficients` at unit ``u`` (G) from (G, 10) facet sums; angles [rad] or None."""
        facets = self.facets
        facet_surface = None if sums is None else facets.surface_of(surface or self.surface)
        if facet_surface is not None:
            c, cp, shear, ctau = self.facet_coefficients(
                u, facets.inward_normals_T, facet_surface, flow
            )
            rows = facet_rows(c, cp, shear)
            Cf_G, Cm_G, area_proj = self.totals_of_sums(u, rows, sums, self.reference)
            index, normals = facets.index, facets.normals
        else:
            c, sigma, cp, ctau = self.panel_coefficients(u, flow, surface)
            Cf_G, Cm_G, area_proj = self.integrate(u, c, sigma, cp, ctau, lighting)
            index = shear = normals = None
        return AeroCoefficients(
            flow_direction=u,
            Cf_G=Cf_G,
            Cm_G=Cm_G,
            reference=self.reference,
            area_projected=float(area_proj),
            model=self.model,
            panel_values=(c, cp, ctau, shear, normals),
            panel_index=index,
            lighting=lighting,
            angles=angles,
        )
