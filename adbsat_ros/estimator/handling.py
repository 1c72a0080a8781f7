"""One input message through the estimator: the per-message path of the node and the bag analysis.

:class:`MessageHandler` takes the decoded fields of an attitude or state message
(:mod:`adbsat_ros.messages.decoding`), feeds them to an
:class:`~adbsat_ros.estimator.estimator.AeroWrenchEstimator` with the node's rules (a rejected
input is counted by its reason; any other failure is counted as ``compute_error`` and never
stops the caller; with ``attitude_source`` odometry a state's pose is the attitude) and returns
an :class:`Outcome`: the sample or why there is none, and the CDR bytes of the wrench and
coefficient messages to publish. The ROS node publishes from it; the bag analysis writes it.
Both therefore compute and serialise every message the same way, bit for bit.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.samples import Rejection, WrenchSample
from adbsat_ros.messages.cdr import (
    AttitudeFields,
    JointStateFields,
    OdometryFields,
    Stamp,
    accel_stamped_cdr,
    joint_state_cdr,
    wrench_stamped_cdr,
)
from adbsat_ros.messages.decoding import UndecodableMessage
from adbsat_ros.messages.stamps import next_regular_stamp, stamp_seconds


class Outcome(NamedTuple):
    """What one input message came to.

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
    wrench_cdr : bytes or None
        CDR bytes of the geometry_msgs/WrenchStamped: force [N] and torque [N m] about the
        centre of mass, body frame (``body_frame_id``), stamped like the message.
    coefficients_cdr : bytes or None
        CDR bytes of the coefficients' WrenchStamped (C_F in ``force``, C_M in ``torque``), when
        asked for.
    inertial_cdr : bytes or None
        When asked for: CDR bytes of a WrenchStamped with the force [N] in the state frame (its
        frame_id the state frame's, ``state_frame``) and the torque [N m] in the body frame, as
        torques are applied.
    acceleration_cdr : bytes or None
        When asked for and a ``mass`` is set: CDR bytes of a geometry_msgs/AccelStamped, the
        non-gravitational acceleration force / mass [m/s^2] in the state frame and, with an
        ``inertia``, the angular acceleration inertia^-1 torque [rad/s^2] in the body frame.
        (With ``solar_pressure`` on, these two carry the total of both wrenches.)
    solar_cdr, total_cdr : bytes or None
        With ``solar_pressure`` on: CDR bytes of the solar radiation pressure WrenchStamped and
        of the aerodynamic plus solar one, body frame, stamped like the message.
    joint_torques_cdr : bytes or None
        For an articulated body: CDR bytes of a sensor_msgs/JointState, stamped like the
        message, with every moving joint's name, the position used and, as ``effort``, the
        aerodynamic torque about its axis [N m] (force along a prismatic one [N]).
    """

    stamp: Stamp | None
    triggered: bool = False
    state_accepted: bool = False
    sample: WrenchSample | None = None
    rejection: Rejection | None = None
    error: Exception | None = None
    wrench_cdr: bytes | None = None
    coefficients_cdr: bytes | None = None
    inertial_cdr: bytes | None = None
    acceleration_cdr: bytes | None = None
    solar_cdr: bytes | None = None
    total_cdr: bytes | None = None
    joint_torques_cdr: bytes | None = None

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
IGNORED = Outcome(None)


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

    def on_state(
        self,
        odometry: OdometryFields,
        coefficients: bool = True,
        inertial: bool = False,
        joint_torques: bool = True,
    ) -> Outcome:
        """A state message: accepted (and with ``attitude_source`` odometry, its wrench), or not.

        Parameters
        ----------
        odometry : OdometryFields
            The decoded nav_msgs/Odometry.
        coefficients : bool
            Whether to serialise the coefficients message too.
        inertial : bool
            Whether to serialise the state-frame wrench and the acceleration too.
        joint_torques : bool
            Whether to serialise an articulated body's joint torques too.
        """
        try:
            _, orientation = self.estimator.on_odometry(odometry)
        except Rejection as exc:
            return Outcome(odometry.stamp, rejection=exc)
        except Exception as exc:  # never let a message take the caller down
            self.estimator.rejections["compute_error"] += 1
            return Outcome(odometry.stamp, error=exc)
        if self.uses_attitude_topic:
            return Outcome(odometry.stamp, state_accepted=True)
        return self._wrench(
            odometry.stamp, orientation, coefficients, True, inertial, joint_torques
        )

    def on_attitude(
        self,
        attitude: AttitudeFields,
        coefficients: bool = True,
        inertial: bool = False,
        joint_torques: bool = True,
    ) -> Outcome:
        """An attitude message: its wrench, or why there is none (:data:`IGNORED` while the
        attitude comes from the odometry pose).

        Parameters
        ----------
        attitude : AttitudeFields
            The decoded geometry_msgs/QuaternionStamped.
        coefficients : bool
            Whether to serialise the coefficients message too.
        inertial : bool
            Whether to serialise the state-frame wrench and the acceleration too.
        joint_torques : bool
            Whether to serialise an articulated body's joint torques too.
        """
        if not self.uses_attitude_topic:
            return IGNORED
        return self._wrench(
            attitude.stamp,
            attitude.quaternion_xyzw,
            coefficients,
            False,
            inertial,
            joint_torques,
        )

    def on_joint_state(self, joint_state: JointStateFields) -> Outcome:
        """A joint_states message: its positions taken for the next wrenches, or refused
        (``bad_joint_state``, counted); it asks for no wrench."""
        try:
            self.estimator.on_joint_state(
                stamp_seconds(joint_state.stamp), joint_state.names, joint_state.positions
            )
        except Rejection as exc:
            return Outcome(joint_state.stamp, rejection=exc)
        except Exception as exc:  # never let a message take the caller down
            self.estimator.rejections["compute_error"] += 1
            return Outcome(joint_state.stamp, error=exc)
        return Outcome(joint_state.stamp)

    def undecodable(self, what: str, exc: UndecodableMessage) -> Outcome:
        """Bytes on the ``what`` input ('attitude', 'state', 'joint_states') that are no
        message: counted as ``undecodable``; the outcome's rejection says what was wrong."""
        self.estimator.rejections["undecodable"] += 1
        return Outcome(None, rejection=Rejection("undecodable", f"{what} message {exc}"))

    def _wrench(
        self,
        stamp: Stamp,
        quaternion,
        coefficients: bool,
        state: bool,
        inertial: bool = False,
        joint_torques: bool = True,
    ) -> Outcome:
        estimator = self.estimator
        try:
            sample = estimator.on_attitude(stamp_seconds(stamp), quaternion)
        except Rejection as exc:
            return Outcome(stamp, True, state, rejection=exc)
        except Exception as exc:  # never let a message take the caller down
            estimator.rejections["compute_error"] += 1
            return Outcome(stamp, True, state, error=exc)
        frame = estimator.settings.body_frame_id
        sec, nanosec = stamp.sec, stamp.nanosec
        wrench = wrench_stamped_cdr(
            sec, nanosec, frame, sample.force.tolist(), sample.torque.tolist()
        )
        coefficients_cdr = None
        if coefficients:
            coefficients_cdr = wrench_stamped_cdr(
                sec,
                nanosec,
                frame,
                sample.force_coefficients.tolist(),
                sample.moment_coefficients.tolist(),
            )
        inertial_cdr = acceleration_cdr = solar_cdr = total_cdr = None
        if inertial:
            inertial_cdr, acceleration_cdr = self._inertial(stamp, sample)
        if sample.solar is not None:
            solar_cdr = wrench_stamped_cdr(
                sec, nanosec, frame, sample.solar.force.tolist(), sample.solar.torque.tolist()
            )
            total_cdr = wrench_stamped_cdr(
                sec, nanosec, frame, sample.total_force.tolist(), sample.total_torque.tolist()
            )
        joints_cdr = None
        if joint_torques and sample.joints is not None:
            joints = sample.joints
            joints_cdr = joint_state_cdr(
                sec, nanosec, frame, joints.names, joints.positions, (), joints.efforts
            )
        self._stamps = (self._stamps[1], stamp)
        return Outcome(
            stamp,
            True,
            state,
            sample,
            None,
            None,
            wrench,
            coefficients_cdr,
            inertial_cdr,
            acceleration_cdr,
            solar_cdr,
            total_cdr,
            joints_cdr,
        )

    def _inertial(self, stamp: Stamp, sample: WrenchSample) -> tuple:
        """The state-frame wrench and (with a mass) the acceleration, as CDR bytes: of the
        aerodynamic wrench, plus the solar one with ``solar_pressure`` on."""
        settings = self.estimator.settings
        force = np.array(sample.rotation).reshape(3, 3) @ sample.total_force
        frame = settings.state_frame
        torque = sample.total_torque.tolist()
        inertial = wrench_stamped_cdr(stamp.sec, stamp.nanosec, frame, force.tolist(), torque)
        if settings.mass <= 0.0:
            return inertial, None
        angular = [0.0, 0.0, 0.0]
        if settings.inertia is not None:
            tensor = np.array(settings.inertia).reshape(3, 3)
            angular = np.linalg.solve(tensor, sample.total_torque).tolist()
        linear = (force / settings.mass).tolist()
        return inertial, accel_stamped_cdr(stamp.sec, stamp.nanosec, frame, linear, angular)

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
