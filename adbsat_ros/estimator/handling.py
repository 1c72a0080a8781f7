"""One input message through the estimator: the per-message path of the node and the bag analysis.

:class:`MessageHandler` takes the decoded fields of an attitude or state message
(:mod:`adbsat_ros.messages.decoding`), feeds them to an
:class:`~adbsat_ros.estimator.estimator.AeroWrenchEstimator` with the node's rules (a rejected
input is counted by its reason; any other failure is counted as ``compute_error`` and never
stops the caller; with ``attitude_source`` odometry a state's pose is the attitude) and returns
an :class:`Outcome`: the sample, or why there is none. The node and the bag analysis turn a
sample into its messages with the same function
(:func:`adbsat_ros.messages.encoding.encode_wrench`), so both compute and serialise every
message alike, bit for bit.
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
    """What one input message came to: the sample, or the rejection or failure.

    Attributes
    ----------
    stamp : Stamp or None
        The message's header stamp (the wrench's), None for bytes that could not be decoded.
    triggered : bool
        Whether the message asked for a wrench: an attitude, or a state accepted while the
        attitude comes from the odometry pose.
    state_accepted : bool
        Whether the message was a state the estimator accepted.
    sample : WrenchSample or None
        The wrench computed.
    rejection : Rejection or None
        Why the input was refused (reason and message; counted by the estimator).
    error : Exception or None
        An unexpected failure (counted as ``compute_error``).
    """

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
    """The node's handling of input messages around one estimator, without ROS.

    Parameters
    ----------
    estimator : AeroWrenchEstimator
        The estimator fed (its counters count the rejections and failures).
    """

    def __init__(self, estimator: AeroWrenchEstimator):
        self.estimator = estimator
        self._stamps: tuple = (None, None)  # stamps of the two latest wrenches

    @property
    def uses_attitude_topic(self) -> bool:
        """Whether attitudes come from their own messages (else from the odometry pose)."""
        return self.estimator.settings.attitude_source == "attitude_topic"

    def on_state(self, odometry: OdometryFields) -> Outcome:
        """A state message (the decoded nav_msgs/Odometry): accepted (and with
        ``attitude_source`` odometry, its wrench), or not."""
        try:
            _, orientation = self.estimator.on_odometry(odometry)
        except Rejection as exc:
            return Outcome(stamp=odometry.stamp, rejection=exc)
        except Exception as exc:  # never let a message take the caller down
            self.estimator.rejections["compute_error"] += 1
            return Outcome(stamp=odometry.stamp, error=exc)
        if self.uses_attitude_topic:
            return Outcome(stamp=odometry.stamp, state_accepted=True)
        return self._wrench(odometry.stamp, orientation, state=True)

    def on_attitude(self, attitude: AttitudeFields) -> Outcome:
        """An attitude message (the decoded geometry_msgs/QuaternionStamped): its wrench, or
        why there is none (:data:`IGNORED` while the attitude comes from the odometry pose)."""
        if not self.uses_attitude_topic:
            return IGNORED
        return self._wrench(attitude.stamp, attitude.quaternion_xyzw, state=False)

    def on_joint_state(self, joint_state: JointStateFields) -> Outcome:
        """A joint_states message: its positions taken for the next wrenches, or refused
        (``bad_joint_state``, counted); it asks for no wrench."""
        try:
            self.estimator.on_joint_state(
                stamp_seconds(joint_state.stamp), joint_state.names, joint_state.positions
            )
        except Rejection as exc:
            return Outcome(stamp=joint_state.stamp, rejection=exc)
        except Exception as exc:  # never let a message take the caller down
            self.estimator.rejections["compute_error"] += 1
            return Outcome(stamp=joint_state.stamp, error=exc)
        return Outcome(stamp=joint_state.stamp)

    def undecodable(self, what: str, exc: UndecodableMessage) -> Outcome:
        """Bytes on the ``what`` input ('attitude', 'state', 'joint_states') that are no
        message: counted as ``undecodable``; the outcome's rejection says what was wrong."""
        self.estimator.rejections["undecodable"] += 1
        return Outcome(stamp=None, rejection=Rejection("undecodable", f"{what} message {exc}"))

    def _wrench(self, stamp: Stamp, quaternion, state: bool) -> Outcome:
        estimator = self.estimator
        try:
            sample = estimator.on_attitude(stamp_seconds(stamp), quaternion)
        except Rejection as exc:
            return Outcome(stamp=stamp, triggered=True, state_accepted=state, rejection=exc)
        except Exception as exc:  # never let a message take the caller down
            estimator.rejections["compute_error"] += 1
            return Outcome(stamp=stamp, triggered=True, state_accepted=state, error=exc)
        self._stamps = (self._stamps[1], stamp)
        return Outcome(stamp=stamp, triggered=True, state_accepted=state, sample=sample)

    def next_stamp(self) -> float | None:
        """The stamp [s] the next wrench most likely has: the latest plus the latest interval
        between wrenches (:func:`next_regular_stamp`); None before two wrenches."""
        previous, latest = self._stamps
        return None if previous is None else next_regular_stamp(previous, latest)

    def prepare_next(self) -> bool:
        """Compute ahead what the next regular attitude would wait for
        (:meth:`AeroWrenchEstimator.prepare` of :meth:`next_stamp`); whether it did."""
        expected = self.next_stamp()
        return expected is not None and self.estimator.prepare(expected)
