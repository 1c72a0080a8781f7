"""Accepting inputs: the checks of a quaternion and an orbital state, and the Odometry frame rules.

Each raises :class:`~adbsat_ros.estimator.samples.Rejection` with the reason. A quaternion
(x, y, z, w) rotates body vectors into the state frame (ECI or ECEF), v_state = R(q) v_body.
"""

from __future__ import annotations

import math

import numpy as np

from adbsat_ros.bounds import BOUNDS
from adbsat_ros.environment.atmosphere import FIRST_YEAR, LAST_YEAR, MAX_ALTITUDE
from adbsat_ros.environment.geodetic import geodetic_of
from adbsat_ros.estimator.samples import OrbitalState, Rejection
from adbsat_ros.geometry.frames import quaternion_matrix_floats
from adbsat_ros.messages.decoding import OdometryFields
from adbsat_ros.messages.stamps import stamp_seconds

#: Largest difference [m] between the geodetic altitudes of a position read in the state frame
#: and in ECEF (an ECI position taken as ECEF: the pole's drift since J2000).
FRAME_ALTITUDE_MARGIN = 1e3


def jumps_back(stamp: float, latest: float | None, time_jump_reset: float, what: str) -> bool:
    """Whether ``stamp`` [s] is ``time_jump_reset`` before ``latest``; less: ``out_of_order``."""
    if latest is None or stamp >= latest:
        return False
    back = latest - stamp
    if back > time_jump_reset:
        return True
    raise Rejection(
        "out_of_order",
        f"{what} stamp {back:.3f} s before the latest {what}: refused alone (the state is kept)",
    )


def checked_rotation(quaternion_xyzw, what: str, max_norm_error: float) -> tuple:
    """R(q / |q|), body to state frame, row-major; Rejection non_finite or bad_quaternion."""
    try:
        x, y, z, w = quaternion_xyzw
        x, y, z, w = float(x), float(y), float(z), float(w)
    except (TypeError, ValueError):
        raise Rejection("non_finite", f"{what} is not four numbers") from None
    if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z) and math.isfinite(w)):
        raise Rejection("non_finite", f"{what} has NaN or Inf")
    norm = math.hypot(x, y, z, w)
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
    min_altitude: float = 0.0,
) -> OrbitalState:
    """An orbital state, velocity in the state frame (arguments as ``on_state``'s)."""
    position = np.asarray(position, dtype=float)
    velocity = np.asarray(velocity, dtype=float)
    if not (
        math.isfinite(stamp) and np.all(np.isfinite(position)) and np.all(np.isfinite(velocity))
    ):
        raise Rejection("non_finite", "state has NaN or Inf in its stamp, position or velocity")
    altitude = geodetic_of(position)[2]
    if altitude < min_altitude:  # (an ECI position taken as ECEF: the pole's drift, < 1 km)
        raise Rejection(
            "altitude_out_of_range",
            f"state altitude {altitude / 1e3:.1f} km is below min_altitude "
            f"{min_altitude / 1e3:g} km (the flow is not free-molecular there)",
        )
    speed = math.hypot(*velocity.tolist())  # (no overflow for huge components)
    if not BOUNDS["orbital_speed"].contains(speed):
        rule = BOUNDS["orbital_speed"]
        raise Rejection(
            "bad_state", f"state speed {speed:.6g} m/s is not in {rule.text()} ({rule.reason})"
        )
    if velocity_in_body_frame:
        rotation = checked_rotation(orientation_xyzw, "state orientation", max_norm_error)
        velocity = np.array(rotation).reshape(3, 3) @ velocity
    return OrbitalState(stamp, position, velocity)


