"""A URDF's joint tree and its links' poses by yourdfpy's forward kinematics (m, rad, G = root)."""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from adbsat_ros.geometry.mesh import MeshError

if TYPE_CHECKING:
    import yourdfpy

#: Joint types whose position moves their child link.
MOVING_JOINTS = ("revolute", "continuous", "prismatic")


@dataclass(frozen=True)
class Joint:
    """A joint that moves: type, axis (own frame), limits ``lower``, ``upper`` [rad or m], links."""

    name: str
    kind: str
    parent: str
    child: str
    axis: tuple
    lower: float
    upper: float


class JointTree:
    """The links and moving joints of a URDF, checked to form one tree.

    MeshError naming ``source``: not one tree, an unsupported joint, no axis, a bad mimic.
    """

    def __init__(self, urdf: yourdfpy.URDF, source: str):
        children = {j.child for j in urdf.joint_map.values()}
        roots = [link for link in urdf.link_map if link not in children]
        if len(roots) != 1:
            raise MeshError(
                f"{source}: the links must form one tree from one root link; links no joint "
                f"carries: {', '.join(roots) or 'none'}"
            )
        self.root = roots[0]
        self.links = tuple(urdf.link_map)
        self.all_joint_names = tuple(urdf.joint_map)
        self.joints = {}
        self._children: dict = {}
        carried: set = set()
        for name, j in urdf.joint_map.items():
            if j.type not in MOVING_JOINTS + ("fixed",):
                raise MeshError(f"{source}: joint {name}: type {j.type!r} is not supported")
            if j.child not in urdf.link_map or j.child in carried:
                raise MeshError(
                    f"{source}: joint {name}: its child {j.child!r} is not a link, or is carried "
                    "by another joint too (the links must form one tree)"
                )
            carried.add(j.child)
            self._children.setdefault(j.parent, []).append(j.child)
            axis = tuple(float(x) for x in (j.axis if j.axis is not None else (1.0, 0.0, 0.0)))
            if j.type != "fixed" and not (all(map(math.isfinite, axis)) and any(axis)):
                text = ", ".join(f"{a:g}" for a in axis)
                raise MeshError(f"{source}: joint {name}: axis ({text}) has no direction")
            if j.type == "fixed" or j.mimic is not None:
                continue
            lower, upper = -math.inf, math.inf
            if j.type != "continuous" and j.limit is not None:
                lower = -math.inf if j.limit.lower is None else float(j.limit.lower)
                upper = math.inf if j.limit.upper is None else float(j.limit.upper)
            self.joints[name] = Joint(name, j.type, j.parent, j.child, axis, lower, upper)
        for name, j in urdf.joint_map.items():
            if j.type != "fixed" and j.mimic is not None and j.mimic.joint not in self.joints:
                raise MeshError(
                    f"{source}: joint {name} mimics {j.mimic.joint!r}, which is not a moving "
                    f"joint; the moving joints are {', '.join(self.joints) or 'none'}"
                )
        unreached = set(self.links) - set(self.carried(self.root))
        if unreached:
            raise MeshError(
                f"{source}: links not carried from the root {self.root} by a chain of joints: "
                f"{', '.join(sorted(unreached))}"
            )
        import yourdfpy  # (imported by whoever read ``urdf``: not at start-up)

        self._kinematics = yourdfpy.URDF(urdf.robot, build_scene_graph=True, load_meshes=False)
        self._unset = {name: math.nan for name in self.joints}
        self._posed = None  # the configuration the scene graph holds
        self._lock = threading.Lock()  # (the scene graph holds one configuration at a time)

    def carried(self, link: str) -> list:
        """``link`` and every link beyond it (names)."""
        out, stack = [], [link]
        while stack:
            out.append(stack.pop())
            stack.extend(self._children.get(out[-1], []))
        return out

    def poses(self, positions: dict) -> np.ndarray:
        """4 x 4 pose of every link in G, shape (L, 4, 4), for checked ``positions``."""
        key = tuple(positions[name] for name in self.joints)
        with self._lock:
            if key != self._posed:
                # (trimesh's scene graph keeps a joint's transform when the new one is within
                # 1e-8 of it: set to NaN first, every moving joint's is replaced)
                self._kinematics.update_cfg(self._unset)
                self._kinematics.update_cfg(positions)
                self._posed = key
            return np.stack([self._kinematics.get_transform(k, self.root) for k in self.links])


class Poses(NamedTuple):
    """Link rotations (L, 3, 3), origins [m], unit joint axes (J, 3) and their points [m] in G."""

    key: tuple
    rotations: np.ndarray
    origins: np.ndarray
    joint_axes: np.ndarray
    joint_origins: np.ndarray


def link_frames(body, positions: dict) -> Poses:
    """The :class:`Poses` of an articulated body at checked ``positions``."""
    key = tuple(positions[name] for name in body.joints)
    matrices = body.link_poses(positions)
    rotations = np.ascontiguousarray(matrices[:, :3, :3])
    origins = np.ascontiguousarray(matrices[:, :3, 3])
    child = [body.links.index(j.child) for j in body.joints.values()]
    axes = np.array([j.axis for j in body.joints.values()], dtype=float).reshape(-1, 3)
    axes = np.einsum("jab,jb->ja", rotations[child], axes)
    axes /= np.sqrt(np.einsum("ja,ja->j", axes, axes))[:, None]
    return Poses(key, rotations, origins, axes, origins[child])
