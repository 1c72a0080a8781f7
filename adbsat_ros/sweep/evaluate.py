"""One chunk of a sweep, computed where a worker runs it.

:func:`compute_chunk` is the task: given the spec and the chunk's index ranges along every axis
it returns the chunk's results (:data:`VECTORS` with a trailing axis of 3, :data:`SCALARS`).
A worker builds a spec's :class:`SweepSetup` (mesh, panel method, shader) on its first task of
that spec and keeps it for the next ones (:data:`SETUPS`). Every point is computed from its own
inputs alone: exact ray-cast shading of its attitude (and joint configuration), no cache whose
contents depend on what came before, so a chunk gives the same numbers bit for bit on any
worker, in any order.
"""

from __future__ import annotations

import datetime as _dt
import itertools
import math

import numpy as np

from adbsat_ros.environment.atmosphere import SpaceWeather
from adbsat_ros.environment.circular_orbit import flight_conditions_circular_orbit
from adbsat_ros.geometry.loading import articulated_body, is_urdf, resolve_mesh
from adbsat_ros.lru import LruStore
from adbsat_ros.physics.articulated_method import ArticulatedMethod
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.physics.surface import MaterialTable, SurfaceProperties
from adbsat_ros.shading.shader import make_shader
from adbsat_ros.sweep.spec import ATMOSPHERE, ATMOSPHERE_DEFAULTS, DEFAULTS, SweepSpec

#: Results with x, y, z components: force and moment coefficients in the mesh (body) frame G,
#: in wind axes and in ADBSat's body axes B.
VECTORS = ("Cf_G", "Cm_G", "Cf_w", "Cm_B")
#: Scalar results: C_D, C_L, C_Y, the lit projected area [m^2], and the gas the point was
#: computed in: mass density [kg/m^3] (NaN unless the gas is the atmosphere's), temperature [K]
#: and speed [m/s].
SCALARS = ("CD", "CL", "CY", "area_projected", "density", "gas_temperature", "gas_speed")


