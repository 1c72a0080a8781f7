"""From attitude and orbital-state messages to the aerodynamic wrench: the node's logic, no ROS.

Frames: the state is in ECI (GCRF) or ECEF (ITRF); the quaternion (x, y, z, w) rotates body vectors
into it, v_state = R(q) v_body. Forces [N] and torques [N m] (about the centre of mass) are in the
body frame. Time and flight conditions: docs/node.md.
"""

from __future__ import annotations

import datetime as _dt
import math
import time
from collections import Counter

import numpy as np

from adbsat_ros.database.matching import DatabaseCoefficients
from adbsat_ros.environment.knots import KnotGrid
from adbsat_ros.estimator.conditions import PropagatedConditions
from adbsat_ros.estimator.diagnostics import diagnostic_values
from adbsat_ros.estimator.joints import JointStates
from adbsat_ros.estimator.parameters import BODY_PARAMETERS
from adbsat_ros.estimator.samples import OrbitalState, Rejection, WrenchSample
from adbsat_ros.estimator.settings import WrenchSettings, setup_from_settings
from adbsat_ros.estimator.state import (
    check_conditions,
    check_frame,
    checked_rotation,
    checked_state,
    conditions_rejection,
    jumps_back,
    odometry_inputs,
)
from adbsat_ros.estimator.sunlight import SolarPressureSource
from adbsat_ros.estimator.timing import stamp_utc
from adbsat_ros.estimator.wrench import Moment, wrench_sample
from adbsat_ros.physics.model import Model, build_model