def check_conditions(evaluate, utc, state: OrbitalState) -> None:
    """Refuse a state whose flight conditions cannot be evaluated at its stamp (Rejection)."""
    where = f"state at stamp {state.stamp!r} s"
    try:
        year = utc(state.stamp).year
    except (ValueError, OverflowError) as exc:  # e.g. a UNIX stamp beyond the year 9999
        raise Rejection(
            "bad_state", f"{where} is no UTC time ({exc}): the latest state is kept"
        ) from None
    if not FIRST_YEAR <= year <= LAST_YEAR:
        raise Rejection(
            "bad_state",
            f"{where} is in the year {year}, outside {FIRST_YEAR}..{LAST_YEAR} (the years of the "
            "atmosphere model's space weather and the time scales): the latest state is kept",
        )
    altitude = geodetic_of(state.position)[2]
    if altitude > MAX_ALTITUDE + FRAME_ALTITUDE_MARGIN:
        km = f"{altitude / 1e3:.1f}" if altitude < 1e12 else f"{altitude / 1e3:.3e}"
        raise Rejection(
            "altitude_out_of_range",
            f"state altitude {km} km is above {MAX_ALTITUDE / 1e3:g} km, the top "
            "of the atmosphere model: the latest state is kept",
        )
    if altitude > MAX_ALTITUDE - FRAME_ALTITUDE_MARGIN:
        try:
            evaluate(state, state.stamp)
        except ValueError as exc:
            raise conditions_rejection(exc, f"{where}: {exc}; the latest state is kept") from None


def conditions_rejection(exc: ValueError, message: str) -> Rejection:
    """``altitude_out_of_range`` if ``exc`` is about the altitude, else ``bad_state``."""
    return Rejection("altitude_out_of_range" if "altitude" in str(exc) else "bad_state", message)


#: Names always taken as the body frame besides ``body_frame_id``: REP-105's and the old default.
BODY_FRAME_NAMES = ("base_link", "body")


def check_frame(name: str, what: str, state_frame: str, frame_ids, body_frame_id: str) -> None:
    """Rejection ``bad_<what>_frame`` unless frame ``name`` (any case, a leading "/" ignored)
    is one of the names of ``state_frame`` in ``frame_ids``; the message says what it names."""
    frame = name.lstrip("/").lower()
    own, other, other_name = (
        (frame_ids.eci, frame_ids.ecef, "ECEF")
        if state_frame == "eci"
        else (frame_ids.ecef, frame_ids.eci, "ECI")
    )
    if frame in own:
        return
    if frame in other:
        text = f"{what} frame_id '{frame}' is {other_name} but parameter state_frame is "
        text += state_frame
    elif frame in (body_frame_id.lower(), *BODY_FRAME_NAMES):
        text = f"{what} frame_id '{frame}' is the body frame, not the state frame ({state_frame})"
    else:
        text = (
            f"unknown frame_id '{frame}' of {'an' if what[0] in 'aeiou' else 'a'} {what}: not "
            f"among the names of eci_frame_ids ({', '.join(frame_ids.eci)}) or ecef_frame_ids "
            f"({', '.join(frame_ids.ecef)})"
        )
    raise Rejection(f"bad_{what}_frame", text)


def odometry_inputs(msg, state_frame: str, body_frame_id: str, frame_ids) -> tuple:
    """``(stamp [s], position, velocity, velocity_in_body_frame, orientation_xyzw)`` of an Odometry.

    ``header.frame_id`` must name ``state_frame`` (:func:`check_frame`). The twist is in the body
    frame if ``child_frame_id`` is ``body_frame_id`` (or one of :data:`BODY_FRAME_NAMES`), in the
    state frame if it is empty or names the state frame; else Rejection ``bad_state_frame``.
    """
    odom = msg if isinstance(msg, OdometryFields) else OdometryFields.of_message(msg)
    header_frame = odom.frame_id.lstrip("/")
    check_frame(header_frame, "state", state_frame, frame_ids, body_frame_id)
    own = frame_ids.eci if state_frame == "eci" else frame_ids.ecef
    child = odom.child_frame_id.lstrip("/")
    if child == body_frame_id or child in BODY_FRAME_NAMES:
        in_body = True
    elif child == "" or child == header_frame or child.lower() in own:
        in_body = False
    else:
        raise Rejection(
            "bad_state_frame",
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
