"""The panel method: sum of flat-plate forces over the mesh, as force and moment coefficients.

For a flow direction u (unit vector of the gas motion relative to the body, mesh frame G), every
panel i with outward normal n_i, area A_i and barycentre r_i sees the incidence
cos(delta_i) = -u . n_i; a gas-surface model gives c_p,i and c_tau,i; the shear acts along the
tangential part of u, t_i = (u + cos(delta_i) n_i) / sin(delta_i). Then (ADBSat's definitions)

    C_F,G = (1/A_ref) sum_i f_i A_i (c_tau,i t_i - c_p,i n_i)
    C_M,G = (1/(A_ref L_ref)) sum_i f_i A_i (r_i - r_ref) x (c_tau,i t_i - c_p,i n_i)

where f_i is the lit fraction from shading (1 without it) and r_i moves to the lit centroid for
partly lit panels. Forces in newtons are q A_ref C_F and torques q A_ref L_ref C_M with
q = rho V^2 / 2.

Coplanar panels share everything the models see (the incidence, and the surface when they share a
material), so :meth:`PanelMethod.coefficients` evaluates the model once per *facet* (panels with
the same outward normal, to 1e-12, and the same material) and sums exactly:
sum_i f_i A_i phi_i = W_g phi_g with W_g = sum f_i A_i, and sum_i f_i A_i r_i x phi_g =
Q_g x phi_g with Q_g = sum f_i A_i r_i (lit centroids included). A CAD satellite of flat faces
meshed into 10k triangles has a few hundred facets; a sphere has one per panel, and is evaluated
panel by panel as before. The per-panel outputs (cp, ctau, cos_delta) are the facet values.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from adbsat_ros.geometry import frames
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.gsi_models import SPECIES_MODELS, SPLIT_MODELS, ModelOptions, canonical_model_name, get_model
from adbsat_ros.shading.lighting import PanelLighting
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.physics.surface import MaterialTable


def _cross(a, b):
    """Cross product over the last axis (np.cross without its per-call overhead)."""
    if a.ndim == 1 and b.ndim == 1:
        a0, a1, a2 = (float(v) for v in a)
        b0, b1, b2 = (float(v) for v in b)
        return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


def _facet_rows(c, cp, shear):
    """The (3, n) rows (q, k, max(c, 0)) of :meth:`PanelMethod._facet_totals` for facet values
    of shape (n,), q = c_tau / sin(delta) (``shear``) and k = q c - cp: elementwise, so the values
    of several directions laid end to end give each direction's own rows, bit for bit."""
    rows = np.empty((3, c.size))
    rows[0] = shear
    np.multiply(shear, c, out=rows[1])
    rows[1] -= cp
    np.maximum(c, 0.0, out=rows[2])
    return rows


def _shear_per_sine(ctau, sigma) -> np.ndarray:
    """c_tau / sin(delta), 0 where sin(delta) = 0 (the shear direction is undefined there, and
    every model's c_tau is 0)."""
    return np.divide(ctau, sigma, out=np.zeros_like(ctau), where=sigma > 0.0)


#: Below this sin(delta) [-] (within 0.06 deg of normal incidence) :func:`sine_of_incidence`
#: takes |u x n| instead of sqrt(1 - c^2).
NEAR_NORMAL_SINE = 1e-3


def sine_of_incidence(u, normals, c) -> np.ndarray:
    """sin(delta) of every panel, given c = cos(delta) = -u . n.

    sqrt(1 - c^2), except within NEAR_NORMAL_SINE of normal incidence, where 1 - c^2 cancels (c
    rounds to +-1 below delta ~ 1.5e-8 rad, and a panel's shear, along (u + c n) / sin(delta),
    would be lost with its sine) and |u x n| is taken instead, which has no cancellation.

    Parameters
    ----------
    u : ndarray, shape (3,) or (M, 3)
        Unit flow direction(s).
    normals : ndarray, shape (N, 3)
        Unit panel normals (either orientation).
    c : ndarray, shape (N,) or (M, N)
        cos(delta) of every panel for every direction, within [-1, 1].

    Returns
    -------
    ndarray, shape of ``c``
    """
    sigma = np.sqrt(1.0 - c * c)
    near = sigma < NEAR_NORMAL_SINE
    if near.any():
        if c.ndim == 1:
            cross = _cross(u, normals[near])
        else:
            rows, panels = np.nonzero(near)
            cross = _cross(u[rows], normals[panels])
        sigma[near] = np.sqrt((cross * cross).sum(axis=-1))
    return sigma


