"""The panel method of an articulated body, exact at every joint configuration (docs/physics.md,
section 8): the links' facets posed in the body frame and evaluated as one rigid body, or each
link in its own frame (F_l = R_l Cf_l, M_l = R_l Cm_l + (t_l - r_ref) x F_l / L_ref). A joint's
effort is its carried links' moment about its axis or force along it. Units: m, rad; frame G."""

from __future__ import annotations

from typing import Mapping

import numpy as np

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.poses import link_frames
from adbsat_ros.physics.articulated_results import ArticulatedCoefficients, Configuration, LoadMaps
from adbsat_ros.physics.coefficients import AeroCoefficients, Reference
from adbsat_ros.physics.facets import facet_rows
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.link_loads import LINK_LOADS, EffortColumns, LinkLoads
from adbsat_ros.physics.panel_method import OWN_SHADING, PanelMethod
from adbsat_ros.physics.posed_facets import PosedFacets, PosedSums
from adbsat_ros.shading.lighting import panel_range
from adbsat_ros.shading.shader import MODES as SHADING_MODES
from adbsat_ros.shading.shader import make_shader


class ArticulatedMethod:
    """The panel method of an :class:`ArticulatedBody` at any joint positions. Parameters as for
    :class:`PanelMethod` (materials by the URDF's material names); ``reference``: A_ref, L_ref
    and moment point (body frame), unset ones from the body at zero joint positions."""

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
        self._joint_names = tuple(body.joints)
        self._prismatic = np.array([j.kind == "prismatic" for j in body.joints.values()], bool)
        #: The joints' effort terms (the load maps', and the posed facets' columns).
        self._effort_columns = EffortColumns(
            self._carries, self._prismatic, self.reference.area, self.reference.length
        )
        methods = [method for *_, method in self._links]
        #: The links' facets posed in the body frame (None if a link is evaluated panel by
        #: panel; then every link is evaluated in its own frame).
        self.facets = PosedFacets.of(
            methods,
            self._link_index,
            [(start, stop) for _, start, stop, _ in self._links],
            self._effort_columns,
        )
        self._evaluator = methods[0]  # (every link has the model and options)
        self._facet_surface = None
        if self.facets is not None:
            self._facet_surface = self.facets.surface([m.surface for m in methods])
        n_links, n_joints = len(body.links), len(body.joints)
        area_length = self.reference.area * self.reference.length
        self._effort_scales = np.where(self._prismatic, self.reference.area, area_length)
        self._effort_scales.setflags(write=False)
        # the rows of a load map's outputs: Cf_G, Cm_G, links' forces, links' moments, joints'
        # efforts, lit projected area
        ends = np.cumsum([0, 3, 3, 3 * n_links, 3 * n_links, n_joints, 1]).tolist()
        self._rows = tuple(slice(a, b) for a, b in zip(ends[:-1], ends[1:]))
        self._load_maps = LoadMaps(self._make_links_map(), self._rows[4], self._effort_columns)

    @property
    def needs_species(self) -> bool:
        """Whether the model needs the gas composition (as :attr:`PanelMethod.needs_species`)."""
        return self._links[0][3].needs_species

    def surface_with(self, **changes) -> tuple:
        """Per-link :meth:`PanelMethod.surface_with`."""
        return tuple(method.surface_with(**changes) for *_, method in self._links)

    def lighting_of(self, u_G, positions=None):
        """The method's shading of the body at ``positions`` for flow ``u_G`` (G), or None."""
        if self.shading == "none":
            return None
        # (no topology store: each configuration's posed panels would be another entry)
        posed = self.body.mesh(positions)
        return make_shader(posed, mode=self.shading, topology_store=None).lighting(u_G)

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
        positions: joint positions [rad or m] (others at zero), or their :meth:`configuration`.
        aoa, aos: angle of attack and sideslip [rad], or ``flow_direction`` (G) instead.
        lighting: the posed body's (panels in ``body.mesh(positions)`` order); None: no occlusion.
        ValueError: a bad joint position (named, with its limits), or a lighting of another size."""
        u, angles = frames.attitude_flow(aoa, aos, flow_direction)
        if not isinstance(positions, Configuration):
            positions = self.configuration(positions)
        elif positions.maps is not self._load_maps:
            raise ValueError("positions: a Configuration made by another ArticulatedMethod")
        configuration = positions
        if lighting is OWN_SHADING:
            lighting = self.lighting_of(u, configuration.positions)
        if lighting is not None and lighting.n_panels != self.n_panels:
            raise ValueError(
                f"lighting has {lighting.n_panels} panels, the body has {self.n_panels}"
            )
        sums = None if self.facets is None else self.facets.sums(lighting, configuration)
        return self.coefficients_of_rows(flow, u, angles, configuration, sums, lighting, surface)

    def coefficients_of_rows(
        self,
        flow: FreeStream,
        u,
        angles,
        configuration: Configuration,
        sums: PosedSums | None,
        lighting=None,
        surface=None,
    ) -> ArticulatedCoefficients:
        """:meth:`coefficients` at unit direction ``u`` (G) from :class:`PosedSums`."""
        posed = None
        if self.facets is not None:
            posed = self._posed_evaluation(flow, u, sums, surface, configuration)
        cf, cm, forces, moments, effort, area = self._rows
        n_links = len(self.body.links)
        if posed is not None:
            (Cf_G, Cm_G, area_projected), panel_values, panel_index, facet_terms = posed
            link_loads = LinkLoads(
                configuration, forces, moments, effort, n_links, facets=facet_terms
            )
        else:  # (a link without facets, or a surface varying within a facet)
            loads, panel_values = self._link_loads(flow, u, lighting, surface, configuration.poses)
            link_loads = LinkLoads(configuration, forces, moments, effort, n_links, loads=loads)
            out = link_loads._outputs
            Cf_G, Cm_G, area_projected = out[cf], out[cm], float(out[area][0])
            panel_index = None

        total = AeroCoefficients(
            flow_direction=u,
            Cf_G=Cf_G,
            Cm_G=Cm_G,
            reference=self.reference,
            area_projected=area_projected,
            model=self.model,
            panel_values=panel_values,
            panel_index=panel_index,
            lighting=lighting,
            angles=angles,
        )
        return ArticulatedCoefficients(
            total, self._joint_names, configuration.joint_positions, self._effort_scales, link_loads
        )

    def configuration(self, positions: Mapping[str, float] | None = None) -> Configuration:
        """The :class:`Configuration` of ``positions`` [rad or m]; ValueError naming bad ones."""
        positions = self.body.positions(positions)
        poses = link_frames(self.body, positions)
        joint_positions = np.array(poses.key, dtype=float)
        joint_positions.setflags(write=False)
        posing = None if self.facets is None else self.facets.posing(poses)
        return Configuration(positions, poses, joint_positions, posing, self._load_maps)

    def _make_links_map(self) -> np.ndarray:
        """The load map's rows that no pose changes (efforts' rows zero)."""
        area, length = self.reference.area, self.reference.length
        force = np.eye(3, LINK_LOADS) / area  # (F, M, S) -> f
        about_point = np.zeros((3, LINK_LOADS))  # (F, M, S) -> m - r x f / L_ref
        about_point[:, 0:3] = -frames.cross_matrix(self.reference.moment_point)
        about_point[:, 3:6] = np.eye(3)
        about_point /= area * length
        cf, cm, forces, moments, _, area_row = self._rows
        out = np.zeros((area_row.stop, LINK_LOADS * len(self._links)))
        for k, link in enumerate(self._link_index.tolist()):
            columns = slice(LINK_LOADS * k, LINK_LOADS * (k + 1))
            out[cf, columns] = force
            out[cm, columns] = about_point
            out[forces.start + 3 * link : forces.start + 3 * link + 3, columns] = force
            out[moments.start + 3 * link : moments.start + 3 * link + 3, columns] = about_point
            out[area_row.start, LINK_LOADS * k + 6] = 1.0  # the lit projected area
        return out

    def _posed_evaluation(self, flow, u, sums, surface, configuration):
        """The posed facets evaluated as one rigid body (None: the surface varies in a facet)."""
        facets = self.facets
        facet_surface = self._facet_surface if surface is None else facets.surface(surface)
        if facet_surface is None:
            return None
        normals = configuration.posing.normals
        c, cp, shear, ctau = self._evaluator.facet_coefficients(
            u, configuration.posing.inward_T, facet_surface, flow
        )
        rows = facet_rows(c, cp, shear)
        return (
            PanelMethod.totals_of_sums(u, rows, sums.ten, self.reference),
            (c, cp, ctau, shear, normals),
            facets.panel_index,
            (rows, sums, facets.starts, u),
        )

    def _link_loads(self, flow, u, lighting, surface, poses):
        """Every evaluated link's loads (F, M, S) from its own frame, and per-panel values."""
        rotations = poses.rotations[self._link_index]
        origins = poses.origins[self._link_index]
        own = [  # (the lighting of each link's panels, shifts in its frame)
            panel_range(lighting, start, stop, rotation.T)
            for (_, start, stop, _), rotation in zip(self._links, rotations)
        ]
        u_links = rotations.transpose(0, 2, 1) @ u  # the flow seen by each link
        loads = np.empty((len(self._links), LINK_LOADS))
        results = []
        area, length = self.reference.area, self.reference.length
        for k, (_, _, _, method) in enumerate(self._links):
            r = method.coefficients(
                flow,
                flow_direction=u_links[k],
                lighting=own[k],
                surface=None if surface is None else surface[k],
            )
            results.append(r)
            loads[k, 0:3] = force = area * (rotations[k] @ r.Cf_G)
            loads[k, 3:6] = (area * length) * (rotations[k] @ r.Cm_G) + frames.cross(
                origins[k], force
            )
            loads[k, 6] = r.area_projected
        return loads.ravel(), lambda: _joined_panel_values(results)


def _joined_panel_values(results) -> tuple:
    """(cos_delta, cp, ctau, None, None) of the posed body's panels, joined."""
    return (
        np.concatenate([r.cos_delta for r in results]),
        np.concatenate([r.cp for r in results]),
        np.concatenate([r.ctau for r in results]),
        None,
        None,
    )
