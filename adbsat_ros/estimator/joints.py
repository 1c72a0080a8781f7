"""The joint positions of an articulated body, from sensor_msgs/JointState messages.

A message is taken whole or refused (``bad_joint_state``); fixed and mimic joints are ignored.
Rules: docs/node.md.
"""

from __future__ import annotations

import math
from typing import Callable

from adbsat_ros.estimator.samples import Rejection
from adbsat_ros.geometry.articulated import ArticulatedBody


class JointStates:
    """The latest position [rad or m] and stamp [s] of every moving joint of ``body``.

    The first attitude after a joint state that moves a joint makes the positions ready
    (``prepare``); the next attitudes reuse them. ``accepted`` counts the messages taken.
    """

    def __init__(self, body: ArticulatedBody):
        self.body = body
        self.timeout = math.inf
        self.prepare: Callable = dict
        self._latest: dict = {}  # name -> (stamp, position)
        self._span = self._stamp_span()
        self._configuration = None
        self.accepted = 0

    def clear(self) -> None:
        """Forget every position (the history restarts)."""
        self._latest.clear()
        self._span = self._stamp_span()
        self._configuration = None

    def configure(self, timeout: float, prepare: Callable) -> None:
        """``timeout``: largest joint-to-attitude stamp gap [s]; ``prepare``: positions -> use."""
        self.timeout = float(timeout)
        self.prepare = prepare
        self._configuration = None

    def on_joint_state(self, stamp: float, names, positions) -> dict:
        """Take a JointState's positions, return the moving joints'; Rejection bad_joint_state."""
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
        latest = self._latest
        if any(latest.get(name, (0, None))[1] != checked[name] for name in given):
            self._configuration = None  # (made when an attitude first needs it)
        for name in given:
            latest[name] = (stamp, checked[name])
        self._span = self._stamp_span()
        self.accepted += 1
        return {name: checked[name] for name in given}

    def configuration_at(self, stamp: float):
        """The joint positions for an attitude at ``stamp`` [s], made ready (or Rejection)."""
        oldest, newest = self._span
        if stamp - oldest > self.timeout or newest - stamp > self.timeout:
            self._refuse(stamp)
        if self._configuration is None:
            latest = self._latest
            self._configuration = self.prepare({name: latest[name][1] for name in self.body.joints})
        return self._configuration

    def _stamp_span(self) -> tuple:
        """(oldest, newest) stamp [s]; (-inf, inf) if a joint has none, (inf, -inf) if no joints."""
        latest = [self._latest.get(name) for name in self.body.joints]
        if not latest:
            return math.inf, -math.inf
        if any(x is None for x in latest):
            return -math.inf, math.inf
        stamps = [x[0] for x in latest]
        return min(stamps), max(stamps)

    def _refuse(self, stamp: float) -> None:
        """Raise the rejection of an attitude at ``stamp``, naming the first joint at fault."""
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