def _unit_direction(flow_direction) -> np.ndarray:
    """``flow_direction`` as a unit 3-vector (float array); ValueError if not a finite non-zero one."""
    u = np.asarray(flow_direction, dtype=float)
    if u.shape != (3,):
        raise ValueError(f"flow_direction must be a finite non-zero 3-vector, got {flow_direction!r}")
    x, y, z = u.tolist()
    norm = math.sqrt(x * x + y * y + z * z)
    if not (math.isfinite(norm) and norm > 0.0):
        raise ValueError(f"flow_direction must be a finite non-zero 3-vector, got {flow_direction!r}")
    return u / norm


def _stacked(values, g: int) -> np.ndarray:
    """Per-direction model parameters (floats, or (G,) arrays) laid out as the (M G,) facet values
    of M directions, each direction's G values in a row."""
    if all(isinstance(v, float) for v in values):  # (np.float64 is a float)
        return np.repeat(np.array(values, dtype=float), g)
    return np.concatenate([np.broadcast_to(np.asarray(v, dtype=float), (g,)) for v in values])


@dataclass(frozen=True)
class Reference:
    """Reference quantities of the coefficients; None means ADBSat's default.

    Parameters
    ----------
    area : float, optional
        A_ref [m^2]; default half the total wetted area (ADBSat's choice, not the projected area).
    length : float, optional
        L_ref [m]; default the x-extent of the mesh, max x - min x.
    moment_point : array_like, shape (3,)
        Point about which moments are taken, in the mesh frame [m]; default the mesh origin.
    """

    area: float | None = None
    length: float | None = None
    moment_point: tuple = (0.0, 0.0, 0.0)

    def __post_init__(self):
        for name in ("area", "length"):
            value = getattr(self, name)
            if value is not None and (not math.isfinite(float(value)) or float(value) <= 0):
                raise ValueError(f"reference {name} must be a finite number > 0, got {value!r}")
        point = np.asarray(self.moment_point, dtype=float)
        if point.shape != (3,) or not np.all(np.isfinite(point)):
            raise ValueError(f"moment_point must be three finite numbers, got {self.moment_point!r}")
        object.__setattr__(self, "moment_point", tuple(float(v) for v in point))

    def resolved(self, mesh: PanelMesh) -> "Reference":
        """A copy with the defaults filled in from ``mesh``."""
        if self.length is None and not mesh.x_extent > 0.0:
            raise ValueError(
                f"{mesh.source}: the mesh has no extent along x, so the default reference length "
                "(max x - min x) is 0: give a reference length"
            )
        return Reference(
            area=float(self.area) if self.area is not None else 0.5 * mesh.total_area,
            length=float(self.length) if self.length is not None else mesh.x_extent,
            moment_point=self.moment_point,
        )


