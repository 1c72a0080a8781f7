"""The joint positions of an articulated body, from sensor_msgs/JointState messages.

State-like, as the orbital state: the latest position of every moving joint is kept with its
stamp, and an attitude uses the positions as they are at its stamp. A message is taken whole or
not at all: a name that is no joint of the body, a position that is not a finite number or
lies beyond its joint's limits, or names and positions that do not pair up refuse it
(``bad_joint_state``). Names of the body's fixed or mimic joints are ignored (a
robot_state_publisher-style source may list them). An attitude is refused with
``no_joint_state`` until every moving joint has had a position, and with ``stale_joint_state``
while a joint's latest position is more than ``timeout`` from the attitude stamp.
"""

from __future__ import annotations

import math

import numpy as np

from adbsat_ros.estimator.samples import Rejection
from adbsat_ros.geometry.articulated import ArticulatedBody


class JointStates:
    """The latest position [rad or m] and stamp [s] of every moving joint of ``body``.

    Parameters
    ----------
    body : ArticulatedBody
    timeout : float
        Largest distance [s] between a joint position's stamp and an attitude stamp.

    Attributes
    ----------
    accepted : int
        Joint-state messages taken.
    """

    def __init__(self, body: ArticulatedBody, timeout: float):
        self.body = body
        self.timeout = float(timeout)
        self._latest: dict = {}  # name -> (stamp, position)
        self.accepted = 0

    def clear(self) -> None:
        """Forget every position (the history restarts)."""
        self._latest.clear()

    def on_joint_state(self, stamp: float, names, positions) -> dict:
        """Take a JointState's positions.

        Returns
        -------
        dict of str to float
            The positions it gave (moving joints only).

        Raises
        ------
        Rejection
            ``bad_joint_state``, naming the joint and the problem; nothing is taken.
        """
        if not math.isfinite(stamp):
            raise Rejection("bad_joint_state", "joint_state stamp is not finite")
        names = [str(n) for n in names]
        positions = list(positions)
        if len(positions) != len(names):
            raise Rejection(
                "bad_joint_state",
                f"joint_state has {len(names)} names and {len(positions)} positions; each "
                "name needs its position",
            )
        if len(set(names)) != len(names):
            raise Rejection("bad_joint_state", "joint_state names a joint twice")
        given = {}
        for name, value in zip(names, positions):
            if name in self.body.joints:
                given[name] = value
            elif name not in self.body.all_joint_names:
                raise Rejection(
                    "bad_joint_state",
                    f"joint_state: joint {name!r} is not in {self.body.source}; its moving "
                    f"joints are {', '.join(self.body.joints) or 'none'}",
                )
        try:
            checked = self.body.positions(given)
        except ValueError as exc:
            raise Rejection("bad_joint_state", f"joint_state: {exc}") from None
        for name in given:
            self._latest[name] = (stamp, checked[name])
        self.accepted += 1
        return {name: checked[name] for name in given}

    def positions_at(self, stamp: float) -> dict:
        """Every moving joint's position for an attitude at ``stamp`` [s].

        Raises
        ------
        Rejection
            ``no_joint_state`` (a joint without a position yet) or ``stale_joint_state``.
        """
        out = {}
        for name in self.body.joints:
            latest = self._latest.get(name)
            if latest is None:
                raise Rejection("no_joint_state", f"no position received yet for joint {name}")
            dt = stamp - latest[0]
            if abs(dt) > self.timeout:
                raise Rejection(
                    "stale_joint_state",
                    f"joint {name}'s latest position is {dt:.3f} s from the attitude stamp "
                    f"(joint_state_timeout {self.timeout:g} s)",
                )
            out[name] = latest[1]
        return out

    def vector(self, positions: dict) -> np.ndarray:
        """``positions`` as an array in the body's joint order."""
        return np.array([positions[name] for name in self.body.joints])
