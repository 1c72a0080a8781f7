"""The one builder of a configured body: :func:`build_model` turns a
:class:`~adbsat_ros.physics.setup.Setup` into a :class:`Model` (panels, panel method, one
shading cache, test-particle solver) that evaluates the body at any flow and joint positions."""

from __future__ import annotations

import math
from dataclasses import replace
from functools import cached_property

import numpy as np

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.loading import articulated_body, is_urdf, resolve_mesh
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.physics import model_evaluate as evaluation
from adbsat_ros.physics.articulated_method import ArticulatedMethod
from adbsat_ros.physics.model_evaluate import Joints
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.physics.setup import BodySpec, Setup
from adbsat_ros.physics.surface import MaterialTable
from adbsat_ros.shading.shader import make_shader


def load_body(spec: BodySpec, given=None) -> tuple:
    """``(body, mesh)``: a URDF's ArticulatedBody and None, or None and the rigid panels.

    Raises MeshError if the mesh or URDF cannot be loaded (or ``scale`` is set for a URDF).
    """
    if isinstance(given, tuple):
        return given
    if isinstance(given, ArticulatedBody):
        return given, None
    if spec.urdf:
        urdf = ArticulatedBody.from_urdf(
            spec.urdf, accept_size=spec.accept_size, source="robot_description"
        )
        return urdf, None
    if is_urdf(spec.mesh):
        if spec.scale != 1.0:
            resolve_mesh(spec.mesh, spec.scale)  # (refuses it, naming the mesh)
        return articulated_body(spec.mesh, spec.accept_size), None
    if given is None:
        given = resolve_mesh(spec.mesh, spec.scale, spec.accept_size)
    return None, given