class AeroCoefficients:
    """Aerodynamic coefficients of one attitude.

    The mesh-frame sums are computed at once; the rest (angles, other axes, per-panel values) on
    first access, so a caller that needs only ``Cf_G`` and ``Cm_G`` (the ROS node) pays for nothing
    else.

    Attributes
    ----------
    flow_direction : ndarray, shape (3,)
        Unit vector of the gas motion relative to the body, mesh frame G.
    Cf_G : ndarray, shape (3,)
        Force coefficient in the mesh frame G.
    Cm_G : ndarray, shape (3,)
        Moment coefficient in G about ``reference.moment_point``.
    reference : Reference
        A_ref [m^2], L_ref [m] and moment point [m] used.
    area_projected : float
        Lit projected area normal to the flow, sum of f_i A_i cos(delta_i) over front faces [m^2]
        (ADBSat ``AreaProj``).
    model : str
        Gas-surface model name.
    aoa, aos : float
        Angle of attack and sideslip [rad] of the flow (frames module).
    Cf_w : ndarray, shape (3,)
        Force coefficient in wind axes (ADBSat ``Cf_w``); drag = -Cf_w[0].
    Cf_f : ndarray, shape (3,)
        Force coefficient in ADBSat's flight axes (``Cf_f``; x aft, z up).
    Cm_B : ndarray, shape (3,)
        Moment coefficient in ADBSat's body axes B (``Cm_B``), about the moment point.
    cos_delta, cp, ctau : ndarray, shape (N,)
        Per-panel incidence cosine and local pressure and shear coefficients (before shading).
    lit_fraction : ndarray, shape (N,)
        Per-panel lit fraction used (all ones without shading).
    """

    def __init__(self, flow_direction, Cf_G, Cm_G, reference: Reference, area_projected: float, model: str,
                 panel_values, panel_index=None, lighting: PanelLighting | None = None, angles=None):
        self.flow_direction = flow_direction
        self.Cf_G = Cf_G
        self.Cm_G = Cm_G
        self.reference = reference
        self.area_projected = area_projected
        self.model = model
        # (cos_delta, cp, ctau, ctau / sin(delta), normals) per panel, or per facet with panel_index
        # mapping panels to facets; ctau may be None (then made from ctau / sin(delta) and the
        # (G, 3) facet normals when asked for), ctau / sin(delta) and normals are None when ctau is
        # given
        self._panel_values = panel_values
        self._panel_index = panel_index
        self._lighting = lighting
        self._angles = angles

    def __repr__(self) -> str:
        return (f"AeroCoefficients(model={self.model!r}, aoa={self.aoa!r}, aos={self.aos!r}, "
                f"Cf_G={self.Cf_G!r}, Cm_G={self.Cm_G!r}, area_projected={self.area_projected!r})")

    @functools.cached_property
    def _angles_rad(self) -> tuple:
        if self._angles is not None:
            return self._angles
        return tuple(float(a) for a in frames.angles_of_flow(self.flow_direction))

    @property
    def aoa(self) -> float:
        return self._angles_rad[0]

    @property
    def aos(self) -> float:
        return self._angles_rad[1]

    @functools.cached_property
    def _Cf_B(self) -> np.ndarray:
        return frames.L_GB @ self.Cf_G

    @functools.cached_property
    def Cf_w(self) -> np.ndarray:
        return frames.body_to_wind(self.aoa, self.aos) @ self._Cf_B

    @functools.cached_property
    def Cf_f(self) -> np.ndarray:
        return frames.L_FB @ self._Cf_B

    @functools.cached_property
    def Cm_B(self) -> np.ndarray:
        return frames.L_GB @ self.Cm_G

    def _per_panel(self, values) -> np.ndarray:
        return values if self._panel_index is None else values[self._panel_index]

    @functools.cached_property
    def _cos_delta(self) -> np.ndarray:
        # within [-1, 1]: a unit u and unit normals give |c| <= 1 only to rounding
        return np.clip(self._panel_values[0], -1.0, 1.0)

    @functools.cached_property
    def cos_delta(self) -> np.ndarray:
        return self._per_panel(self._cos_delta)

    @functools.cached_property
    def cp(self) -> np.ndarray:
        return self._per_panel(self._panel_values[1])

    @functools.cached_property
    def ctau(self) -> np.ndarray:
        _, _, ctau, shear, normals = self._panel_values
        if ctau is None:
            ctau = shear * sine_of_incidence(self.flow_direction, normals, self._cos_delta)
        return self._per_panel(ctau)

    @functools.cached_property
    def lit_fraction(self) -> np.ndarray:
        if self._lighting is not None:
            return self._lighting.lit_fraction
        return np.ones(self.cos_delta.shape)

    @property
    def drag(self) -> float:
        """Drag coefficient C_D = -Cf_w[0] (along the gas motion)."""
        return float(-self.Cf_w[0])

    @property
    def side_force(self) -> float:
        """Side-force coefficient C_Y = Cf_w[1]."""
        return float(self.Cf_w[1])

    @property
    def lift(self) -> float:
        """Lift coefficient C_L = -Cf_w[2]."""
        return float(-self.Cf_w[2])

    def force(self, dynamic_pressure: float) -> np.ndarray:
        """Force [N] in the mesh frame G for a dynamic pressure q = rho V^2 / 2 [Pa]."""
        return dynamic_pressure * self.reference.area * self.Cf_G

    def torque(self, dynamic_pressure: float) -> np.ndarray:
        """Torque [N m] in G about the moment point, for dynamic pressure q [Pa]."""
        return dynamic_pressure * self.reference.area * self.reference.length * self.Cm_G

    def to_dict(self, flow: FreeStream | None = None, per_panel: bool = False) -> dict:
        """A JSON-ready dict with ADBSat's names (angles in degrees, vectors as lists).

        With ``flow`` carrying a density, ``force_N`` and ``torque_Nm`` (mesh frame, about the
        moment point) and ``dynamic_pressure_Pa`` are added.
        """
        out = {
            "aoa_deg": math.degrees(self.aoa),
            "aos_deg": math.degrees(self.aos),
            "model": self.model,
            "Cf_w": self.Cf_w.tolist(),
            "Cf_f": self.Cf_f.tolist(),
            "Cm_B": self.Cm_B.tolist(),
            "Cf_G": self.Cf_G.tolist(),
            "Cm_G": self.Cm_G.tolist(),
            "CD": self.drag,
            "CL": self.lift,
            "CY": self.side_force,
            "Aref": self.reference.area,
            "Lref": self.reference.length,
            "moment_ref": list(self.reference.moment_point),
            "AreaProj": self.area_projected,
            "flow_direction_G": self.flow_direction.tolist(),
        }
        if flow is not None and flow.mass_density is not None:
            q = flow.dynamic_pressure()
            out["dynamic_pressure_Pa"] = q
            out["force_N"] = self.force(q).tolist()
            out["torque_Nm"] = self.torque(q).tolist()
        if per_panel:
            out["cp"] = self.cp.tolist()
            out["ctau"] = self.ctau.tolist()
            out["lit_fraction"] = self.lit_fraction.tolist()
        return out


