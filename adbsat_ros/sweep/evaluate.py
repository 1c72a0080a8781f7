"""One chunk of a sweep, computed where a worker runs it.

A chunk is its index ranges along every axis, its result the chunk's :data:`VECTORS` and
:data:`SCALARS`. Every point is computed from its own inputs alone (exact ray-cast shading of
its attitude and joints, no cache whose contents depend on what came before), so a chunk gives
the same numbers bit for bit on any worker, in any order."""

from __future__ import annotations

import itertools
import math

import numpy as np

from adbsat_ros.database.build import attitude_seed
from adbsat_ros.lru import LruStore
from adbsat_ros.physics.constants import AMU
from adbsat_ros.physics.model import build_model
from adbsat_ros.sweep.gas import point_gas, point_inputs
from adbsat_ros.sweep.spec import SweepSpec, body_setup

#: Results with x, y, z components: force and moment coefficients in the mesh (body) frame G,
#: in wind axes, and the moment in ADBSat's body axes B.
VECTORS = ("Cf_G", "Cm_G", "Cf_w", "Cm_w", "Cm_B")
#: With test particles also their standard errors, of Cf_G and Cm_G.
ERRORS = ("Cf_G_error", "Cm_G_error")
#: Scalar results: C_D, C_L, C_Y, the lit projected area [m^2], and the gas the point was
#: computed in: mass density [kg/m^3] (NaN unless the gas is the atmosphere's), temperature [K],
#: speed [m/s], mean molecular mass [amu] and speed ratio.
SCALARS = (
    "CD",
    "CL",
    "CY",
    "area_projected",
    "density",
    "gas_temperature",
    "gas_speed",
    "gas_mean_mass",
    "speed_ratio",
)
#: Surface parameters a sweep may set on every panel.
SURFACE_AXES = ("alpha", "wall_temperature")


def vector_results(spec: SweepSpec) -> tuple:
    """The names of a sweep's results with x, y, z components."""
    return VECTORS + ERRORS if spec.tpmc is not None else VECTORS


class BodySetup:
    """One body of a sweep (its mesh, or one of its mesh variants): its model, with its shaders
    by joint configuration and test-particle solvers by configuration and surface (``LruStore``).

    Attributes
    ----------
    mesh : PanelMesh
        The body's panels (an articulated body's at zero joint positions).
    """

    def __init__(self, spec: SweepSpec, mesh: str):
        self.spec = spec
        self.model = build_model(body_setup(spec, mesh))
        self.body, self.mesh, self.method = self.model.body, self.model.mesh, self.model.method
        self.shaders = LruStore(8)
        self.solvers = LruStore(8)

    def shader(self, positions: dict):
        """The ray caster of the body at joint ``positions``."""
        key = tuple(sorted(positions.items()))
        return self.shaders.get(key, lambda: self.model.shader_at(positions))

    def solver(self, positions: dict, changes: dict):
        """The test-particle solver of the body at joint ``positions`` with the surface
        parameters ``changes``."""
        key = (tuple(sorted(positions.items())), tuple(sorted(changes.items())))
        return self.solvers.get(key, lambda: self.model.test_particles_at(positions, changes))


class SweepSetup:
    """A spec's bodies (one per mesh variant), made once per worker; ``body``, ``mesh`` and
    ``method`` are the first body's."""

    def __init__(self, spec: SweepSpec):
        self.spec = spec
        self.bodies = [BodySetup(spec, mesh) for mesh in spec.meshes or (spec.mesh,)]
        first = self.bodies[0]
        self.body, self.mesh, self.method = first.body, first.mesh, first.method

    def point(self, index: tuple, values: dict, lightings: dict, flows: dict):
        """The coefficients and the gas of one point (grid ``index``, axis ``values`` in the
        spec's units), with the lightings and gases already made for this chunk."""
        spec = self.spec
        inputs = point_inputs(spec, values)
        flow = point_gas(spec, inputs, flows)
        variant = int(inputs.get("mesh", 0))
        body = self.bodies[variant]
        aoa, aos = math.radians(inputs["aoa"]), math.radians(inputs["aos"])
        positions = {}
        for joint, axis in spec.joint_axes().items():
            kind = body.body.joints[joint].kind
            positions[joint] = inputs[axis] if kind == "prismatic" else math.radians(inputs[axis])
        changes = {k: inputs[k] for k in SURFACE_AXES if k in inputs}
        run = spec.tpmc
        if run is not None:
            seed = attitude_seed(run["seed"], int(np.ravel_multi_index(index, spec.shape)))
            return body.solver(positions, changes).coefficients(
                flow,
                aoa,
                aos,
                particles=run["particles"],
                tolerance=run["tolerance"],
                seed=seed,
            ), flow
        surface = body.method.surface_with(**changes) if changes else None
        lighting = None
        if spec.shading != "none":  # (the same body, attitude and joints: the same rays)
            key = (variant, aoa, aos, tuple(positions.values()))
            if key not in lightings:
                lightings[key] = body.shader(positions).lighting_angles(aoa, aos)
            lighting = lightings[key]
        if body.body is None:
            result = body.method.coefficients(flow, aoa, aos, lighting=lighting, surface=surface)
        else:
            result = body.method.coefficients(
                flow, positions, aoa, aos, lighting=lighting, surface=surface
            ).total
        return result, flow

    def evaluate(self, slices) -> dict:
        """The results of the block ``slices`` ((start, stop) per axis) of the grid."""
        names = list(self.spec.axes)
        ranges = [range(a, b) for a, b in slices]
        shape = tuple(len(r) for r in ranges)
        vectors = vector_results(self.spec)
        out = {name: np.empty((*shape, 3)) for name in vectors}
        out.update({name: np.empty(shape) for name in SCALARS})
        lightings, flows = {}, {}
        for local in itertools.product(*(range(n) for n in shape)):
            index = tuple(r[i] for r, i in zip(ranges, local))
            values = {n: float(self.spec.axes[n][i]) for n, i in zip(names, index)}
            r, flow = self.point(index, values, lightings, flows)
            for name in vectors:
                out[name][local] = getattr(r, name)
            out["CD"][local] = r.drag
            out["CL"][local] = r.lift
            out["CY"][local] = r.side_force
            out["area_projected"][local] = r.area_projected
            density = flow.mass_density
            out["density"][local] = math.nan if density is None else density
            out["gas_temperature"][local] = flow.temperature
            out["gas_speed"][local] = flow.speed
            out["gas_mean_mass"][local] = flow.mean_mass / AMU
            out["speed_ratio"][local] = flow.speed_ratio
        return out


class SweepJob:
    """A sweep as a job of :func:`adbsat_ros.tasks.run_chunks`: its chunks are index ranges
    ((start, stop) per axis); a worker builds the spec's :class:`SweepSetup` once."""

    def __init__(self, spec: SweepSpec):
        self.spec = spec
        self.key = "sweep " + spec.fingerprint

    def setup(self) -> SweepSetup:
        """The spec's set-up (mesh, panel method, shaders)."""
        return SweepSetup(spec=self.spec)
