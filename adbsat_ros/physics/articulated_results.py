"""What an articulated body's panel method takes and gives besides the joint positions: a
:class:`Configuration` (positions checked and posed, made once for many evaluations) and the
:class:`ArticulatedCoefficients` of one evaluation.

Units: metres, radians; frame G = the root link's frame.
"""

from __future__ import annotations

import dataclasses
import functools
from typing import NamedTuple

import numpy as np

from adbsat_ros.geometry.poses import Poses
from adbsat_ros.physics.coefficients import AeroCoefficients
from adbsat_ros.physics.link_loads import LINK_LOADS, EffortColumns, LinkLoads
from adbsat_ros.physics.posed_facets import Posing


class LoadMaps:
    """What makes a configuration's load map: the matrix that takes the evaluated links' loads
    to every output (:attr:`Configuration.load_map`).

    Its input is, link after link, (F, M, S): the link's force W (q u + k n) summed over its
    facets [m^2], their moment about G's origin [m^3] (body frame) and its lit projected area
    [m^2]. Its output: Cf_G, Cm_G (about the reference point r), each link's force and moment
    coefficients (all links, zero without geometry), each joint's effort coefficient and the
    body's lit projected area. A link's coefficients are f = F / A_ref and, about r,
    (M - r x F) / (A_ref L_ref); joint j (axis a through o) carrying the links C_j has the
    effort coefficient sum_(l in C_j) a . (M_l - o x F_l) / (A_ref L_ref) =
    (a . M_l - (a x o) . F_l) / (A_ref L_ref) if it turns, and sum_(l in C_j) a . F_l / A_ref
    if it slides.

    Parameters
    ----------
    links : ndarray
        The map's rows that no joint's pose changes (the joints' efforts' rows zero).
    efforts : slice
        The joints' efforts' rows.
    columns : EffortColumns
        The joints' effort terms (``carries``: 1 where joint j carries evaluated link l).
    """

    def __init__(self, links: np.ndarray, efforts: slice, columns: EffortColumns):
        self.links, self.efforts, self.columns = links, efforts, columns
        links.setflags(write=False)

    def at(self, poses: Poses) -> np.ndarray:
        """The load map at ``poses``' configuration (read-only)."""
        per_joint = np.array([(*f, *m, 0.0) for f, m in self.columns.per_joint(poses)]).reshape(
            -1, LINK_LOADS
        )
        out = self.links.copy()
        # joint j's row: per_joint[j] in the columns of every link it carries
        out[self.efforts] = (self.columns.carries[:, :, None] * per_joint[:, None, :]).reshape(
            len(per_joint), out.shape[1]
        )
        out.setflags(write=False)
        return out


@dataclasses.dataclass(frozen=True, eq=False)
class Configuration:
    """Joint positions checked and posed, with what an evaluation there reads: made by
    :meth:`ArticulatedMethod.configuration` once per joint state, given to
    :meth:`ArticulatedMethod.coefficients` for every attitude at those positions.

    Attributes
    ----------
    positions : dict of str to float
        Every moving joint's position [rad or m], checked.
    poses : Poses
        The links' and joints' frames.
    joint_positions : ndarray, shape (J,)
        The positions in the body's joint order (read-only).
    posing : Posing or None
        The posed facets' normals and posing matrices; None without posed facets.
    maps : LoadMaps
        What makes :attr:`load_map`: the method's own (it tells which method made it).
    """

    positions: dict
    poses: Poses
    joint_positions: np.ndarray
    posing: Posing | None
    maps: LoadMaps

    @functools.cached_property
    def load_map(self) -> np.ndarray:
        """The map from the links' loads to every output (:class:`LoadMaps`), made when the
        links' loads, or every output of a body evaluated link by link, are first read."""
        return self.maps.at(self.poses)


class ArticulatedCoefficients(NamedTuple):
    """The coefficients of an articulated body at one configuration and flow direction.

    The links' forces and moments and the joints' efforts are computed from the evaluation's
    sums when first read (:class:`~adbsat_ros.physics.link_loads.LinkLoads`), so a caller that
    needs only the total (a node publishing the wrench) does not pay for them. A tuple, made at
    every message: cheaper to make than a frozen dataclass.

    Attributes
    ----------
    total : AeroCoefficients
        The whole body's (as :meth:`PanelMethod.coefficients` of the posed mesh: Cf_G, Cm_G,
        area_projected, wind axes, and per-panel values in the posed mesh's order).
    link_force, link_moment : ndarray, shape (L, 3)
        Force and moment coefficient of every link of the body (zero for links without
        geometry), body frame, moments about the reference moment point; they sum to the total.
    joint_names : tuple of str
        The moving joints, in the body's order.
    effort_coefficients : ndarray, shape (J,)
        For each moving joint, the moment coefficient of the loads on the links it carries
        about its axis through it (revolute, continuous), or their force coefficient along its
        axis (prismatic).
    joint_positions : ndarray, shape (J,)
        The joint positions [rad or m] (read-only: the configuration's own array).
    effort_scales : ndarray, shape (J,)
        What turns an effort coefficient into newton metres or newtons once multiplied by the
        dynamic pressure: A_ref L_ref [m^3] (revolute, continuous) or A_ref [m^2] (prismatic).
    link_loads : LinkLoads
        What gives ``link_force``, ``link_moment`` and ``effort_coefficients``.
    """

    total: AeroCoefficients
    joint_names: tuple
    joint_positions: np.ndarray
    effort_scales: np.ndarray
    link_loads: LinkLoads

    @property
    def effort_coefficients(self) -> np.ndarray:
        """Each moving joint's effort coefficient (J,), in the order of :attr:`joint_names`."""
        return self.link_loads.effort_coefficients

    @property
    def link_force(self) -> np.ndarray:
        """Every link's force coefficient (L, 3), body frame."""
        return self.link_loads.values[0]

    @property
    def link_moment(self) -> np.ndarray:
        """Every link's moment coefficient (L, 3) about the reference moment point."""
        return self.link_loads.values[1]

    @property
    def joint_effort(self) -> dict:
        """Each moving joint's effort coefficient, by name."""
        return dict(zip(self.joint_names, self.effort_coefficients.tolist()))

    @property
    def positions(self) -> dict:
        """Each moving joint's position [rad or m], by name."""
        return dict(zip(self.joint_names, self.joint_positions.tolist()))

    def efforts(self, dynamic_pressure: float) -> np.ndarray:
        """Joint efforts [N m, or N for a prismatic joint] at dynamic pressure q [Pa], in the
        order of :attr:`joint_names`."""
        return (dynamic_pressure * self.effort_scales) * self.effort_coefficients

    def joint_efforts(self, dynamic_pressure: float) -> dict:
        """:meth:`efforts` by joint name."""
        return dict(zip(self.joint_names, self.efforts(dynamic_pressure).tolist()))
