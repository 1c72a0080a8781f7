"""The frames of an articulated body's links and joints at a joint configuration, cached.

Forward kinematics (:mod:`~adbsat_ros.geometry.kinematics`) and the joints' axes are computed per
configuration, and a stream of wrench messages meets the same configuration again and again (joint
states come at a tenth of the attitudes' rate, or not at all for fixed joints), so
:class:`PoseCache` keeps the poses of the latest configurations.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.lru import LruStore


class Poses(NamedTuple):
    """Link and joint frames in the body frame G at one configuration.

    Attributes
    ----------
    key : tuple of float
        The joint positions, in the body's joint order.
    rotations : ndarray, shape (L, 3, 3)
        Rotation of every link's frame into G.
    origins : ndarray, shape (L, 3)
        Every link's origin in G [m].
    joint_axes : ndarray, shape (J, 3)
        Unit axis of every moving joint in G.
    joint_origins : ndarray, shape (J, 3)
        Where each joint's axis passes (its child link's origin) [m].
    """

    key: tuple
    rotations: np.ndarray
    origins: np.ndarray
    joint_axes: np.ndarray
    joint_origins: np.ndarray


class PoseCache:
    """The :class:`Poses` of a body's latest joint configurations.

    Key: the checked joint positions in joint order (exact floats). Value: the Poses. Bound:
    ``max_entries`` (least recently used dropped). Counters: :attr:`store`'s ``hits`` and
    ``misses``.
    """

    def __init__(self, body: ArticulatedBody, max_entries: int = 16):
        self.body = body
        self.store = LruStore(max_entries)
        self._child = [body.links.index(j.child) for j in body.joints.values()]
        self._axes = np.array([j.axis for j in body.joints.values()], dtype=float).reshape(-1, 3)

    def poses(self, positions: dict) -> Poses:
        """The Poses of checked ``positions`` (every moving joint named)."""
        key = tuple(positions[name] for name in self.body.joints)
        return self.store.get(key, lambda: self._poses(key, positions))

    def _poses(self, key: tuple, positions: dict) -> Poses:
        matrices = self.body.link_poses(positions)
        rotations = np.ascontiguousarray(matrices[:, :3, :3])
        origins = np.ascontiguousarray(matrices[:, :3, 3])
        axes = np.einsum("jab,jb->ja", rotations[self._child], self._axes)
        axes /= np.sqrt(np.einsum("ja,ja->j", axes, axes))[:, None]
        return Poses(key, rotations, origins, axes, origins[self._child])
