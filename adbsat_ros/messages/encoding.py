"""The output messages of one wrench as CDR bytes, for the node and the bag analysis."""

from __future__ import annotations

from typing import NamedTuple

from adbsat_ros.messages.cdr import Stamp, accel_stamped_cdr, joint_state_cdr, wrench_stamped_cdr


class WrenchMessages(NamedTuple):
    """The CDR bytes of one wrench's messages (fields, units: docs/node.md); None: not made.

    ``wrench``: force [N], torque [N m] about the centre of mass, body frame; ``inertial``:
    force in the ``state_frame``; ``acceleration`` [m/s^2, rad/s^2]; ``joint_torques``:
    ``effort`` [N m or N].
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
    *,
    coefficients: bool = True,
    inertial: bool = False,
    joint_torques: bool = True,
) -> WrenchMessages:
    """The messages of one wrench sample, stamped ``stamp`` (the input's header stamp); the
    flags say which optional messages to make."""
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
        joints_cdr = joint_state_cdr(stamp, frame, joints.names, joints.positions, joints.efforts)
    return WrenchMessages(
        wrench, coefficients_cdr, inertial_cdr, acceleration_cdr, solar_cdr, total_cdr, joints_cdr
    )
