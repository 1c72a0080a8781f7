"""The panel method of an articulated body, exact at every joint configuration.

Each link's panels are rigid in the link's own frame, so the link is evaluated there, with a
:class:`~adbsat_ros.physics.panel_method.PanelMethod` made once: for link l at pose (R_l, t_l) in
the body frame G and the flow direction u (G), its coefficients about its own origin are those of
its panels at u_l = R_l^T u, and in the body frame (section 8 of docs/physics.md)

    F_l = R_l Cf_l,    M_l = R_l Cm_l + (t_l - r_ref) x F_l / L_ref,

summed over the links to the body's Cf_G and Cm_G. Nothing is rebuilt when a joint moves: the
geometry is exact at any joint positions, and a wrench costs one evaluation per link with
geometry. The effort on a joint is the moment of the loads of the links it carries about its
axis through the joint (revolute, continuous) or their force along it (prismatic).

The same numbers, to rounding, as a :class:`PanelMethod` of
:meth:`~adbsat_ros.geometry.articulated.ArticulatedBody.mesh` at those positions (tested).
Shading is the only thing that depends on the configuration as a whole (one part shades
another): the lighting of the posed body, panels in the order of
:meth:`~adbsat_ros.geometry.articulated.ArticulatedBody.mesh`, is split by link.

Units: metres, radians; frame G = the root link's frame.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.poses import PoseCache
from adbsat_ros.physics.coefficients import AeroCoefficients, Reference
from adbsat_ros.physics.facets import facet_rows
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.panel_method import OWN_SHADING, PanelMethod
from adbsat_ros.physics.posed_facets import PosedFacets
from adbsat_ros.shading.link_split import LinkSplitCache
from adbsat_ros.shading.shader import MODES as SHADING_MODES
from adbsat_ros.shading.shader import make_shader


@dataclass(frozen=True)
class ArticulatedCoefficients:
    """The coefficients of an articulated body at one configuration and flow direction.

    Attributes
    ----------
    total : AeroCoefficients
        The whole body's (as :meth:`PanelMethod.coefficients` of the posed mesh: Cf_G, Cm_G,
        area_projected, wind axes, and per-panel values in the posed mesh's order).
    link_force, link_moment : ndarray, shape (L, 3)
        Force and moment coefficient of every link of the body (zero for links without
        geometry), body frame, moments about the reference moment point; they sum to the total.
    joint_effort : dict of str to float
        For each moving joint, the moment coefficient of the loads on the links it carries
        about its axis through it (revolute, continuous; times q A_ref L_ref: N m), or their
        force coefficient along its axis (prismatic; times q A_ref: N).
    positions : dict of str to float
        The joint positions [rad or m].
    joint_kinds : dict of str to str
        Each moving joint's type (revolute, continuous, prismatic).
    """

    total: AeroCoefficients
    link_force: np.ndarray
    link_moment: np.ndarray
    joint_effort: dict
    positions: dict
    joint_kinds: dict

    def joint_efforts(self, dynamic_pressure: float) -> dict:
        """Joint efforts [N m, or N for a prismatic joint] at dynamic pressure q [Pa]."""
        ref = self.total.reference
        return {
            name: dynamic_pressure
            * ref.area
            * (1.0 if self.joint_kinds[name] == "prismatic" else ref.length)
            * value
            for name, value in self.joint_effort.items()
        }


class ArticulatedMethod:
    """The panel method of an :class:`ArticulatedBody` at any joint positions.

    Parameters
    ----------
    body : ArticulatedBody
    model, materials, options, group_facets
        As for :class:`PanelMethod` (the materials by the URDF's material names).
    reference : Reference, optional
        A_ref, L_ref and moment point (body frame); unset values as :class:`PanelMethod` sets
        them for the body at zero joint positions.
    shading : {"raycast", "projection", "none"}
        How :meth:`coefficients` shades the posed body when given no ``lighting``.
    """

    def __init__(
        self,
        body: ArticulatedBody,
        model: str = "sentman",
        materials=None,
        *,
        options=None,
        reference=None,
        group_facets: bool = True,
        shading: str = "raycast",
    ):
        if shading not in SHADING_MODES:
            raise ValueError(f"shading must be one of {', '.join(SHADING_MODES)}, got {shading!r}")
        self.body = body
        self.shading = shading
        zero = body.mesh()
        self.reference = (reference or Reference()).resolved(zero)
        own = Reference(area=self.reference.area, length=self.reference.length)
        self._links = []  # (link index, first panel, end, its method in its frame)
        for link, (start, stop) in sorted(body.link_spans.items()):
            method = PanelMethod(
                body.link_mesh(link),
                model,
                materials,
                options=options,
                reference=own,
                group_facets=group_facets,
                shading="none",
            )
            self._links.append((link, start, stop, method))
        self.model = self._links[0][3].model
        self.n_panels = zero.n_panels
        self._link_index = np.array([link for link, *_ in self._links])
        evaluated = {link: k for k, link in enumerate(self._link_index.tolist())}
        # each joint's carried links with geometry, as indices of the evaluated links
        self._carries = np.zeros((len(body.joints), len(self._links)))  # joint j carries link
        for j, name in enumerate(body.joints):
            for link in body.carried_links(name):
                if link in evaluated:
                    self._carries[j, evaluated[link]] = 1.0
        self._kinds = {name: joint.kind for name, joint in body.joints.items()}
        self._moment_point = np.asarray(self.reference.moment_point)
        self._prismatic = np.array([j.kind == "prismatic" for j in body.joints.values()], bool)
        #: The links' and joints' frames of the latest configurations.
        self.poses = PoseCache(body)
        #: The lightings of the posed body split by link, in the links' frames.
        self.splits = LinkSplitCache([(start, stop) for _, start, stop, _ in self._links])
        methods = [method for *_, method in self._links]
        #: The links' facets posed in the body frame (None if a link is evaluated panel by
        #: panel; then every link is evaluated in its own frame).
        self.facets = PosedFacets.of(methods, self.splits)
        self._evaluator = methods[0]  # (every link has the model and options)
        self._facet_surface = None
        if self.facets is not None:
            self._facet_surface = self.facets.surface([m.surface for m in methods])
        # r_ref x F = -(F @ cross(I, r_ref)), row by row
        self._cross_point = np.cross(np.eye(3), self._moment_point)

    @property
    def needs_species(self) -> bool:
        """Whether the model needs the gas composition (as :attr:`PanelMethod.needs_species`)."""
        return self._links[0][3].needs_species

    def surface_with(self, **changes) -> tuple:
        """Per-link surface parameters with some set to one value (see
        :meth:`PanelMethod.surface_with`); pass as ``surface=`` to :meth:`coefficients`."""
        return tuple(method.surface_with(**changes) for *_, method in self._links)

    def lighting_of(self, u_G, positions=None):
        """The method's own ``shading`` of the body posed at ``positions``, for flow direction
        ``u_G``: a lighting of the posed mesh's panels, or None for shading none (a shader is
        made for every call: for many calls use a cache)."""
        if self.shading == "none":
            return None
        return make_shader(self.body.mesh(positions), mode=self.shading).lighting(u_G)

    def coefficients(
        self,
        flow: FreeStream,
        positions: Mapping[str, float] | None = None,
        aoa: float | None = None,
        aos: float | None = None,
        *,
        flow_direction=None,
        lighting=OWN_SHADING,
        surface=None,
    ) -> ArticulatedCoefficients:
        """Coefficients at joint ``positions`` and one attitude.

        Parameters
        ----------
        flow : FreeStream
        positions : mapping of str to float, optional
            Joint positions [rad or m] (others at zero), checked as
            :meth:`ArticulatedBody.positions` checks them.
        aoa, aos : float, optional
            Angle of attack and sideslip [rad], or ``flow_direction`` (G) instead.
        lighting : PanelLighting, LightingBlend or None, optional
            The posed body's lighting (panels in the order of ``body.mesh(positions)``); None
            for nothing occluded; by default the method's own ``shading``.
        surface : tuple of PanelSurface, optional
            From :meth:`surface_with`.

        Raises
        ------
        ValueError
            A bad joint position (named, with its limits), or a lighting of another panel count.
        """
        u, angles = frames.attitude_flow(aoa, aos, flow_direction)
        positions = self.body.positions(positions)
        poses = self.poses.poses(positions)
        if lighting is OWN_SHADING:
            lighting = self.lighting_of(u, positions)
        if lighting is not None and lighting.n_panels != self.n_panels:
            raise ValueError(
                f"lighting has {lighting.n_panels} panels, the body has {self.n_panels}"
            )
        rotations = poses.rotations[self._link_index]
        origins = poses.origins[self._link_index]
        evaluated = None
        if self.facets is not None:
            evaluated = self._posed_loads(flow, u, lighting, surface, poses, rotations, origins)
        if evaluated is None:  # (a link without facets, or a surface varying within a facet)
            evaluated = self._link_loads(flow, u, lighting, surface, poses, rotations, origins)
        forces, moments, area_projected, panel_values, panel_index = evaluated
        ref = self.reference
        # every joint at once: the loads of the links it carries, their moment about it
        carried_force = self._carries @ forces
        about = self._carries @ moments + (
            frames.cross(self._moment_point - poses.joint_origins, carried_force) / ref.length
        )
        about[self._prismatic] = carried_force[self._prismatic]  # (along a prismatic joint)
        effort = dict(zip(self.body.joints, (about * poses.joint_axes).sum(axis=1).tolist()))
        link_force = np.zeros((len(self.body.links), 3))
        link_moment = np.zeros((len(self.body.links), 3))
        link_force[self._link_index] = forces
        link_moment[self._link_index] = moments
        total = AeroCoefficients(
            flow_direction=u,
            Cf_G=forces.sum(axis=0),
            Cm_G=moments.sum(axis=0),
            reference=ref,
            area_projected=float(area_projected),
            model=self.model,
            panel_values=panel_values,
            panel_index=panel_index,
            lighting=lighting,
            angles=angles,
        )
        return ArticulatedCoefficients(
            total, link_force, link_moment, effort, positions, self._kinds
        )

    def _posed_loads(self, flow, u, lighting, surface, poses, rotations, origins):
        """Every evaluated link's force and moment coefficients (body frame, about the moment
        point), their lit projected area, and the per-facet values, from the posed facets in
        one evaluation (None if the surface varies within a facet)."""
        facets = self.facets
        facet_surface = self._facet_surface if surface is None else facets.surface(surface)
        if facet_surface is None:
            return None
        normals, inward_T = facets.normals(poses, rotations)
        c, cp, shear, ctau = self._evaluator.facet_coefficients(u, inward_T, facet_surface, flow)
        rows = facet_rows(c, cp, shear)
        sums = facets.sums(lighting, poses, rotations, origins)
        # facet g: force W (q u) + k (W n); moment q (Q x u) + k (Q x n), about the origin of
        # G; projected area max(c, 0) W: the weighted columns summed link by link
        weighted = np.empty((facets.n, 11))
        np.multiply(rows[_ROW_OF_SUM].T, sums, out=weighted[:, :10])
        np.multiply(rows[2], sums[:, 0], out=weighted[:, 10])
        per_link = np.add.reduceat(weighted, facets.starts)
        q_w, k_wn, q_q, k_qn = per_link[:, 0], per_link[:, 1:4], per_link[:, 4:7], per_link[:, 7:10]
        area = float(per_link[:, 10].sum())
        force = q_w[:, None] * u + k_wn
        ux, uy, uz = u.tolist()
        cross_u = np.array([[0.0, -uz, uy], [uz, 0.0, -ux], [-uy, ux, 0.0]])  # a x u = a @ it
        moment = q_q @ cross_u + k_qn + force @ self._cross_point  # (- r_ref x F)
        ref = self.reference
        return (
            force / ref.area,
            moment / (ref.area * ref.length),
            area,
            (c, cp, ctau, shear, normals),
            facets.panel_index,
        )

    def _link_loads(self, flow, u, lighting, surface, poses, rotations, origins):
        """As :meth:`_posed_loads`, link by link in the links' frames (per-panel values)."""
        own = self.splits.split(lighting, rotations, poses.key)
        u_links = rotations.transpose(0, 2, 1) @ u  # the flow seen by each link
        n = len(self._links)
        forces, moments = np.empty((n, 3)), np.empty((n, 3))  # body frame; about the point
        area_projected = 0.0
        results = []
        ref = self.reference
        for k, (_, _, _, method) in enumerate(self._links):
            r = method.coefficients(
                flow,
                flow_direction=u_links[k],
                lighting=own[k],
                surface=None if surface is None else surface[k],
            )
            results.append(r)
            forces[k] = force = rotations[k] @ r.Cf_G
            arm = origins[k] - self._moment_point
            moments[k] = rotations[k] @ r.Cm_G + frames.cross(arm, force) / ref.length
            area_projected += r.area_projected
        return forces, moments, area_projected, lambda: _joined_panel_values(results), None


#: Which row of :func:`facet_rows` (q, k) weights each column of the facet sums (W, W n, Q,
#: Q x n) in the load: q W, k W n, q Q, k Q x n.
_ROW_OF_SUM = np.array([0, 1, 1, 1, 0, 0, 0, 1, 1, 1])


def _joined_panel_values(results) -> tuple:
    """(cos_delta, cp, ctau, None, None) of every panel of the posed body from its links'."""
    return (
        np.concatenate([r.cos_delta for r in results]),
        np.concatenate([r.cp for r in results]),
        np.concatenate([r.ctau for r in results]),
        None,
        None,
    )
