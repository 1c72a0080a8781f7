"""Accepting inputs: the checks of a quaternion and an orbital state, and the Odometry frame rules.

Each function checks one message's contents and raises
:class:`~adbsat_ros.estimator.samples.Rejection` with the reason when it cannot be used; the
estimator counts the rejection and keeps the ordering rules (time going back, stale states).

Frames: the state (position, and velocity unless it is given in the body frame) is in ECI (GCRF)
or ECEF (ITRF) as the settings say; a quaternion (x, y, z, w) rotates body-frame vectors into
that frame, v_state = R(q) v_body.
"""

from __future__ import annotations

import math

import numpy as np

from adbsat_ros.estimator.samples import OrbitalState, Rejection
from adbsat_ros.geometry.frames import quaternion_matrix_floats
from adbsat_ros.messages.cdr import OdometryFields
from adbsat_ros.messages.stamps import stamp_seconds

#: Names accepted in Odometry.child_frame_id for a twist already in the state frame.
STATE_FRAME_NAMES = ("", "eci", "ecef", "gcrf", "itrf", "j2000", "earth", "world", "map")


def checked_rotation(quaternion_xyzw, what: str, max_norm_error: float) -> tuple:
    """The rotation matrix (body -> state frame) of a quaternion, checked.

    Parameters
    ----------
    quaternion_xyzw : sequence of 4 numbers
        (x, y, z, w); normalised here.
    what : str
        What the quaternion is, for the messages ("attitude quaternion", ...).
    max_norm_error : float
        Largest accepted | |q| - 1 |.

    Returns
    -------
    tuple of 9 floats
        R(q / |q|), row-major.

    Raises
    ------
    Rejection
        ``non_finite`` (not four finite numbers) or ``bad_quaternion`` (norm too far from 1).
    """
    try:
        x, y, z, w = quaternion_xyzw
        x, y, z, w = float(x), float(y), float(z), float(w)
    except (TypeError, ValueError):
        raise Rejection("non_finite", f"{what} is not four numbers") from None
    if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z) and math.isfinite(w)):
        raise Rejection("non_finite", f"{what} has NaN or Inf")
    norm = math.sqrt(x * x + y * y + z * z + w * w)
    if abs(norm - 1.0) > max_norm_error:
        raise Rejection(
            "bad_quaternion",
            f"{what} norm {norm:.6g} differs from 1 by more than {max_norm_error:g}",
        )
    return quaternion_matrix_floats(x / norm, y / norm, z / norm, w / norm)


def checked_state(
    stamp: float,
    position,
    velocity,
    velocity_in_body_frame: bool,
    orientation_xyzw,
    max_norm_error: float,
) -> OrbitalState:
    """An orbital state from a message's numbers, its velocity in the state frame.

    Parameters
    ----------
    stamp : float
        Message time [s].
    position : array_like, shape (3,)
        Position in the state frame [m].
    velocity : array_like, shape (3,)
        Velocity [m/s]: in the state frame, or in the body frame if ``velocity_in_body_frame``
        (then ``orientation_xyzw``, the body's orientation in the state frame, rotates it).
    velocity_in_body_frame : bool
        Where ``velocity`` is given.
    orientation_xyzw : sequence of 4 numbers or None
        Body orientation (x, y, z, w), needed for a body-frame velocity.
    max_norm_error : float
        Largest accepted | |q| - 1 | of the orientation.

    Raises
    ------
    Rejection
        ``non_finite`` (NaN or Inf in the stamp or a vector) or ``bad_quaternion``.
    """
    position = np.asarray(position, dtype=float)
    velocity = np.asarray(velocity, dtype=float)
    if not (
        math.isfinite(stamp) and np.all(np.isfinite(position)) and np.all(np.isfinite(velocity))
    ):
        raise Rejection("non_finite", "state has NaN or Inf in its stamp, position or velocity")
    if velocity_in_body_frame:
        rotation = checked_rotation(orientation_xyzw, "state orientation", max_norm_error)
        velocity = np.array(rotation).reshape(3, 3) @ velocity
    return OrbitalState(stamp, position, velocity)


def odometry_inputs(msg, state_frame: str, body_frame_id: str) -> tuple:
    """What an Odometry message gives :func:`checked_state`, by the frame rules.

    ``header.frame_id`` naming 'eci' or 'ecef' must match ``state_frame``. The twist is in the
    body frame if ``child_frame_id`` is ``body_frame_id`` (it is then rotated with the pose
    orientation), in the state frame if ``child_frame_id`` is empty, one of
    :data:`STATE_FRAME_NAMES` or the header's frame_id.

    Parameters
    ----------
    msg : object
        A nav_msgs/Odometry (rclpy or rosbags) or its
        :class:`~adbsat_ros.messages.cdr.OdometryFields`.
    state_frame : {"eci", "ecef"}
        The frame states are expected in.
    body_frame_id : str
        The body (mesh) frame's name.

    Returns
    -------
    tuple
        ``(stamp [s], position, linear velocity, velocity_in_body_frame, orientation_xyzw)``,
        vectors as lists of floats.

    Raises
    ------
    Rejection
        ``bad_state`` for a frame mismatch or a child_frame_id that is neither frame.
    """
    odom = msg if isinstance(msg, OdometryFields) else OdometryFields.of_message(msg)
    header_frame = odom.frame_id.lstrip("/")
    frame = header_frame.lower()
    if frame in ("eci", "ecef") and frame != state_frame:
        raise Rejection(
            "bad_state", f"state frame_id '{frame}' but parameter state_frame is {state_frame}"
        )
    child = odom.child_frame_id.lstrip("/")
    if child == body_frame_id:
        in_body = True
    elif child.lower() in STATE_FRAME_NAMES or child == header_frame:
        in_body = False
    else:
        raise Rejection(
            "bad_state",
            f"twist child_frame_id '{child}' is neither the body frame '{body_frame_id}' "
            "nor the state frame",
        )
    return (
        stamp_seconds(odom.stamp),
        list(odom.position),
        list(odom.linear_velocity),
        in_body,
        list(odom.orientation_xyzw),
    )
