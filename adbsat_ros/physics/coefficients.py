"""Reference quantities and the panel method's result: force and moment coefficients in the mesh
frame G, and on demand in ADBSat's wind, flight, body frames (:mod:`adbsat_ros.geometry.frames`)."""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from adbsat_ros.bounds import body_point
from adbsat_ros.geometry import frames
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.incidence import sine_of_incidence
from adbsat_ros.shading.lighting import PanelLighting


@dataclass(frozen=True)
class Reference:
    """Reference quantities of the coefficients; None means ADBSat's default. area: A_ref [m^2],
    default half the total wetted area (ADBSat's, not the projected area); length: L_ref [m],
    default the mesh's x-extent; moment_point: mesh frame [m], (3,), default the mesh origin."""

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
            raise ValueError(
                f"moment_point must be three finite numbers, got {self.moment_point!r}"
            )
        object.__setattr__(self, "moment_point", tuple(float(v) for v in point))

    def resolved(self, mesh: PanelMesh, name: str = "moment_point") -> "Reference":
        """A copy with ``mesh``'s defaults; ValueError if the moment point is ten body sizes off."""
        body_point(name, self.moment_point, *mesh.bounds.tolist())
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
    """Aerodynamic coefficients of one attitude; other axes and per-panel values computed on access.
    flow_direction: unit gas motion relative to the body, G; Cf_G, Cm_G: in G, moments about
    ``reference.moment_point``; area_projected: lit area normal to the flow [m^2] (``AreaProj``)."""

    def __init__(
        self,
        flow_direction,
        Cf_G,
        Cm_G,
        reference: Reference,
        area_projected: float,
        model: str,
        panel_values,
        panel_index=None,
        lighting: PanelLighting | None = None,
        angles=None,
    ):
        self.flow_direction = flow_direction
        self.Cf_G = Cf_G
        self.Cm_G = Cm_G
        self.reference = reference
        self.area_projected = area_projected
        self.model = model
        # (cos_delta, cp, ctau, ctau / sin(delta), normals) per panel, or per facet by panel_index;
        # ctau None: made from ctau / sin(delta) and the (G, 3) facet normals when asked for (else
        # those two are None); or a no-argument function returning that tuple when first needed
        self._panel_source = panel_values
        self._panel_index = panel_index
        self._lighting = lighting
        self._angles = angles

    def __repr__(self) -> str:
        return (
            f"AeroCoefficients(model={self.model!r}, aoa={self.aoa!r}, aos={self.aos!r}, "
            f"Cf_G={self.Cf_G!r}, Cm_G={self.Cm_G!r}, area_projected={self.area_projected!r})"
        )

    @functools.cached_property
    def _panel_values(self) -> tuple:
        source = self._panel_source  # (the tuple, or what makes it when first asked for)
        return source() if callable(source) else source

    @functools.cached_property
    def _angles_rad(self) -> tuple:
        if self._angles is not None:
            return self._angles
        return tuple(float(a) for a in frames.angles_of_flow(self.flow_direction))

    @property
    def aoa(self) -> float:
        """Angle of attack [rad] of the flow (frames module)."""
        return self._angles_rad[0]

    @property
    def aos(self) -> float:
        """Angle of sideslip [rad] of the flow (frames module)."""
        return self._angles_rad[1]

    @functools.cached_property
    def _Cf_B(self) -> np.ndarray:
        return frames.L_GB @ self.Cf_G

    @functools.cached_property
    def _body_to_wind(self) -> np.ndarray:
        """L_WB, first row from the flow direction itself (cos(aos) rounds to 0 at +-90 deg)."""
        matrix = frames.body_to_wind(self.aoa, self.aos)
        matrix[0] = frames.L_GB @ -np.asarray(self.flow_direction, dtype=float)
        return matrix

    @functools.cached_property
    def Cf_w(self) -> np.ndarray:
        """Force coefficient in wind axes (ADBSat ``Cf_w``; drag = -Cf_w[0])."""
        return self._body_to_wind @ self._Cf_B

    @functools.cached_property
    def Cm_w(self) -> np.ndarray:
        """Moment coefficient in wind axes about the moment point."""
        return self._body_to_wind @ (frames.L_GB @ self.Cm_G)

    @functools.cached_property
    def Cf_f(self) -> np.ndarray:
        """Force coefficient in ADBSat's flight axes (``Cf_f``; x aft, z up)."""
        return frames.L_FB @ self._Cf_B

    @functools.cached_property
    def Cm_B(self) -> np.ndarray:
        """Moment coefficient in ADBSat's body axes B about the moment point."""
        return frames.L_GB @ self.Cm_G

    def _per_panel(self, values) -> np.ndarray:
        return values if self._panel_index is None else values[self._panel_index]

    @functools.cached_property
    def _cos_delta(self) -> np.ndarray:
        # within [-1, 1]: a unit u and unit normals give |c| <= 1 only to rounding
        return np.clip(self._panel_values[0], -1.0, 1.0)

    @functools.cached_property
    def cos_delta(self) -> np.ndarray:
        """Incidence cosine -u . n of every panel, in [-1, 1]."""
        return self._per_panel(self._cos_delta)

    @functools.cached_property
    def cp(self) -> np.ndarray:
        """Local pressure coefficient of every panel (before shading)."""
        return self._per_panel(self._panel_values[1])

    @functools.cached_property
    def ctau(self) -> np.ndarray:
        """Local shear coefficient of every panel (before shading)."""
        _, _, ctau, shear, normals = self._panel_values
        if ctau is None:
            ctau = shear * sine_of_incidence(self.flow_direction, normals, self._cos_delta)
        return self._per_panel(ctau)

    @property
    def lighting(self) -> PanelLighting | None:
        """The shading used, or None for none."""
        return self._lighting

    @functools.cached_property
    def lit_fraction(self) -> np.ndarray:
        """Lit fraction of every panel (all ones without shading)."""
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
        """A JSON-ready dict, ADBSat's names (angles [deg]); with ``flow``, force and torque too."""
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
