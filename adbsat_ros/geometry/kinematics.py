"""Forward kinematics of a URDF's joint tree: every link's pose in the root's frame.

yourdfpy reads the URDF (its joints' origins, axes, types and mimic rules) and makes each
joint's own transform (``origin @ R(q, axis)`` for a revolute or continuous joint,
``origin @ T(q axis)`` for a prismatic one, the origin alone for a fixed one, a mimic joint at
``multiplier q + offset`` of the joint it follows), as its forward kinematics does. This module
only chains those transforms from the root outwards, parent before child. yourdfpy's own chain goes
through its scene graph (``update_cfg`` and ``get_transform``), which costs more, and a node meets a
new configuration with every joint state. The tests check both give the same poses.

Units: metres and radians.
"""

from __future__ import annotations

from typing import Mapping, NamedTuple

import numpy as np
import trimesh.transformations as tra


class ChainJoint(NamedTuple):
    """One joint of the tree, as the chain uses it.

    Attributes
    ----------
    parent, child : int
        Indices of its links.
    origin : ndarray, shape (4, 4)
        The child's frame at zero position, in the parent's.
    kind : str
        ``revolute``, ``continuous``, ``prismatic`` or ``fixed``.
    axis : ndarray, shape (3,)
        Its axis in the child's frame at zero position.
    source : str or None
        The moving joint whose position it takes (itself, or the joint it mimics); None for a
        fixed joint.
    multiplier, offset : float
        Its position is ``multiplier * q_source + offset`` (1 and 0 unless it mimics).
    """

    parent: int
    child: int
    origin: np.ndarray
    kind: str
    axis: np.ndarray
    source: str | None
    multiplier: float
    offset: float


class KinematicChain:
    """The joints of a URDF in the order that poses every parent before its children.

    Parameters
    ----------
    urdf : yourdfpy.URDF
        The parsed URDF.
    links : sequence of str
        Link names, in the order of the poses returned.
    root : str
        The root link (its pose is the identity).
    moving : collection of str
        The joints whose positions are given (the others are fixed, or mimic one of these).

    Raises
    ------
    ValueError
        Naming the links that no chain of joints carries from the root, or a moving joint
        whose axis has no direction (zero or not finite).
    """

    def __init__(self, urdf, links, root: str, moving):
        index = {name: k for k, name in enumerate(links)}
        self.n_links = len(links)
        self.root = index[root]
        children: dict = {}
        for joint in urdf.joint_map.values():
            children.setdefault(joint.parent, []).append(joint)
        self.joints: list[ChainJoint] = []
        frontier = [root]
        while frontier:  # breadth first from the root: every parent posed before its children
            parent = frontier.pop(0)
            for joint in children.get(parent, []):
                origin = np.eye(4) if joint.origin is None else np.asarray(joint.origin, float)
                axis = np.asarray(joint.axis if joint.axis is not None else (1.0, 0.0, 0.0), float)
                if joint.type != "fixed" and not (np.isfinite(axis).all() and axis.any()):
                    raise ValueError(
                        f"joint {joint.name}: axis ({', '.join(f'{a:g}' for a in axis)}) has no "
                        "direction"
                    )
                source, multiplier, offset = None, 1.0, 0.0
                if joint.type != "fixed":
                    source = joint.name
                    if joint.mimic is not None:
                        mimic = joint.mimic
                        source = mimic.joint if mimic.joint in moving else None
                        multiplier = 1.0 if mimic.multiplier is None else float(mimic.multiplier)
                        offset = 0.0 if mimic.offset is None else float(mimic.offset)
                self.joints.append(
                    ChainJoint(
                        index[joint.parent],
                        index[joint.child],
                        origin,
                        joint.type,
                        axis,
                        source,
                        multiplier,
                        offset,
                    )
                )
                frontier.append(joint.child)
        unreached = set(links) - {root} - {links[j.child] for j in self.joints}
        if unreached:
            raise ValueError(
                f"links not carried from the root {root} by a chain of joints: "
                f"{', '.join(sorted(unreached))}"
            )

    def poses(self, positions: Mapping[str, float]) -> np.ndarray:
        """4 x 4 pose of every link in the root's frame, shape (L, 4, 4), for checked
        ``positions`` (every moving joint named; a mimic joint follows its joint, at its
        offset if that joint does not move)."""
        poses = np.empty((self.n_links, 4, 4))
        poses[self.root] = np.eye(4)
        for joint in self.joints:
            if joint.kind == "fixed":
                matrix = joint.origin
            else:
                q = joint.offset
                if joint.source is not None:
                    q += joint.multiplier * positions[joint.source]
                if joint.kind == "prismatic":
                    matrix = joint.origin @ tra.translation_matrix(q * joint.axis)
                else:
                    matrix = joint.origin @ rotation(q, joint.axis)
            poses[joint.child] = poses[joint.parent] @ matrix
        return poses


def rotation(angle: float, axis) -> np.ndarray:
    """4 x 4 rotation by ``angle`` [rad] about ``axis`` (three numbers, not zero) through the
    origin (``trimesh.transformations.rotation_matrix``)."""
    return tra.rotation_matrix(angle, np.asarray(axis, dtype=float))