class _Facets:
    """Coplanar panels of one material grouped into facets (see the module docstring).

    Attributes
    ----------
    index : ndarray of int, shape (N,)
        Facet of every panel.
    first : ndarray of int, shape (G,)
        One member panel of every facet (its normal and surface are the facet's).
    normals : ndarray, shape (G, 3)
        Outward unit normal of every facet (of its first member; members agree to 1e-12).
    inward_normals_T : ndarray, shape (3, G)
        ``-normals.T``, so that ``u @ inward_normals_T`` is every facet's cos(delta).
    """

    #: Normals equal to this many decimals (of a unit vector) make panels coplanar-facing.
    NORMAL_DECIMALS = 12
    #: Group only when it divides the work by at least this much.
    MIN_PANELS_PER_FACET = 2.0
    #: Read-only lightings (the shading cache's) whose facet sums are kept, oldest dropped first;
    #: as many as the cache keeps unpacked (shading_cache.RECENT_CELLS).
    MEMO_SIZE = 8

    def __init__(self, mesh: PanelMesh, index: np.ndarray, first: np.ndarray, surface):
        self.mesh = mesh
        self.index = index
        self.first = first
        self.n = len(first)
        self.normals = np.ascontiguousarray(mesh.normals[first])
        self.inward_normals_T = np.ascontiguousarray(-self.normals.T)
        self._areas = mesh.areas
        self._weighted_bary = mesh.areas[:, None] * mesh.barycentres
        self._all_lit = self._sums(mesh.areas, self._weighted_bary)
        self._surface = None
        self._facet_surface = self._facet_values(surface)
        self._surface = surface
        self._memo = {}  # id(lighting) -> (lighting, sums) of the MEMO_SIZE latest read-only lightings

    @classmethod
    def of(cls, mesh: PanelMesh, surface) -> "_Facets | None":
        """The facets of ``mesh``, or None if grouping would not save work (e.g. a sphere)."""
        key = np.column_stack([np.round(mesh.normals, cls.NORMAL_DECIMALS) + 0.0, mesh.material_index])
        _, first, index = np.unique(key, axis=0, return_index=True, return_inverse=True)
        if len(first) * cls.MIN_PANELS_PER_FACET > mesh.n_panels:
            return None
        return cls(mesh, index.reshape(-1), first, surface)

    def _sums(self, weights, weighted_bary):
        """Facet sums for panel weights w_i = f_i A_i and w_i (r_i + shift_i), as one (G, 10) matrix
        of columns W_g, W_g n_g, Q_g and Q_g x n_g (W = sum w_i, Q = sum w_i (r_i + shift_i))."""
        W = np.bincount(self.index, weights=weights, minlength=self.n)
        Q = np.stack([np.bincount(self.index, weights=weighted_bary[:, k], minlength=self.n) for k in range(3)],
                     axis=-1)
        sums = np.column_stack([W, W[:, None] * self.normals, Q, _cross(Q, self.normals)])
        sums.setflags(write=False)
        return sums

    def lit_sums(self, lighting):
        """The (G, 10) facet sums of :meth:`_sums` for a lighting (None: everything lit).

        Results for the latest :attr:`MEMO_SIZE` read-only lightings (what the shading cache hands
        out) are kept for later calls with the same objects.
        """
        if lighting is None:
            return self._all_lit
        kept = self._memo.get(id(lighting))
        if kept is not None and kept[0] is lighting:
            return kept[1]
        w = self._areas * lighting.lit_fraction
        wr = lighting.lit_fraction[:, None] * self._weighted_bary
        if lighting.shift_index.size:
            i = lighting.shift_index
            wr[i] += w[i, None] * lighting.shift
        sums = self._sums(w, wr)
        if not lighting.lit_fraction.flags.writeable:
            # kept with the lighting itself, so its id cannot be reused while the entry lives
            self._memo[id(lighting)] = (lighting, sums)
            if len(self._memo) > self.MEMO_SIZE:
                del self._memo[next(iter(self._memo))]
        return sums

    def surface_of(self, surface):
        """Facet values of a per-panel surface, or None if some parameter varies within a facet."""
        return self._facet_surface if surface is self._surface else self._facet_values(surface)

    def _facet_values(self, surface):
        from adbsat_ros.physics.surface import SURFACE_PARAMETERS, PanelSurface

        values = {}
        for name in SURFACE_PARAMETERS:
            value = getattr(surface, name)
            if type(value) is float or np.ndim(value) == 0:  # (the type test first: np.ndim costs ~1 us)
                values[name] = value
                continue
            if self._surface is not None and value is getattr(self._surface, name):
                # the materials' own array (e.g. a surface_with() that changed only alpha)
                values[name] = getattr(self._facet_surface, name)
                continue
            value = np.asarray(value)
            facet_value = value[self.first]
            if not np.array_equal(facet_value[self.index], value):
                return None
            values[name] = facet_value
        return PanelSurface(**values)


