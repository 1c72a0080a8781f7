"""The output messages of one wrench as CDR bytes, for the node and the bag analysis alike.

Joint torques (sensor_msgs/JointState) by the caller's serialiser, the rest by
:mod:`adbsat_ros.messages.cdr`.
"""

from __future__ import annotations

from typing import Callable, NamedTuple

from adbsat_ros.messages.cdr import Stamp, accel_stamped_cdr, wrench_stamped_cdr


class WrenchMessages(NamedTuple):
    """The CDR bytes of the messages of one wrench; None for a message not made.

    Attributes
    ----------
    wrench : bytes
        WrenchStamped: force [N] and torque [N m] about the centre of mass, body frame.
    coefficients : bytes or None
        WrenchStamped of the coefficients (C_F in ``force``, C_M in ``torque``).
    inertial : bytes or None
        WrenchStamped: force [N] in the ``state_frame``, torque [N m] in the body frame.
    acceleration : bytes or None
        AccelStamped (needs ``mass``): force / mass [m/s^2] in the state frame and, with an
        ``inertia``, inertia^-1 torque [rad/s^2] in the body frame. With ``solar_pressure`` on,
        ``inertial`` and ``acceleration`` carry the total of both wrenches.
    solar, total : bytes or None
        With ``solar_pressure`` on: the solar pressure wrench and aero plus solar, body frame.
    joint_torques : bytes or None
        Articulated body: JointState with each moving joint's name, position used and, as
        ``effort``, the aerodynamic torque about its axis [N m] (force for a prismatic one [N]).
    """

    wrench: bytes
    coefficients: bytes | None = None
    inertial: bytes | None = None
    acceleration: bytes | None = None
    solar: bytes | None = None
    total: bytes | None = None
    joint_torques: bytes | None = None


def encode_wrench(
    stamp: Stamp,
    sample,
    settings,
    serialise_joint_state: Callable | None = None,
    coefficients: bool = True,
    inertial: bool = False,
    joint_torques: bool = True,
) -> WrenchMessages:
    """The messages of one wrench sample, stamped ``stamp``.

    Parameters
    ----------
    stamp : Stamp
        The input message's header stamp.
    sample : WrenchSample
        The estimator's sample.
    settings : WrenchSettings
        Its ``body_frame_id``, ``state_frame``, ``mass`` and ``inertia`` are read.
    serialise_joint_state : callable or None
        ``serialise_joint_state(stamp, frame_id, names, positions, efforts)`` -> CDR bytes of a
        JointState; needed for an articulated body's joint torques.
    coefficients, inertial, joint_torques : bool
        Whether to make the coefficients message, the state-frame wrench and acceleration, and the
        joint torques.
    """
    frame = settings.body_frame_id
    sec, nanosec = stamp.sec, stamp.nanosec
    wrench = wrench_stamped_cdr(sec, nanosec, frame, sample.force.tolist(), sample.torque.tolist())
    coefficients_cdr = inertial_cdr = acceleration_cdr = solar_cdr = total_cdr = joints_cdr = None
    if coefficients:
        coefficients_cdr = wrench_stamped_cdr(
            sec,
            nanosec,
            frame,
            sample.force_coefficients.tolist(),
            sample.moment_coefficients.tolist(),
        )
    if inertial:
        force, torque, linear, angular = sample.state_frame_wrench(settings.mass, settings.inertia)
        state_frame = settings.state_frame
        inertial_cdr = wrench_stamped_cdr(
            sec, nanosec, state_frame, force.tolist(), torque.tolist()
        )
        if linear is not None:
            acceleration_cdr = accel_stamped_cdr(
                sec, nanosec, state_frame, linear.tolist(), angular.tolist()
            )
    solar = sample.solar
    if solar is not None:
        solar_cdr = wrench_stamped_cdr(
            sec, nanosec, frame, solar.force.tolist(), solar.torque.tolist()
        )
        total_cdr = wrench_stamped_cdr(
            sec, nanosec, frame, sample.total_force.tolist(), sample.total_torque.tolist()
        )
    joints = sample.joints
    if joint_torques and joints is not None:
        joints_cdr = serialise_joint_state(
            stamp, frame, joints.names, joints.positions, joints.efforts
        )
    return WrenchMessages(
        wrench, coefficients_cdr, inertial_cdr, acceleration_cdr, solar_cdr, total_cdr, joints_cdr
    )
