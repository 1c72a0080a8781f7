"""The one builder of a configured body: :func:`build_model` turns a
:class:`~adbsat_ros.physics.setup.Setup` into a :class:`Model` (panels, panel method, shader and
test-particle solver).

The command line, the estimator, database metadata, sweeps and the demo all build their body
here.
"""

from __future__ import annotations

import math
from dataclasses import replace
from functools import cached_property

from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.loading import articulated_body, is_urdf, resolve_mesh
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.physics.articulated_method import ArticulatedMethod
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.physics.setup import BodySpec, Setup
from adbsat_ros.physics.surface import MaterialTable
from adbsat_ros.shading.shader import make_shader


def load_body(spec: BodySpec, given=None) -> tuple:
    """``(body, mesh)``: the ArticulatedBody of a URDF (``spec.urdf``, or a URDF ``spec.mesh``)
    and None, or None and the rigid panels. An ArticulatedBody ``given`` is taken as it is; a
    PanelMesh ``given`` stands for the panels of a mesh file or bundled body (not a URDF); a
    pair ``given`` is ``(body, mesh)`` loaded already.

    Raises
    ------
    MeshError
        If the mesh or URDF cannot be loaded (or ``scale`` is set for a URDF).
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
    """A set-up built: its panels, panel method, shader and test-particle solver.

    Attributes
    ----------
    setup : Setup
    body : ArticulatedBody or None
        The URDF body (posed once at ``positions``, or moving: ``method`` is then an
        :class:`ArticulatedMethod`), None for a mesh.
    positions : dict or None
        Every joint's position [rad or m] of a URDF posed once; None otherwise.
    mesh : PanelMesh
        The panels (posed; an articulated body's at zero joint positions).
    materials : MaterialTable
    method : PanelMethod or ArticulatedMethod
    """

    def __init__(self, setup: Setup, body, mesh: PanelMesh, positions: dict | None):
        self.setup, self.body, self.mesh, self.positions = setup, body, mesh, positions
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
            self.test_particles  # (a model without a kernel is refused here)

    @property
    def articulated(self) -> bool:
        """Whether the joints move (an ArticulatedMethod)."""
        return self.body is not None and self.positions is None

    @cached_property
    def shader(self):
        """The shader of the panels by the set-up's policy (None for ``none``), made once."""
        policy = self.setup.shading
        if policy.mode == "none":
            return None
        return make_shader(self.mesh, mode=policy.mode, samples=policy.samples)

    def shader_at(self, positions: dict):
        """The shader of the body at joint ``positions`` [rad or m] (of a rigid body: its own)."""
        if not self.articulated:
            return self.shader
        # (no topology store: each configuration's posed panels would be another entry)
        posed = self.body.mesh(positions)
        policy = self.setup.shading
        return make_shader(posed, mode=policy.mode, samples=policy.samples, topology_store=None)

    @cached_property
    def test_particles(self):
        """The :class:`TestParticleMethod` of the panels (ValueError naming ``solver`` for a
        model without a test-particle kernel)."""
        return self.test_particles_at({}, {})

    def test_particles_at(self, positions: dict, changes: dict):
        """The test-particle solver of the body at joint ``positions``, with the surface
        parameters ``changes`` on every panel."""
        from adbsat_ros.physics.tpmc.method import TestParticleMethod

        table = self.materials
        if changes:
            table = MaterialTable(
                replace(table.default, **changes),
                {k: replace(v, **changes) for k, v in table.materials.items()},
            )
        mesh = self.body.mesh(positions) if self.articulated else self.mesh
        reference = self.method.reference
        return self.setup.prefixed(
            "solver", lambda: TestParticleMethod(mesh, self.setup.model, table, reference=reference)
        )


def build_model(setup: Setup, given=None) -> Model:
    """The :class:`Model` of ``setup``: the mesh or URDF loaded (``given``: already loaded,
    as :func:`load_body` takes it), a URDF posed at ``setup.body.joints`` unless they move.

    Raises
    ------
    MeshError
        If the mesh or URDF cannot be loaded.
    ValueError
        Naming (:attr:`Setup.labels`) joint positions the URDF refuses, a material the mesh
        does not have, a moment point far from the body or a model without a test-particle
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
