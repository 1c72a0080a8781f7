"""One input message through the estimator: the per-message path of the node and bag analysis.

A rejection is counted by its reason, any other failure as ``compute_error`` (it never stops
the caller); with ``attitude_source`` odometry a state's pose is the attitude. Both callers
encode a sample with :func:`adbsat_ros.messages.encoding.encode_wrench`: equal bit for bit.
"""

from __future__ import annotations

from dataclasses import dataclass

from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.samples import Rejection, WrenchSample
from adbsat_ros.messages.cdr import AttitudeFields, Stamp
from adbsat_ros.messages.decoding import JointStateFields, OdometryFields, UndecodableMessage
from adbsat_ros.messages.stamps import next_regular_stamp, stamp_seconds


@dataclass(frozen=True, kw_only=True, slots=True)
class Outcome:
    """What one input message came to: the sample, or the rejection or failure (``error``,
    counted as ``compute_error``). ``stamp`` is None for bytes that could not be decoded;
    ``triggered``: whether the message asked for a wrench."""

    stamp: Stamp | None
    triggered: bool = False
    state_accepted: bool = False
    sample: WrenchSample | None = None
    rejection: Rejection | None = None
    error: Exception | None = None

    @property
    def reason(self) -> str | None:
        """The rejection's reason, ``compute_error`` for a failure, else None."""
        if self.rejection is not None:
            return self.rejection.reason
        return None if self.error is None else "compute_error"

    @property
    def status(self) -> str | None:
        """None if the message asked for no wrench, ``ok`` if it got one, else the reason."""
        if not self.triggered:
            return None
        return "ok" if self.sample is not None else self.reason


#: The outcome of an attitude while the attitude comes from the odometry pose.
IGNORED = Outcome(stamp=None)


class MessageHandler:
    """The node's handling of input messages around one estimator, without ROS."""

    def __init__(self, estimator: AeroWrenchEstimator):
        self.estimator = estimator
        self._stamps: tuple = (None, None)  # stamps of the two latest wrenches

    @property
    def uses_attitude_topic(self) -> bool:
        """Whether attitudes come from their own messages (else from the odometry pose)."""
        return self.estimator.settings.attitude_source == "attitude_topic"

    def on_state(self, odometry: OdometryFields) -> Outcome:
        """A decoded nav_msgs/Odometry: accepted (and its wrench if it gives attitudes), or not."""
        try:
            _, orientation = self.estimator.on_odometry(odometry)
        except Exception as exc:  # never let a message take the caller down
            return self._failed(odometry.stamp, exc)
        if self.uses_attitude_topic:
            return Outcome(stamp=odometry.stamp, state_accepted=True)
        return self._wrench(odometry.stamp, orientation, state=True)

    def on_attitude(self, attitude: AttitudeFields) -> Outcome:
        """A decoded attitude: its wrench, or why none (:data:`IGNORED` if odometry gives them)."""
        if not self.uses_attitude_topic:
            return IGNORED
        return self._wrench(
            attitude.stamp, attitude.quaternion_xyzw, state=False, frame_id=attitude.frame_id
        )

    def on_joint_state(self, joint_state: JointStateFields) -> Outcome:
        """A joint_states message: positions taken for the next wrenches, or ``bad_joint_state``."""
        try:
            self.estimator.on_joint_state(
                stamp_seconds(joint_state.stamp), joint_state.names, joint_state.positions
            )
        except Exception as exc:  # never let a message take the caller down
            return self._failed(joint_state.stamp, exc)
        return Outcome(stamp=joint_state.stamp)

    def undecodable(self, what: str, exc: UndecodableMessage) -> Outcome:
        """Bytes on input ``what`` that are no message: counted as ``undecodable``."""
        self.estimator.rejections["undecodable"] += 1
        return Outcome(stamp=None, rejection=Rejection("undecodable", f"{what} message {exc}"))

    def _failed(self, stamp: Stamp, exc: Exception, **fields) -> Outcome:
        """The outcome of a message whose handling raised ``exc``."""
        if isinstance(exc, Rejection):
            return Outcome(stamp=stamp, rejection=exc, **fields)
        self.estimator.rejections["compute_error"] += 1
        return Outcome(stamp=stamp, error=exc, **fields)

    def _wrench(self, stamp: Stamp, quaternion, state: bool, frame_id: str = "") -> Outcome:
        try:
            sample = self.estimator.on_attitude(stamp_seconds(stamp), quaternion, frame_id)
        except Exception as exc:  # never let a message take the caller down
            return self._failed(stamp, exc, triggered=True, state_accepted=state)
        self._stamps = (self._stamps[1], stamp)
        return Outcome(stamp=stamp, triggered=True, state_accepted=state, sample=sample)

    def next_stamp(self) -> float | None:
        """The next wrench's likely stamp [s], None before two."""
        previous, latest = self._stamps
        return None if previous is None else next_regular_stamp(previous, latest)

    def prepare_next(self) -> bool:
        """:meth:`AeroWrenchEstimator.prepare` of :meth:`next_stamp`; whether it prepared."""
        expected = self.next_stamp()
        return expected is not None and self.estimator.prepare(expected)