class PanelMethod:
    """A mesh with a gas-surface model and materials, ready to evaluate at any attitude.

    Construction does the per-mesh work once (per-panel parameter arrays, r x n products); each
    evaluation is a handful of vectorised numpy operations over the panels.

    Parameters
    ----------
    mesh : PanelMesh
        The satellite surface.
    model : str
        Gas-surface model name (see :data:`adbsat_ros.physics.gsi_models.MODELS`).
    materials : MaterialTable or SurfaceProperties, optional
        Surface properties by material name (default: alpha = sigma = 1, T_w = 300 K).
    options : ModelOptions, optional
        Incident-temperature form and ADBSat compatibility switches.
    reference : Reference, optional
        Reference area, length and moment point (default ADBSat's).
    group_facets : bool
        Evaluate the model once per facet of coplanar panels of one material (module docstring;
        the same result to rounding). False evaluates every panel, e.g. as a reference in tests.
    """

    def __init__(self, mesh: PanelMesh, model="sentman", materials=None, options=None, reference=None,
                 group_facets: bool = True):
        from adbsat_ros.physics.surface import SurfaceProperties

        self.mesh = mesh
        self.model = canonical_model_name(model)
        self._model_fn = get_model(self.model)
        self._split = SPLIT_MODELS.get(self.model)  # (parameters, plate), or None
        if materials is None:
            materials = MaterialTable()
        elif isinstance(materials, SurfaceProperties):
            materials = MaterialTable(materials)
        self.materials = materials
        self.options = options or ModelOptions()
        self.reference = (reference or Reference()).resolved(mesh)
        self.surface = materials.expand(mesh.material_names, mesh.material_index)
        self._normals = mesh.normals
        self._inward_normals_T = np.ascontiguousarray(-mesh.normals.T)
        self._areas = mesh.areas
        self._bary = mesh.barycentres
        self._r_cross_n = np.ascontiguousarray(np.cross(mesh.barycentres, mesh.normals))
        self._moment_point = np.asarray(self.reference.moment_point)
        self._facets = _Facets.of(mesh, self.surface) if group_facets else None

    @property
    def needs_species(self) -> bool:
        """True if the model needs the gas composition."""
        return self.model in SPECIES_MODELS

    # ------------------------------------------------------------------------------ per panel
    def surface_with(self, **changes):
        """Per-panel surface parameters with some set to one value on every panel.

        E.g. ``surface_with(alpha=0.9)`` when an accommodation model gives alpha from the
        atmosphere. Pass the result as ``surface=`` to :meth:`coefficients`.
        """
        from adbsat_ros.physics.surface import SURFACE_PARAMETERS, PanelSurface

        values = {name: getattr(self.surface, name) for name in SURFACE_PARAMETERS}
        for name, value in changes.items():
            if name not in values:
                raise ValueError(f"unknown surface parameter {name!r}")
            values[name] = float(value)
        return PanelSurface(**values)

    def panel_coefficients(self, u_G, flow: FreeStream, surface=None):
        """Incidence and local coefficients of every panel.

        Parameters
        ----------
        u_G : array_like, shape (3,) or (M, 3)
            Unit flow direction(s) in G.
        flow : FreeStream
        surface : PanelSurface, optional
            Surface parameters to use instead of the materials' (see :meth:`surface_with`).

        Returns
        -------
        cos_delta, sin_delta, cp, ctau : ndarray, shape (N,) or (M, N)
        """
        return self._local_coefficients(u_G, self._inward_normals_T, surface or self.surface, flow)

    def _local_coefficients(self, u_G, inward_normals_T, surface, flow):
        """c = cos(delta) = -u . n, sigma = sin(delta) and the model's cp, ctau for normals given as
        the (3, N) array -n^T."""
        u = np.asarray(u_G, dtype=float)
        c = u @ inward_normals_T
        np.minimum(c, 1.0, out=c)  # |c| <= 1 despite rounding
        np.maximum(c, -1.0, out=c)
        sigma = sine_of_incidence(u, inward_normals_T.T, c)
        cp, ctau = self._model_fn(c, sigma, surface, flow, self.options)
        return c, sigma, np.asarray(cp, dtype=float), np.asarray(ctau, dtype=float)

    def _facet_coefficients(self, u, facet_surface, flow):
        """c = cos(delta), c_p and c_tau / sin(delta) of every facet (shape (G,)) for one unit
        direction ``u``, and c_tau when the model gave it (else None).

        A model of :data:`gsi_models.SPLIT_MODELS` is its plate, which gives c_tau / sin(delta)
        itself: no sin(delta), and no clipping of c (within rounding of [-1, 1], where the plates
        are smooth). Other models are evaluated as over panels (:meth:`_local_coefficients`).
        """
        split = self._split
        parameters = None if split is None else split[0](facet_surface, flow, self.options)
        if parameters is None:
            c, sigma, cp, ctau = self._local_coefficients(u, self._facets.inward_normals_T, facet_surface, flow)
            return c, cp, _shear_per_sine(ctau, sigma), ctau
        c = u @ self._facets.inward_normals_T
        cp, shear = split[1](c, *parameters)  # (float arrays like c: the plates are elementwise)
        return c, cp, shear, None

    def _facet_totals(self, u, rows, lighting):
        """Cf_G, Cm_G and the lit projected area from the (3, G) rows (q, k, max(c, 0)) of
        :func:`_facet_rows`, q = c_tau / sin(delta) and k = q c - c_p per facet.

        Facet g carries the force W_g (q_g u + k_g n_g) (the shear along t = (u + c n) /
        sin(delta)) and the moment q_g (Q_g x u) + k_g (Q_g x n_g); so one product of the rows
        with the facet sums (W, W n, Q, Q x n) gives every sum needed.
        """
        sums = self._facets.lit_sums(lighting)
        (r_w, _, _, _, r_qx, r_qy, r_qz, _, _, _), (_, k_nx, k_ny, k_nz, _, _, _, k_mx, k_my, k_mz), \
            (area_projected, *_) = (rows @ sums).tolist()
        ux, uy, uz = u.tolist()
        fx, fy, fz = r_w * ux + k_nx, r_w * uy + k_ny, r_w * uz + k_nz
        px, py, pz = self.reference.moment_point
        # moment = (sum r Q) x u + sum k (Q x n) - r_ref x force
        mx = r_qy * uz - r_qz * uy + k_mx - (py * fz - pz * fy)
        my = r_qz * ux - r_qx * uz + k_my - (pz * fx - px * fz)
        mz = r_qx * uy - r_qy * ux + k_mz - (px * fy - py * fx)
        area = self.reference.area
        area_length = area * self.reference.length
        return (np.array([fx / area, fy / area, fz / area]),
                np.array([mx / area_length, my / area_length, mz / area_length]), area_projected)

    # ------------------------------------------------------------------------------ integration
    def integrate(self, u_G, c, sigma, cp, ctau, lighting: PanelLighting | None = None):
        """Sum panel loads into force and moment coefficients in G.

        Parameters
        ----------
        u_G : ndarray, shape (3,) or (M, 3)
            Flow direction(s) used for ``c`` (unit vectors, G).
        c, sigma, cp, ctau : ndarray, shape (N,) or (M, N)
            As returned by :meth:`panel_coefficients`.
        lighting : PanelLighting, optional
            Lit fractions and lit-centroid shifts (single direction only).

        Returns
        -------
        Cf_G, Cm_G : ndarray, shape (3,) or (M, 3)
            Coefficients in G, moments about the reference moment point.
        area_projected : float or ndarray, shape (M,)
            Lit projected area [m^2].
        """
        area = self._areas if lighting is None else self._areas * lighting.lit_fraction
        # Shear along t = (u + c n) / sin(delta): weight w_t multiplies (u + c n).
        w_t = np.divide(area * ctau, sigma, out=np.zeros_like(ctau), where=sigma > 0.0)
        g = w_t * c - area * cp  # coefficient of n_i in the panel force
        sum_w = w_t.sum(axis=-1)
        u = np.asarray(u_G, dtype=float)
        force = sum_w[..., None] * u + g @ self._normals
        moment = _cross(w_t @ self._bary, u) + g @ self._r_cross_n
        if lighting is not None and lighting.shift_index.size:
            i, d = lighting.shift_index, lighting.shift
            moment = moment + _cross(w_t[i] @ d, u) + g[i] @ _cross(d, self._normals[i])
        ref = self.reference
        moment = moment - _cross(self._moment_point, force)
        Cf = force / ref.area
        Cm = moment / (ref.area * ref.length)
        area_projected = (area * np.maximum(c, 0.0)).sum(axis=-1)
        return Cf, Cm, area_projected

    # ------------------------------------------------------------------------------ public API
    def coefficients(
        self,
        flow: FreeStream,
        aoa: float | None = None,
        aos: float | None = None,
        *,
        flow_direction=None,
        lighting: PanelLighting | None = None,
        surface=None,
    ) -> AeroCoefficients:
        """Coefficients at one attitude, given by angles or by the flow direction.

        Parameters
        ----------
        flow : FreeStream
            Free-stream gas (speed, temperature, composition).
        aoa, aos : float, optional
            Angle of attack and sideslip [rad] (frames module conventions).
        flow_direction : array_like, shape (3,), optional
            Direction of the gas motion relative to the body in G, instead of the angles.
        lighting : PanelLighting, optional
            Shading result for this flow direction (default: nothing occluded).
        surface : PanelSurface, optional
            Surface parameters overriding the materials' (see :meth:`surface_with`).
        """
        if flow_direction is not None:
            if aoa is not None or aos is not None:
                raise ValueError("give either aoa/aos or flow_direction, not both")
            u = _unit_direction(flow_direction)
            angles = None  # from u, when asked for
        else:
            aoa = 0.0 if aoa is None else float(aoa)
            aos = 0.0 if aos is None else float(aos)
            if not (math.isfinite(aoa) and math.isfinite(aos)):
                raise ValueError(f"aoa and aos must be finite, got {aoa!r}, {aos!r}")
            u = frames.flow_direction(aoa, aos)
            angles = (aoa, aos)
        return self._unit_coefficients(flow, u, lighting, surface, angles)

    def _unit_coefficients(self, flow: FreeStream, u: np.ndarray, lighting=None, surface=None,
                           angles=None) -> AeroCoefficients:
        """:meth:`coefficients` at the unit flow direction ``u`` (float array, shape (3,), G),
        taken as it is (the ROS node's per-message path, which makes ``u`` a unit vector itself);
        ``angles`` (aoa, aos) [rad] if ``u`` was made from them."""
        facets = self._facets
        facet_surface = None if facets is None else facets.surface_of(surface or self.surface)
        if facet_surface is not None:
            c, cp, shear, ctau = self._facet_coefficients(u, facet_surface, flow)
            Cf_G, Cm_G, area_proj = self._facet_totals(u, _facet_rows(c, cp, shear), lighting)
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

    def coefficients_many(self, flows, flow_directions, lightings=None, surfaces=None) -> list:
        """:meth:`coefficients` at several flow directions, each with its own free stream,
        lighting and surface: the same results, bit for bit, for less than the calls' cost.

        On a mesh grouped into facets, with a model of :data:`gsi_models.SPLIT_MODELS`, the
        incidences of all directions are laid out in one (M G,) array and the model's elementwise
        plate runs once over it; each direction's parameters (speed ratio, re-emission ...) and its
        final facet sums are its own, computed as :meth:`coefficients` computes them. Otherwise
        (a sphere, a species model, ADBSat's maxwell) each direction is evaluated on its own, as
        :meth:`coefficients` evaluates it.

        Parameters
        ----------
        flows : sequence of FreeStream
        flow_directions : sequence of array_like, shape (3,)
            Gas motion relative to the body in G, one per flow (normalised here).
        lightings : sequence of PanelLighting or None, optional
            Shading of each direction (None: nothing occluded).
        surfaces : sequence of PanelSurface or None, optional
            Surface parameters of each direction (None: the materials').

        Returns
        -------
        list of AeroCoefficients
            One per flow, in order.

        Raises
        ------
        ValueError
            If the sequences differ in length or a direction is not a finite non-zero 3-vector.
        """
        m = len(flows)
        lightings = [None] * m if lightings is None else list(lightings)
        surfaces = [None] * m if surfaces is None else list(surfaces)
        if not (len(flow_directions) == len(lightings) == len(surfaces) == m):
            raise ValueError(f"coefficients_many: {m} flows, {len(flow_directions)} flow_directions, "
                             f"{len(lightings)} lightings and {len(surfaces)} surfaces")
        return self._unit_coefficients_many(flows, [_unit_direction(d) for d in flow_directions], lightings, surfaces)

    def _unit_coefficients_many(self, flows, units, lightings, surfaces) -> list:
        """:meth:`coefficients_many` at unit flow directions ``units`` taken as they are, with a
        lighting and a surface (or None) for each: each result is :meth:`_unit_coefficients`'s,
        bit for bit."""
        m = len(flows)
        facets = self._facets
        split = self._split
        parameters = []
        if facets is not None and split is not None and m > 1:
            parameters_of, plate = split
            for flow, surface in zip(flows, surfaces):
                facet_surface = facets.surface_of(surface or self.surface)
                values = None if facet_surface is None else parameters_of(facet_surface, flow, self.options)
                if values is None:
                    break
                parameters.append(values)
        if len(parameters) < m or m < 2:
            return [self._unit_coefficients(flow, u, lighting, surface)
                    for flow, u, lighting, surface in zip(flows, units, lightings, surfaces)]
        # M directions' G facet values in one flat (M G,) array: numpy's fastest loops (a 2-D
        # broadcast costs several microseconds more per operation), the same value in each element
        g = facets.n
        c = np.concatenate([u @ facets.inward_normals_T for u in units])  # each its own (3,) @ (3, G)
        cp, shear = plate(c, *(_stacked(values, g) for values in zip(*parameters)))
        # (3, M G) rows made (M, 3, G): rows[k] the C-contiguous (3, G) rows of direction k
        rows = np.ascontiguousarray(_facet_rows(c, cp, shear).reshape(3, m, g).transpose(1, 0, 2))
        results = []
        for k, (u, lighting) in enumerate(zip(units, lightings)):
            Cf_G, Cm_G, area_proj = self._facet_totals(u, rows[k], lighting)
            own = slice(k * g, (k + 1) * g)
            results.append(AeroCoefficients(
                flow_direction=u, Cf_G=Cf_G, Cm_G=Cm_G, reference=self.reference,
                area_projected=float(area_proj), model=self.model,
                panel_values=(c[own], cp[own], None, shear[own], facets.normals),
                panel_index=facets.index, lighting=lighting, angles=None,
            ))
        return results
