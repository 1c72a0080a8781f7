"""One chunk of a sweep (index ranges along every axis), computed where a worker runs it.

Every point from its own inputs alone (exact shading, the model's cache in exact mode), so a
chunk gives the same numbers bit for bit on any worker, in any order.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import replace

import numpy as np

from adbsat_ros.database.build import attitude_seed
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


def attitudes_per_chunk(spec: SweepSpec) -> int:
    """At most the distinct attitudes and joint positions of a chunk of ``spec``."""
    shaded = ("aoa", "aos", *spec.joint_axes().values())
    count = math.prod(len(values) for axis, values in spec.axes.items() if axis in shaded)
    return max(1, min(spec.chunk_points, count))


def body_model(spec: SweepSpec, mesh: str):
    """The model of one body (or mesh variant) of a sweep, keeping a chunk's lightings."""
    setup = body_setup(spec, mesh)
    shading = replace(setup.shading, exact_offline=attitudes_per_chunk(spec))
    return build_model(replace(setup, shading=shading))


class SweepSetup:
    """A spec's bodies, a model per mesh variant, made once per worker."""

    def __init__(self, spec: SweepSpec):
        self.spec = spec
        self.bodies = [body_model(spec, mesh) for mesh in spec.meshes or (spec.mesh,)]
        first = self.bodies[0]
        self.body, self.mesh, self.method = first.body, first.mesh, first.method

    def point(self, index: tuple, values: dict, flows: dict):
        """The coefficients and gas of one point (axis ``values`` in the spec's units)."""
        spec = self.spec
        inputs = point_inputs(spec, values)
        flow = point_gas(spec, inputs, flows)
        model = self.bodies[int(inputs.get("mesh", 0))]
        angles = (math.radians(inputs["aoa"]), math.radians(inputs["aos"]))
        positions = {}
        for joint, axis in spec.joint_axes().items():
            kind = model.body.joints[joint].kind
            positions[joint] = inputs[axis] if kind == "prismatic" else math.radians(inputs[axis])
        changes = {k: inputs[k] for k in SURFACE_AXES if k in inputs}
        seed = None
        if spec.tpmc is not None:
            seed = attitude_seed(spec.tpmc["seed"], int(np.ravel_multi_index(index, spec.shape)))
        result = model.evaluate(flow, None, positions, angles=angles, changes=changes, seed=seed)
        return (result.total if model.backend == "articulated" else result), flow

    def evaluate(self, slices) -> dict:
        """The results of the block ``slices`` ((start, stop) per axis) of the grid."""
        names = list(self.spec.axes)
        ranges = [range(a, b) for a, b in slices]
        shape = tuple(len(r) for r in ranges)
        vectors = vector_results(self.spec)
        out = {name: np.empty((*shape, 3)) for name in vectors}
        out.update({name: np.empty(shape) for name in SCALARS})
        flows, points = {}, []
        for local in itertools.product(*(range(n) for n in shape)):
            index = tuple(r[i] for r, i in zip(ranges, local))
            points.append(
                (local, index, {n: float(self.spec.axes[n][i]) for n, i in zip(names, index)})
            )
        if self.spec.tpmc is None:  # (each body's attitudes of the chunk shaded in one call)
            angles = {}
            for _, _, values in points:
                inputs = point_inputs(self.spec, values)
                attitude = (math.radians(inputs["aoa"]), math.radians(inputs["aos"]))
                angles.setdefault(int(inputs.get("mesh", 0)), {})[attitude] = None
            for body, chunk_angles in angles.items():
                self.bodies[body].prepare(list(chunk_angles))
        for local, index, values in points:
            r, flow = self.point(index, values, flows)
            for name in vectors:
                out[name][local] = getattr(r, name)
            density = math.nan if flow.mass_density is None else flow.mass_density
            gas = (density, flow.temperature, flow.speed, flow.mean_mass / AMU, flow.speed_ratio)
            for name, value in zip(SCALARS, (r.drag, r.lift, r.side_force, r.area_projected, *gas)):
                out[name][local] = value
        return out
