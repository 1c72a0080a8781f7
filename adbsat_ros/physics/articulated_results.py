"""What an articulated body's panel method takes and gives: a :class:`Configuration` (positions
checked and posed, made once for many evaluations) and the :class:`ArticulatedCoefficients`.
Units: metres, radians; frame G = the root link's frame."""

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
    """What makes a configuration's load map from the links' (F, M, S) to every output. A link's
    coefficients are F / A_ref and (M - r x F) / (A_ref L_ref); joint j (axis a through o) has
    effort coefficient sum_(l in C_j) (a . M_l - (a x o) . F_l) / (A_ref L_ref) if it turns,
    sum_(l in C_j) a . F_l / A_ref if it slides (docs/physics.md, section 8)."""

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
    """Checked, posed joints: ``positions`` [rad or m] by name; ``joint_positions`` (J,)."""

    positions: dict
    poses: Poses
    joint_positions: np.ndarray
    posing: Posing | None
    maps: LoadMaps

    @functools.cached_property
    def load_map(self) -> np.ndarray:
        """The map from the links' loads to every output (:class:`LoadMaps`), made when read."""
        return self.maps.at(self.poses)


class ArticulatedCoefficients(NamedTuple):
    """The coefficients of an articulated body at one configuration and flow direction.
    ``total``: the whole body's; ``joint_positions`` [rad or m]; ``effort_scales`` (J,): q times
    these turns effort coefficients into efforts, A_ref L_ref [m^3] or A_ref [m^2] (prismatic)."""

    total: AeroCoefficients
    joint_names: tuple
    joint_positions: np.ndarray
    effort_scales: np.ndarray
    link_loads: LinkLoads

    @property
    def effort_coefficients(self) -> np.ndarray:
        """Each moving joint's effort coefficient (J,): moment about its axis, or force along it."""
        return self.link_loads.effort_coefficients

    @property
    def link_force(self) -> np.ndarray:
        """Every link's force coefficient (L, 3), body frame; they sum to the total."""
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
        """Joint efforts (J,) [N m, or N for a prismatic joint] at dynamic pressure q [Pa]."""
        return (dynamic_pressure * self.effort_scales) * self.effort_coefficients

    def joint_efforts(self, dynamic_pressure: float) -> dict:
        """:meth:`efforts` by joint name."""
        return dict(zip(self.joint_names, self.efforts(dynamic_pressure).tolist()))