class SweepSetup:
    """A spec's body, panel method and shading, made once per worker.

    Attributes
    ----------
    method : PanelMethod or ArticulatedMethod
    body : ArticulatedBody or None
    mesh : PanelMesh
        The body's panels (an articulated body's at zero joint positions).
    shaders : LruStore
        Shaders by joint configuration (one entry, ``()``, for a rigid body).
    """

    def __init__(self, spec: SweepSpec):
        self.spec = spec
        self.body = articulated_body(spec.mesh) if is_urdf(spec.mesh) else None
        self.mesh = self.body.mesh() if self.body is not None else resolve_mesh(spec.mesh)
        materials = MaterialTable.from_texts(SurfaceProperties(), spec.materials)
        unknown = materials.check_names(self.mesh.material_names)
        if unknown:
            raise ValueError(
                f"materials: the mesh has no material {', '.join(map(repr, unknown))}; its "
                f"materials are {', '.join(self.mesh.material_names)}"
            )
        ref = spec.reference
        reference = Reference(
            area=ref.get("area"),
            length=ref.get("length"),
            moment_point=tuple(ref.get("moment_point", (0.0, 0.0, 0.0))),
        )
        if self.body is None:
            self.method = PanelMethod(
                self.mesh, spec.model, materials, reference=reference, shading="none"
            )
        else:
            self.method = ArticulatedMethod(
                self.body, spec.model, materials, reference=reference, shading="none"
            )
        self.shaders = LruStore(8)

    def _shader(self, positions: dict):
        def make():
            mesh = self.mesh if self.body is None else self.body.mesh(positions)
            return make_shader(mesh, mode=self.spec.shading)

        return self.shaders.get(tuple(sorted(positions.items())), make)

    def flow(self, inputs: dict, flows: dict):
        """The free stream of a point: given (speed, temperature, mean mass), or the
        atmosphere's at a circular orbit (NRLMSISE-00 at the spec's time; ``speed`` if given,
        else the orbit's); ``flows`` holds those already made for this chunk."""
        spec = self.spec
        if not spec.atmosphere:
            return FreeStream(
                inputs["speed"], inputs["temperature"], mean_mass_amu=inputs["mean_mass_amu"]
            )
        values = {**ATMOSPHERE_DEFAULTS, **inputs}
        key = tuple(values[k] for k in ATMOSPHERE) + (inputs.get("speed"),)
        if key not in flows:
            weather = SpaceWeather(values["f107"], values["f107a"], values["ap"])
            conditions = flight_conditions_circular_orbit(
                _dt.datetime.fromisoformat(spec.time),
                1e3 * values["altitude"],
                math.radians(values["latitude"]),
                math.radians(values["longitude"]),
                weather,
                speed=inputs.get("speed"),
            )
            flows[key] = conditions.free_stream()
        return flows[key]

    def point(self, values: dict, lightings: dict, flows: dict):
        """The AeroCoefficients of one point (axis and fixed values in the spec's units);
        ``lightings`` holds the lightings already cast for this chunk, by attitude and joint
        positions."""
        spec = self.spec
        inputs = {**spec.fixed, **values}
        if not spec.atmosphere:
            inputs = {**DEFAULTS, **inputs}
        flow = self.flow(inputs, flows)
        aoa, aos = math.radians(inputs["aoa"]), math.radians(inputs["aos"])
        positions = {}
        for joint, axis in spec.joint_axes().items():
            kind = self.body.joints[joint].kind
            positions[joint] = inputs[axis] if kind == "prismatic" else math.radians(inputs[axis])
        changes = {k: inputs[k] for k in ("alpha", "wall_temperature") if k in inputs}
        surface = self.method.surface_with(**changes) if changes else None
        lighting = None
        if self.spec.shading != "none":  # (the same attitude and joints: the same rays)
            key = (aoa, aos, tuple(positions.values()))
            if key not in lightings:
                lightings[key] = self._shader(positions).lighting_angles(aoa, aos)
            lighting = lightings[key]
        if self.body is None:
            result = self.method.coefficients(flow, aoa, aos, lighting=lighting, surface=surface)
        else:
            result = self.method.coefficients(
                flow, positions, aoa, aos, lighting=lighting, surface=surface
            ).total
        return result, flow

    def evaluate(self, slices) -> dict:
        """The results of the block ``slices`` ((start, stop) per axis) of the grid."""
        names = list(self.spec.axes)
        ranges = [range(a, b) for a, b in slices]
        shape = tuple(len(r) for r in ranges)
        out = {name: np.empty((*shape, 3)) for name in VECTORS}
        out.update({name: np.empty(shape) for name in SCALARS})
        lightings, flows = {}, {}
        for local in itertools.product(*(range(n) for n in shape)):
            index = tuple(r[i] for r, i in zip(ranges, local))
            values = {n: float(self.spec.axes[n][i]) for n, i in zip(names, index)}
            r, flow = self.point(values, lightings, flows)
            out["Cf_G"][local] = r.Cf_G
            out["Cm_G"][local] = r.Cm_G
            out["Cf_w"][local] = r.Cf_w
            out["Cm_B"][local] = r.Cm_B
            out["CD"][local] = r.drag
            out["CL"][local] = r.lift
            out["CY"][local] = r.side_force
            out["area_projected"][local] = r.area_projected
            density = flow.mass_density
            out["density"][local] = math.nan if density is None else density
            out["gas_temperature"][local] = flow.temperature
            out["gas_speed"][local] = flow.speed
        return out


#: Setups of the latest specs on this process, by the spec's fingerprint: a worker builds a
#: spec's mesh and shader on its first chunk and keeps them for the rest.
SETUPS = LruStore(2)


def compute_chunk(spec: SweepSpec, slices) -> dict:
    """The task: the results of one chunk (:meth:`SweepSetup.evaluate`)."""
    setup = SETUPS.get(spec.fingerprint, lambda: SweepSetup(spec))
    return setup.evaluate(slices)