class Model:
    """A set-up built: its panels, panel method, one shading cache and test-particle solver.

    ``body``: the URDF body (posed at ``positions`` [rad or m], or moving), None for a mesh;
    ``lookup``: a database's ``lookup(u) -> (Cf_G, Cm_G)`` or None.
    """

    def __init__(self, setup: Setup, body, mesh: PanelMesh, positions: dict | None):
        self.setup, self.body, self.mesh, self.positions = setup, body, mesh, positions
        self.lookup = self._solver = None
        self.materials = setup.materials()
        unknown = self.materials.check_names(mesh.material_names)
        if unknown:
            label = setup.label("materials") or f"materials: the mesh {setup.body.mesh}"
            raise ValueError(
                f"{label}: the mesh has no material {', '.join(map(repr, unknown))}; "
                f"its materials are {', '.join(mesh.material_names)}"
            )
        # (the moment point near the body: docs/physics.md section 11)
        reference = setup.reference.resolved(mesh, setup.label("moment_point"))
        if self.articulated:
            self.method = ArticulatedMethod(
                body,
                setup.model,
                self.materials,
                options=setup.options,
                reference=reference,
                shading="none",
            )
        else:
            self.method = PanelMethod(
                mesh, setup.model, self.materials, options=setup.options, reference=reference
            )
        if setup.solver.method != "panel":
            self.test_particles({}, {})  # (a model without a kernel is refused here)

    @property
    def articulated(self) -> bool:
        """Whether the joints move (an ArticulatedMethod)."""
        return self.body is not None and self.positions is None

    @property
    def backend(self) -> str:
        """What :meth:`evaluate` uses: ``database``, ``tpmc``, ``articulated`` or ``panel``."""
        if self.lookup is not None:
            return "database"
        if self.setup.solver.method == "tpmc":
            return "tpmc"
        return "articulated" if self.articulated else "panel"

    @cached_property
    def shader(self):
        """The shader of the panels by the set-up's policy (None for ``none``), made once."""
        policy = self.setup.shading
        if policy.mode == "none":
            return None
        return make_shader(self.mesh, mode=policy.mode, samples=policy.samples)

    @cached_property
    def cache(self):
        """The one ShadingCache of the panel method, made at first read; None without shading or
        lookup."""
        return None if self.lookup is not None else evaluation.make_cache(self)

    @cached_property
    def _all_lit(self):
        return evaluation.all_lit_cell(self.method, self.articulated)

    def test_particles(self, positions: dict, changes: dict):
        """The test-particle solver at joint ``positions`` [rad or m] with surface ``changes``; the
        latest kept."""
        from adbsat_ros.physics.tpmc.method import TestParticleMethod

        key = (tuple(sorted(positions.items())), tuple(sorted(changes.items())))
        kept = self._solver
        if kept is not None and kept[0] == key:
            return kept[1]
        table = self.materials
        if changes:
            table = MaterialTable(
                replace(table.default, **changes),
                {k: replace(v, **changes) for k, v in table.materials.items()},
            )
        mesh = self.body.mesh(positions) if self.articulated else self.mesh
        reference = self.method.reference
        solver = self.setup.prefixed(
            "solver", lambda: TestParticleMethod(mesh, self.setup.model, table, reference=reference)
        )
        self._solver = (key, solver)
        return solver

    # ------------------------------------------------------------------------------ evaluation
    def prepare_joints(self, positions=None) -> Joints:
        """Joint ``positions`` [rad or m] checked, posed and placed on the cache's grid."""
        configuration = self.method.configuration(positions)
        cache = self.cache
        vertices = None if cache is None else cache.vertices(configuration.positions)
        return Joints(configuration.positions, configuration, vertices)

    def evaluate(
        self,
        free_stream,
        flow_direction=None,
        joints=None,
        *,
        angles=None,
        changes=None,
        seed=None,
        solver=None,
        **run,
    ):
        """The coefficients of the body in ``free_stream`` (a FreeStream).

        flow_direction: gas motion relative to the body (body frame), (3,), or ``angles``.
        joints: :meth:`prepare_joints`' result, or positions [rad or m] (others at zero).
        angles: angle of attack and sideslip [rad] instead of ``flow_direction``.
        changes: surface parameters set on every panel (:meth:`PanelMethod.surface_with`).
        solver: ``"panel"`` or ``"tpmc"`` for a set-up with both (default :attr:`backend`).
        **run: the test particles' ``workers``, ``progress`` and ``stop``.
        Returns AeroCoefficients, ArticulatedCoefficients or TpmcCoefficients.
        ValueError: a bad direction, angle, joint position or surface change, or outside the
        database.
        """
        u, given = None, None
        if angles is None and type(flow_direction) is np.ndarray:  # (a message's gas motion)
            u = evaluation.unit_of_array(flow_direction)
        if u is None:  # (anything else, checked and named as frames.attitude_flow does)
            aoa, aos = (None, None) if angles is None else angles
            u, given = frames.attitude_flow(aoa, aos, flow_direction)
        if solver is None:
            if self.setup.solver.method == "tpmc" and self.lookup is None:
                solver = "tpmc"
        elif solver not in ("panel", "tpmc"):
            raise ValueError(f"solver must be panel or tpmc, got {solver!r}")
        if solver == "tpmc":
            return self._test_particles(
                free_stream, flow_direction, angles, joints, changes, seed, run
            )
        method = self.method
        if self.lookup is not None:
            return evaluation.looked_up_coefficients(self.lookup, method, u, given)
        surface = method.surface_with(**changes) if changes else None
        direction = u if flow_direction is None else flow_direction  # (as the caller gave it)
        if self.body is None or self.positions is not None:  # (not articulated)
            parts = self._read(direction)
            return evaluation.rigid_coefficients(method, free_stream, u, given, parts, surface)
        if not isinstance(joints, Joints):
            joints = self.prepare_joints(joints)
        parts = self._read(direction, joints.vertices)
        return evaluation.articulated_coefficients(
            method, free_stream, u, given, joints.configuration, parts, surface
        )

    def prepare(self, angles) -> None:
        """Shade the attitudes ``angles`` [(aoa, aos) rad, ...] about to be evaluated in one
        call (a rigid body's; the same numbers as one at a time)."""
        if self.cache is not None and self.lookup is None:
            self.cache.prepare([frames.attitude_flow(a, b)[0] for a, b in angles])

    def _read(self, direction, vertices=None, count: bool = True) -> list:
        """``[(weight, Cell), ...]`` of a flow ``direction``."""
        cache = self.cache
        if cache is None:
            return [(1.0, self._all_lit)]
        return cache.read(direction, vertices, count)

    def _test_particles(self, flow, flow_direction, angles, joints, changes, seed, run):
        """The test particles' coefficients (the set-up's particles and tolerance)."""
        positions = {}
        if self.articulated:
            positions = joints.positions if isinstance(joints, Joints) else dict(joints or {})
        solver = self.test_particles(positions, changes or {})
        spec = self.setup.solver
        aoa, aos = (None, None) if angles is None else angles
        return solver.coefficients(
            flow,
            aoa,
            aos,
            flow_direction=flow_direction,
            particles=spec.particles,
            tolerance=spec.tolerance,
            seed=spec.seed if seed is None else seed,
            **run,
        )

    def solar(self, sun_direction_body):
        """Solar radiation pressure coefficients for the Sun direction (body frame); not
        articulated."""
        if self.articulated:
            raise ValueError(
                "solar radiation pressure is computed for rigid bodies only, not for an "
                "articulated body"
            )
        # (photons travel away from the Sun)
        parts = self._read(-np.asarray(sun_direction_body, dtype=float), count=False)
        return evaluation.solar_of_cells(self.method, sun_direction_body, parts)

    # ------------------------------------------------------------------------------ variants
    def with_setup(self, setup: Setup) -> "Model":
        """The model of ``setup``, reusing this one's body, panels and shading cache where they
        match."""
        if setup.body != self.setup.body:
            return build_model(setup)
        model = Model(setup, self.body, self.mesh, self.positions)
        if setup.shading == self.setup.shading:
            for name in ("shader", "cache"):
                if name in self.__dict__:
                    model.__dict__[name] = self.__dict__[name]
        return model

    def with_lookup(self, lookup) -> "Model":
        """This model evaluated by a database ``lookup(u) -> (Cf_G, Cm_G)`` (body frame)."""
        model = Model.__new__(Model)
        model.__dict__.update(
            {k: v for k, v in self.__dict__.items() if k not in ("cache", "_all_lit")}
        )
        model.lookup = lookup
        return model


def build_model(setup: Setup, given=None) -> Model:
    """The :class:`Model` of ``setup`` (``given``: body already loaded, as :func:`load_body` takes
    it).

    MeshError: the mesh or URDF cannot be loaded.
    ValueError: bad joint positions, a material the mesh lacks, a far moment point, or no TPMC
    kernel.
    """
    body, mesh = load_body(setup.body, given)
    positions = None
    if body is not None and setup.body.joints is not None:
        values = {}
        for name, value in setup.body.joints:
            joint = body.joints.get(name)
            angular = joint is not None and joint.kind != "prismatic"
            values[name] = math.radians(value) if angular and setup.body.joint_degrees else value
        try:
            mesh = body.mesh(values)
        except ValueError as exc:  # (the limits in radians: a revolute position was converted)
            raise ValueError(f"{setup.label('joints')}: {exc}") from None
        positions = body.positions(values)
    elif body is not None and mesh is None:
        mesh = body.mesh()
    return Model(setup, body, mesh, positions)