class AeroWrenchEstimator:
    """Aerodynamic wrench from attitude and orbital-state inputs (the ROS node's core).

    settings: everything but the ROS plumbing (:data:`adbsat_ros.estimator.parameters.PARAMETERS`).
    mesh: an already loaded PanelMesh or ArticulatedBody (default: load ``settings.mesh``).
    ValueError: settings that cannot be applied; MeshError: a mesh that cannot be loaded.
    """

    def __init__(self, settings: WrenchSettings, mesh=None):
        self._panels = build_model(setup_from_settings(settings), mesh)  # (no database lookup)
        self.body = self._panels.body
        self.mesh = self._panels.mesh
        self.joints = None
        self.rejections: Counter = Counter()
        self.published = 0
        self._state: OrbitalState | None = None
        self._last_attitude_stamp: float | None = None
        self._last_state_stamp: float | None = None
        self._solar: SolarPressureSource | None = None
        self._attitude_frame = ""
        self.settings = None
        self.knots = None
        self.apply_settings(settings)

    # ----------------------------------------------------------------------------- settings
    def apply_settings(self, settings: WrenchSettings) -> None:
        """Switch to new settings; ValueError (and the old ones kept) if they do not apply."""
        if self.settings is not None:
            for name in BODY_PARAMETERS:
                if getattr(settings, name) != getattr(self.settings, name):
                    raise ValueError(
                        f"parameter {name}: the mesh is loaded once at start-up and cannot change"
                    )
        setup = setup_from_settings(settings)
        panels = self._panels
        panels = panels if setup == panels.setup else panels.with_setup(setup)
        if panels.articulated and settings.solar_pressure:
            raise ValueError(
                "parameter solar_pressure: not available for an articulated body (the solar "
                "radiation pressure is computed for rigid bodies only); set it false"
            )
        model, database = panels, None
        if settings.coefficients_source == "database":
            database = _database(settings, panels)
            model = panels.with_lookup(database.body_coefficients)
        conditions = PropagatedConditions(settings)
        solar = None
        if settings.solar_pressure:  # (shaded through the panels' cache, uncounted)
            solar = SolarPressureSource(
                panels, settings.state_frame, conditions.options.orientation_options
            )
        if self.knots is None:
            self.knots = KnotGrid(settings.conditions_step, conditions)
        else:  # the knots of the old settings go, the counters run on
            self.knots.configure(settings.conditions_step, conditions)
        if self.body is not None:
            if self.joints is None:
                self.joints = JointStates(self.body)
            self.joints.configure(settings.joint_state_timeout, model.prepare_joints)
        _ = panels.cache  # (with its shader: made here, not at the first attitude)
        self._panels, self.model, self.database = panels, model, database
        self._attitude_frame = ""  # (the frame names may have changed)
        self.method = model.method
        self._solar = solar
        self.settings = settings

    @property
    def state(self) -> OrbitalState | None:
        """The latest accepted orbital state (None before the first or after a reset)."""
        return self._state

    def utc(self, stamp: float) -> _dt.datetime:
        """UTC of a message stamp [s] per ``time_mode``."""
        return stamp_utc(stamp, self.settings.time_mode, self.settings.epoch_utc)

    def reset(self) -> None:
        """Forget the state, the last stamps and the knots (e.g. after time jumped back)."""
        self._state = None
        self._last_attitude_stamp = None
        self._last_state_stamp = None
        self.knots.clear()
        if self.joints is not None:
            self.joints.clear()

    # ----------------------------------------------------------------------------- inputs
    def on_state(
        self,
        stamp: float,
        position,
        velocity,
        velocity_in_body_frame: bool = False,
        orientation_xyzw=None,
    ) -> OrbitalState:
        """Accept an orbital state; a refused one leaves the latest state and its knots in place.

        stamp: message time [s]; position [m], velocity [m/s]: in the state frame (the velocity in
        the body frame if ``velocity_in_body_frame``, then with ``orientation_xyzw`` (x, y, z, w)).
        Rejection: ``non_finite``, ``bad_quaternion``, ``altitude_out_of_range``, ``bad_state``,
        ``out_of_order``, ``conflicting_state`` or ``time_backwards`` (history restarts here).
        """
        try:
            state = checked_state(
                stamp,
                position,
                velocity,
                velocity_in_body_frame,
                orientation_xyzw,
                self.settings.max_quaternion_norm_error,
                self.settings.min_altitude,
            )
            last = self._last_state_stamp
            restart = jumps_back(stamp, last, self.settings.time_jump_reset, "state")
            if stamp == last and state != self._state:  # a duplicate stamp that disagrees
                raise Rejection(
                    "conflicting_state",
                    f"a second state at stamp {stamp!r} s with other numbers: the first is kept",
                )
            if state != self._state:  # (the model takes it at its own stamp)
                check_conditions(self.knots.evaluate, self.utc, state)
        except Rejection as exc:
            self.rejections[exc.reason] += 1
            raise
        if restart:
            self.reset()
            self._last_state_stamp, self._state = stamp, state
            self.rejections["time_backwards"] += 1
            raise Rejection(
                "time_backwards",
                f"state time went back by {last - stamp:.3f} s: history reset, state kept",
            )
        self._last_state_stamp, self._state = stamp, state
        return state

    def on_odometry(self, msg) -> tuple:
        """Accept a nav_msgs/Odometry state; returns ``(state, orientation_xyzw)`` of the pose.

        Frame rules: :func:`~.state.odometry_inputs`. Rejection: ``bad_state`` for a frame mismatch
        or an unknown child_frame_id, and those of :meth:`on_state`.
        """
        s = self.settings
        try:
            stamp, position, velocity, in_body, orientation = odometry_inputs(
                msg, s.state_frame, s.body_frame_id, s.frame_ids
            )
        except Rejection as exc:
            self.rejections[exc.reason] += 1
            raise
        return self.on_state(stamp, position, velocity, in_body, orientation), orientation

    def on_joint_state(self, stamp: float, names, positions) -> dict:
        """Accept a JointState (stamp [s], positions [rad or m]); returns the positions taken.

        Rejection: ``bad_joint_state`` (also for a rigid mesh); nothing is taken.
        """
        try:
            if self.joints is None:
                raise Rejection(
                    "bad_joint_state", "joint_state for a rigid mesh: the body has no joints"
                )
            return self.joints.on_joint_state(stamp, names, positions)
        except Rejection as exc:
            self.rejections[exc.reason] += 1
            raise

    def on_attitude(self, stamp: float, quaternion_xyzw, frame_id: str = "") -> WrenchSample:
        """The wrench at an attitude (stamp [s], quaternion (x, y, z, w) in the state frame, which
        a non-empty ``frame_id`` must name: else ``bad_attitude_frame``, see ``check_frame``).

        Rejection: with its reason, counted in :attr:`rejections` (``time_backwards``: reset).
        """
        t0 = time.perf_counter()
        try:
            if frame_id and frame_id != self._attitude_frame:
                s = self.settings
                check_frame(frame_id, "attitude", s.state_frame, s.frame_ids, s.body_frame_id)
                self._attitude_frame = frame_id  # (the latest name taken: checked once)
            sample = self._sample(stamp, quaternion_xyzw, t0)
            if self._solar is not None:
                sample = self._solar.with_sunlight(sample, t0)
            if not all(map(math.isfinite, [*sample.force.tolist(), *sample.torque.tolist()])):
                raise Rejection("compute_error", "the wrench is not finite: nothing published")
        except Rejection as exc:
            self.rejections[exc.reason] += 1
            raise
        self.published += 1
        return sample

    def _sample(self, stamp: float, quaternion_xyzw, t0: float) -> WrenchSample:
        """:meth:`on_attitude` without the counting."""
        s = self.settings
        if not math.isfinite(stamp):
            raise Rejection("non_finite", "attitude stamp is not finite")
        m = checked_rotation(quaternion_xyzw, "attitude quaternion", s.max_quaternion_norm_error)
        last = self._last_attitude_stamp
        if jumps_back(stamp, last, s.time_jump_reset, "attitude"):
            self.reset()
            raise Rejection(
                "time_backwards", f"attitude time went back by {last - stamp:.3f} s: history reset"
            )
        state = self._state
        if state is None:
            raise Rejection("no_state", "no orbital state received yet")
        dt = stamp - state.stamp
        if abs(dt) > s.state_timeout:
            raise Rejection(
                "stale_state",
                f"latest state is {dt:.3f} s from the attitude stamp "
                f"(state_timeout {s.state_timeout:g} s)",
            )
        joints = None if self.joints is None else self.joints.configuration_at(stamp)
        self._last_attitude_stamp = stamp
        try:
            utc = self.utc(stamp)
        except (ValueError, OverflowError) as exc:  # e.g. a UNIX stamp beyond year 9999
            raise Rejection(
                "bad_state", f"attitude stamp {stamp!r} s is no UTC time: {exc}"
            ) from None
        try:
            conditions = self.knots.conditions(state, stamp, utc)
            flow = conditions.free_stream() if conditions.speed > 0.0 else None
        except ValueError as exc:
            raise conditions_rejection(exc, str(exc)) from None
        if flow is None or conditions.speed < s.min_relative_speed:  # at rest in the air
            reference, zero = self.method.reference, np.zeros(3)
            return WrenchSample(
                stamp, utc, zero, zero.copy(), zero.copy(), zero.copy(), reference.area,
                reference.length, 0.0, conditions, None, zero.copy(), time.perf_counter() - t0, m
            )  # fmt: skip
        # gas motion relative to the body, body axes: -R^T v_rel (its direction is the flow's)
        relative = (
            conditions.relative_velocity_eci
            if s.state_frame == "eci"
            else conditions.relative_velocity_ecef
        )
        gas_body = -(relative @ np.array(m).reshape(3, 3))
        moment = Moment(stamp, utc, conditions, m, t0)
        changes = None  # (the materials' accommodation, or the model's at the conditions)
        if s.accommodation_model != "fixed":
            changes = {"alpha": conditions.alpha, "alpha_n": conditions.alpha}
        return wrench_sample(self.model, gas_body, flow, changes, joints, moment)

    def prepare(self, stamp: float) -> bool:
        """Compute the knots an attitude expected at ``stamp`` [s] would wait for; True if done."""
        state, last = self._state, self._last_attitude_stamp
        if state is None or not math.isfinite(stamp) or (last is not None and stamp <= last):
            return False
        if abs(stamp - state.stamp) > self.settings.state_timeout:
            return False
        return self.knots.prepare(state, stamp)

    def diagnostic_values(self, last_sample: WrenchSample | None, compute_ms) -> dict:
        """Key/values of the node's DiagnosticStatus; ``compute_ms``: recent compute times [ms]."""
        return diagnostic_values(self, last_sample, compute_ms)


def _database(settings: WrenchSettings, panels: Model) -> DatabaseCoefficients:
    """The database of ``database_path`` for the panels' method; ValueError if it does not apply."""
    if panels.articulated:
        raise ValueError(
            "parameter coefficients_source: a database is made for one rigid mesh; an "
            "articulated body needs coefficients_source panel"
        )
    if settings.accommodation_model != "fixed":
        raise ValueError(
            "parameter accommodation_model: coefficients_source database needs a fixed "
            "accommodation (the database was made at one alpha), got "
            f"{settings.accommodation_model}"
        )
    return DatabaseCoefficients(settings.database_path, panels.method)
