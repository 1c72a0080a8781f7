"""From attitude and orbital state messages to the aerodynamic wrench: the node's logic, no ROS.

:class:`AeroWrenchEstimator` holds the mesh (loaded once), the panel method, the shading cache
and the latest orbital state. The ROS node feeds it decoded messages; bag analysis feeds it the
same messages from a file, so both compute exactly the same numbers.

Frames: the state (position, and velocity unless it is given in the body frame) is in ECI (GCRF)
or ECEF (ITRF) as the settings say; the attitude quaternion (x, y, z, w) rotates body-frame
vectors into that frame, v_state = R(q) v_body; the body frame is the mesh frame. Forces [N] and
torques [N m] are returned in the body frame, torques about the centre of mass.

Flight conditions: the latest state is propagated to each attitude stamp at constant velocity.
With ``conditions_step`` h > 0 (default 10 ms) they are evaluated exactly (NRLMSISE-00, Earth
orientation, relative wind, accommodation) at the knots, the stamps ``j h`` for integers j, only
and interpolated linearly in between (:func:`adbsat_ros.environment.flight_conditions.interpolated_flight_conditions`;
density within ~2e-9 of an evaluation at the stamp itself at h = 10 ms). A stamp gets the same
numbers whatever messages came before it; one within 1 us of a knot takes the knot's alone.
"""

from __future__ import annotations

import datetime as _dt
import math
import time
from collections import Counter
from typing import NamedTuple

import numpy as np

from adbsat_ros.database.matching import DatabaseCoefficients
from adbsat_ros.environment.atmosphere import SpaceWeather
from adbsat_ros.environment.flight_conditions import (
    FlightConditions,
    flight_conditions,
    interpolated_flight_conditions,
)
from adbsat_ros.estimator.samples import OrbitalState, Rejection, WrenchSample
from adbsat_ros.estimator.settings import WrenchSettings, materials_from_settings
from adbsat_ros.geometry.frames import quaternion_matrix_floats
from adbsat_ros.geometry.loading import resolve_mesh
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.messages.cdr import OdometryFields
from adbsat_ros.messages.stamps import stamp_seconds
from adbsat_ros.physics.coefficients import AeroCoefficients, Reference
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.gsi_models import ModelOptions
from adbsat_ros.physics.panel_method import PanelMethod

#: Precession-nutation is evaluated once per minute of TT (error < 1e-9 rad; see earth_frames).
PRECESSION_NUTATION_STEP_S = 60.0

#: A stamp this close to a knot of the flight conditions [s] takes the knot's conditions alone:
#: UNIX stamps as float seconds resolve 0.24 us, so a stream stamped on multiples of
#: ``conditions_step`` (e.g. 100 Hz at the default 10 ms) lands on knots and needs one evaluation
#: per message, as without knots.
KNOT_SNAP_S = 1e-6
#: Knots kept per state: the two around the latest stamp, the one after them (prepare's
#: look-ahead), one spare.
KNOTS_KEPT = 4
#: :meth:`AeroWrenchEstimator.prepare` also evaluates the knot this many steps after the one at or
#: before the prepared stamp (when it evaluated no knot for that stamp itself), so that attitudes
#: served together that cross into the next interval find its far knot ready.
KNOT_LOOKAHEAD = 2

#: Names accepted in Odometry.child_frame_id for a twist already in the state frame.
STATE_FRAME_NAMES = ("", "eci", "ecef", "gcrf", "itrf", "j2000", "earth", "world", "map")


def _knot_position(stamp: float, step: float) -> tuple:
    """(j, past): the knot j step at or before ``stamp`` and the time past it [s], a stamp within
    KNOT_SNAP_S of a knot taking that knot (past = 0)."""
    j = math.floor(stamp / step)
    past = stamp - j * step  # [s] after knot j
    if past >= step - KNOT_SNAP_S:
        return j + 1, 0.0
    if past <= KNOT_SNAP_S:
        return j, 0.0
    return j, past


class _KeptConditions(NamedTuple):
    """Flight conditions kept by the estimator for one stamp (see ``_conditions_at``)."""

    state: OrbitalState
    stamp: float
    settings: WrenchSettings
    utc: _dt.datetime
    conditions: FlightConditions
    flow: FreeStream | None


class _ShadingSource:
    """Lighting for a flow direction, through the shading cache (or nothing for 'none')."""

    def __init__(self, mesh: PanelMesh, settings: WrenchSettings):
        self.key = (
            settings.shading,
            settings.shading_samples,
            settings.shading_cache_resolution_deg,
            settings.shading_cache_size,
        )
        self.cache = None
        if settings.shading != "none":
            from adbsat_ros.shading.cache import ShadingCache
            from adbsat_ros.shading.shader import make_shader

            shader = make_shader(mesh, mode=settings.shading, samples=settings.shading_samples)
            self.cache = ShadingCache(
                shader,
                resolution_deg=settings.shading_cache_resolution_deg,
                max_entries=settings.shading_cache_size,
            )

    def lighting(self, u_G):
        if self.cache is None:
            return None, None
        hits = self.cache.hits
        lighting = self.cache.lighting(u_G)
        return lighting, self.cache.hits > hits

    @property
    def hits(self) -> int:
        return 0 if self.cache is None else self.cache.hits

    @property
    def misses(self) -> int:
        return 0 if self.cache is None else self.cache.misses


class AeroWrenchEstimator:
    """Aerodynamic wrench from attitude and orbital-state inputs (the ROS node's core).

    Parameters
    ----------
    settings : WrenchSettings
        Everything but the ROS plumbing (see :data:`adbsat_ros.estimator.settings.PARAMETERS`).
    mesh : PanelMesh, optional
        An already loaded mesh (default: load ``settings.mesh`` once).

    Raises
    ------
    MeshError
        If the mesh cannot be loaded.
    ValueError
        For settings that cannot be applied (e.g. an unknown material name).
    """

    def __init__(self, settings: WrenchSettings, mesh: PanelMesh | None = None):
        self.mesh = mesh if mesh is not None else resolve_mesh(settings.mesh, settings.mesh_scale)
        self.rejections: Counter = Counter()
        self.published = 0
        self._state: OrbitalState | None = None
        self._conditions_memo: tuple = ()  # _KeptConditions of the latest two stamps
        self._knots: tuple = (None, None, {})  # state, settings, {knot index: FlightConditions}
        self.prepared_used = 0  # attitudes at the stamp prepare() had made ready
        self._prepared: tuple | None = None  # (stamp, state, settings) of the latest prepare()
        self.knots_evaluated = 0  # exact flight conditions evaluated at knots (conditions_step)
        self._last_attitude_stamp: float | None = None
        self._last_state_stamp: float | None = None
        self._shading: _ShadingSource | None = None
        self._database: DatabaseCoefficients | None = None
        self.settings = None
        self.method = None
        self.apply_settings(settings)

    # ----------------------------------------------------------------------------- settings
    def apply_settings(self, settings: WrenchSettings) -> None:
        """Switch to new settings; raises ValueError (and keeps the old ones) if they do not apply."""
        if self.settings is not None:
            for name in ("mesh", "mesh_scale"):
                if getattr(settings, name) != getattr(self.settings, name):
                    raise ValueError(
                        f"parameter {name}: the mesh is loaded once at start-up and cannot change"
                    )
        materials = materials_from_settings(settings)
        unknown = materials.check_names(self.mesh.material_names)
        if unknown:
            raise ValueError(
                f"parameter material_overrides: the mesh has no material {', '.join(map(repr, unknown))}; "
                f"its materials are {', '.join(self.mesh.material_names)}"
            )
        method = PanelMethod(
            self.mesh,
            settings.gsi_model,
            materials,
            options=ModelOptions(settings.incident_temperature, settings.adbsat_compat),
            reference=Reference(moment_point=settings.center_of_mass),
        )
        weather = SpaceWeather(settings.f107, settings.f107a, settings.ap, settings.ap_history)
        database = None
        if settings.coefficients_source == "database":
            if settings.accommodation_model != "fixed":
                raise ValueError(
                    "parameter accommodation_model: coefficients_source database needs a fixed accommodation "
                    f"(the database was made at one alpha), got {settings.accommodation_model}"
                )
            database = DatabaseCoefficients(
                settings.database_path, method
            )  # checked against this set-up
        shading = self._shading
        key = (
            settings.shading,
            settings.shading_samples,
            settings.shading_cache_resolution_deg,
            settings.shading_cache_size,
        )
        if database is None and (shading is None or shading.key != key):
            shading = _ShadingSource(self.mesh, settings)  # built when first needed
        self.method, self.weather, self._shading, self.settings = method, weather, shading, settings
        self._database = database
        self._wind = np.asarray(settings.wind_ecef) if any(settings.wind_ecef) else None
        self._accommodation_options = (
            {"alpha": settings.alpha} if settings.accommodation_model == "fixed" else None
        )

    @property
    def shading_cache_hits(self) -> int:
        return 0 if self._shading is None else self._shading.hits

    @property
    def shading_cache_misses(self) -> int:
        return 0 if self._shading is None else self._shading.misses

    @property
    def shading_cache(self):
        """The ShadingCache in use (None without shading or when coefficients come from a database)."""
        return None if self._shading is None or self._database is not None else self._shading.cache

    @property
    def database(self) -> DatabaseCoefficients | None:
        """The database in use when ``coefficients_source`` is database, else None."""
        return self._database

    # ----------------------------------------------------------------------------- time
    def utc(self, stamp: float) -> _dt.datetime:
        """UTC of a message stamp [s] per ``time_mode``."""
        if self.settings.time_mode == "unix":
            return _dt.datetime.fromtimestamp(stamp, tz=_dt.timezone.utc)
        return self.settings.epoch_utc + _dt.timedelta(seconds=stamp)

    def reset(self) -> None:
        """Forget the state and the last stamps (e.g. after time jumped back)."""
        self._state = None
        self._last_attitude_stamp = None
        self._last_state_stamp = None
        self._knots = (None, None, {})
        self._prepared = None

    def _reject(self, reason: str, message: str):
        self.rejections[reason] += 1
        raise Rejection(reason, message)

    # ----------------------------------------------------------------------------- inputs
    def on_state(
        self,
        stamp: float,
        position,
        velocity,
        velocity_in_body_frame: bool = False,
        orientation_xyzw=None,
    ) -> OrbitalState:
        """Accept an orbital state.

        Parameters
        ----------
        stamp : float
            Message time [s].
        position : array_like, shape (3,)
            Position in the state frame [m].
        velocity : array_like, shape (3,)
            Velocity [m/s]: in the state frame, or in the body frame if ``velocity_in_body_frame``
            (then ``orientation_xyzw``, the body's orientation in the state frame, rotates it).
        orientation_xyzw : array_like, shape (4,), optional
            Body orientation (x, y, z, w), needed for a body-frame velocity.

        Raises
        ------
        Rejection
            ``non_finite``, ``bad_quaternion`` or ``time_backwards`` (which also resets).
        """
        position = np.asarray(position, dtype=float)
        velocity = np.asarray(velocity, dtype=float)
        if not (
            math.isfinite(stamp) and np.all(np.isfinite(position)) and np.all(np.isfinite(velocity))
        ):
            self._reject("non_finite", "state has NaN or Inf in its stamp, position or velocity")
        if velocity_in_body_frame:
            m = self._rotation(orientation_xyzw, "state orientation")
            velocity = np.array(m).reshape(3, 3) @ velocity
        if self._last_state_stamp is not None and stamp < self._last_state_stamp:
            jump = self._last_state_stamp - stamp
            self.reset()
            self.rejections["time_backwards"] += 1
            self._last_state_stamp = stamp
            self._state = OrbitalState(stamp, position, velocity)
            raise Rejection(
                "time_backwards", f"state time went back by {jump:.3f} s: history reset, state kept"
            )
        self._last_state_stamp = stamp
        self._state = OrbitalState(stamp, position, velocity)
        return self._state

    def on_odometry(self, msg):
        """Accept a nav_msgs/Odometry state: an rclpy or rosbags message, or its
        :class:`~adbsat_ros.messages.cdr.OdometryFields` (what the node reads from the CDR bytes).

        ``header.frame_id`` naming 'eci' or 'ecef' must match the ``state_frame`` setting. The
        twist is in the body frame if ``child_frame_id`` is ``body_frame_id`` (it is then rotated
        with the pose orientation), in the state frame if ``child_frame_id`` is empty, one of
        :data:`STATE_FRAME_NAMES` or the header's frame_id.

        Returns
        -------
        state : OrbitalState
            The accepted state (velocity in the state frame).
        orientation_xyzw : list of float
            The pose orientation (the attitude when ``attitude_source`` is odometry).

        Raises
        ------
        Rejection
            ``bad_state`` for a frame mismatch or a child_frame_id that is neither frame, and the
            reasons of :meth:`on_state`.
        """
        odom = msg if isinstance(msg, OdometryFields) else OdometryFields.of_message(msg)
        s = self.settings
        header_frame = odom.frame_id.lstrip("/")
        frame = header_frame.lower()
        if frame in ("eci", "ecef") and frame != s.state_frame:
            self._reject(
                "bad_state",
                f"state frame_id '{frame}' but parameter state_frame is {s.state_frame}",
            )
        child = odom.child_frame_id.lstrip("/")
        if child == s.body_frame_id:
            in_body = True
        elif child.lower() in STATE_FRAME_NAMES or child == header_frame:
            in_body = False
        else:
            self._reject(
                "bad_state",
                f"twist child_frame_id '{child}' is neither the body frame '{s.body_frame_id}' nor the state frame",
            )
        orientation = list(odom.orientation_xyzw)
        state = self.on_state(
            stamp_seconds(odom.stamp),
            list(odom.position),
            list(odom.linear_velocity),
            in_body,
            orientation,
        )
        return state, orientation

    def diagnostic_values(self, last_sample: "WrenchSample | None", compute_ms) -> dict:
        """Key/values of the node's DiagnosticStatus (bag analysis writes the same ones).

        Parameters
        ----------
        last_sample : WrenchSample or None
            The latest wrench computed.
        compute_ms : sequence or ndarray of float
            Recent compute times [ms]; their p50, p99 (nearest rank) and largest are reported.
        """
        s = self.settings
        values = {
            "gsi_model": s.gsi_model,
            "coefficients_source": s.coefficients_source,
            "shading": s.shading,
            "published": self.published,
            "shading_cache_hits": self.shading_cache_hits,
            "shading_cache_misses": self.shading_cache_misses,
            "conditions_prepared_used": self.prepared_used,
            "reference_area_m2": self.method.reference.area,
            "reference_length_m": self.method.reference.length,
        }
        database = self._database
        if database is not None:
            values["database_path"] = database.path
            values["database_speed_ratio"] = database.speed_ratio
            for key in ("force_coefficient", "moment_coefficient"):
                if key in database.error_bound:
                    values[f"database_{key}_error"] = database.error_bound[key]
        times = (
            compute_ms
            if isinstance(compute_ms, np.ndarray)
            else np.fromiter(compute_ms, dtype=float)
        )
        n = times.size
        if n:
            # nearest-rank percentiles (the ceil(p n)-th smallest), one partial sort for all three;
            # np.percentile's interpolation costs ~0.1 ms more per call, once a second in the node
            ranks = [max(math.ceil(0.50 * n) - 1, 0), max(math.ceil(0.99 * n) - 1, 0), n - 1]
            p50, p99, worst = np.partition(times, ranks)[ranks].tolist()
            values["compute_ms_p50"] = p50
            values["compute_ms_p99"] = p99
            values["compute_ms_max"] = worst
        if last_sample is not None:
            c = last_sample.conditions
            values.update(
                density_kg_m3=c.mass_density,
                temperature_K=c.temperature,
                altitude_m=c.altitude,
                relative_speed_m_s=c.speed,
                speed_ratio=c.speed_ratio,
                alpha=c.alpha,
                drag_coefficient=last_sample.drag_coefficient,
            )
        for reason in sorted(self.rejections):
            values[f"rejected_{reason}"] = self.rejections[reason]
        return values

    def _rotation(self, q, what: str) -> tuple:
        """Rotation matrix (body -> state frame) of quaternion ``q`` (x, y, z, w), checked, as
        nine floats, row-major."""
        try:
            x, y, z, w = q
            x, y, z, w = float(x), float(y), float(z), float(w)
        except (TypeError, ValueError):
            self._reject("non_finite", f"{what} is not four numbers")
        if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z) and math.isfinite(w)):
            self._reject("non_finite", f"{what} has NaN or Inf")
        norm = math.sqrt(x * x + y * y + z * z + w * w)
        if abs(norm - 1.0) > self.settings.max_quaternion_norm_error:
            self._reject(
                "bad_quaternion",
                f"{what} norm {norm:.6g} differs from 1 by more than {self.settings.max_quaternion_norm_error:g}",
            )
        return quaternion_matrix_floats(x / norm, y / norm, z / norm, w / norm)

    def on_attitude(self, stamp: float, quaternion_xyzw) -> WrenchSample:
        """The wrench at an attitude message, with the latest state brought to its stamp.

        Raises
        ------
        Rejection
            With the reason; nothing is published for this message.
        """
        t0 = time.perf_counter()
        request = self._request(stamp, quaternion_xyzw, t0)
        if isinstance(request, _PanelRequest):
            request = self._panel_sample(
                request, self._coefficients(request), time.perf_counter() - t0
            )
        self.published += 1
        return request

    def on_attitudes(self, messages) -> list:
        """:meth:`on_attitude` for attitude messages that arrived together, in their order.

        Each message is checked, counted and brought to its flight conditions as by its own
        :meth:`on_attitude` call, in order (a time jump back resets the history before the next
        message, as it would); the panel method then runs once for all of them
        (:meth:`PanelMethod.coefficients_many`). So the samples, the counters and the state
        afterwards are those of one call per message, bit for bit, at less cost per message:
        the ROS node uses it for the attitudes that wait while it computes, a burst after a
        hold-up.

        Parameters
        ----------
        messages : sequence of (float, sequence of 4 floats)
            (stamp [s], quaternion x, y, z, w) of each message.

        Returns
        -------
        list of WrenchSample or Rejection
            One per message, in order. A panel sample's ``compute_seconds`` is the whole call's
            time divided by the number of messages.
        """
        t0 = time.perf_counter()
        results: list = []
        requests = []  # (index in results, _PanelRequest)
        for stamp, quaternion in messages:
            try:
                request = self._request(stamp, quaternion, time.perf_counter())
            except Rejection as exc:
                results.append(exc)
                continue
            if isinstance(request, _PanelRequest):
                requests.append((len(results), request))
            results.append(request)
        coefficients = [None] * len(requests)  # each computed below, with its own rejection
        share = (time.perf_counter() - t0) / max(len(results), 1)
        for (i, request), coeffs in zip(requests, coefficients):
            try:
                if coeffs is None:
                    coeffs = self._coefficients(request)
                results[i] = self._panel_sample(request, coeffs, share)
            except Rejection as exc:
                results[i] = exc
        self.published += sum(isinstance(r, WrenchSample) for r in results)
        return results

    def _request(self, stamp: float, quaternion_xyzw, t0: float):
        """An attitude message checked and brought to its flight conditions: a finished
        WrenchSample (at rest, or from the database) or the _PanelRequest of the panel method."""
        if not math.isfinite(stamp):
            self._reject("non_finite", "attitude stamp is not finite")
        rotation = self._rotation(quaternion_xyzw, "attitude quaternion")
        if self._last_attitude_stamp is not None and stamp < self._last_attitude_stamp:
            jump = self._last_attitude_stamp - stamp
            self.reset()
            self._reject(
                "time_backwards", f"attitude time went back by {jump:.3f} s: history reset"
            )
        state = self._state
        if state is None:
            self._reject("no_state", "no orbital state received yet")
        dt = stamp - state.stamp
        if abs(dt) > self.settings.state_timeout:
            self._reject(
                "stale_state",
                f"latest state is {dt:.3f} s from the attitude stamp "
                f"(state_timeout {self.settings.state_timeout:g} s)",
            )
        self._last_attitude_stamp = stamp
        try:
            utc, conditions, flow = self._conditions_at(stamp, state)
        except ValueError as exc:
            reason = "altitude_out_of_range" if "altitude" in str(exc) else "bad_state"
            self._reject(reason, str(exc))
        return self._wrench_request(stamp, utc, rotation, conditions, flow, t0)

    def _conditions_at(self, stamp: float, state: OrbitalState):
        """UTC, flight conditions and free stream (None at rest) at ``stamp`` from ``state``.

        The latest two results are kept: another attitude at the same stamp and state (a simulator
        publishing attitude and state at every step), or with ``conditions_step`` 0 the stamp
        :meth:`prepare` computed ahead, gets them back instead of a second identical computation.

        Raises
        ------
        ValueError
            From :func:`flight_conditions` (e.g. an altitude outside the atmosphere model).
        """
        s = self.settings
        prepared = self._prepared
        if (
            prepared is not None
            and prepared[0] == stamp
            and prepared[1] is state
            and prepared[2] is s
        ):
            self.prepared_used += 1
        for kept in self._conditions_memo:
            if kept.state is state and kept.stamp == stamp and kept.settings is s:
                return kept.utc, kept.conditions, kept.flow
        utc = self.utc(stamp)
        conditions = None
        if s.conditions_step > 0.0:
            conditions = self._interpolated_conditions(stamp, state, utc, s.conditions_step)
        if conditions is None:
            conditions = self._exact_conditions(stamp, state, utc)
        flow = conditions.free_stream() if conditions.speed > 0.0 else None
        kept = _KeptConditions(state, stamp, s, utc, conditions, flow)
        self._conditions_memo = self._conditions_memo[-1:] + (kept,)
        return utc, conditions, flow

    def _exact_conditions(
        self, stamp: float, state: OrbitalState, utc: _dt.datetime
    ) -> FlightConditions:
        """:func:`flight_conditions` of ``state`` propagated (first order) to ``stamp``."""
        s = self.settings
        position = state.position + state.velocity * (
            stamp - state.stamp
        )  # first-order propagation
        return flight_conditions(
            utc,
            position,
            state.velocity,
            self.weather,
            frame=s.state_frame,
            earth_rotation=s.earth_rotation,
            wind=self._wind,
            wind_frame="ecef",
            anomalous_oxygen=s.anomalous_oxygen,
            accommodation_model=s.accommodation_model,
            accommodation_options=self._accommodation_options,
            precession_nutation_step=PRECESSION_NUTATION_STEP_S,
        )

    def _interpolated_conditions(
        self, stamp: float, state: OrbitalState, utc: _dt.datetime, step: float
    ) -> FlightConditions | None:
        """The conditions at ``stamp`` interpolated between the knots around it: the exact
        conditions of ``state`` at the stamps ``j step`` for integers j (so the same stamp and
        state always give the same numbers, live or from a bag, and a stream stamped on multiples
        of the step lands on knots); None if a knot cannot be evaluated (e.g. it lies outside the
        atmosphere model while the stamp does not), for the exact evaluation."""
        try:
            _, past, a, b = self._knots_around(state, stamp, step)
        except ValueError:
            return None
        return interpolated_flight_conditions(a, b, past / step, utc)

    def _knots_around(self, state: OrbitalState, stamp: float, step: float) -> tuple:
        """(j, past, a, b): the knot j at or before ``stamp`` and the time past it
        (:func:`_knot_position`), and the exact conditions at knots j and j + 1 (``b`` is ``a``
        for a stamp on knot j). Raises ValueError if a knot cannot be evaluated."""
        j, past = _knot_position(stamp, step)
        a = self._knot(state, j, step)
        b = a if past == 0.0 else self._knot(state, j + 1, step)
        return j, past, a, b

    def _knot(self, state: OrbitalState, j: int, step: float) -> FlightConditions:
        """The exact conditions of ``state`` at the stamp ``j step`` (the latest KNOTS_KEPT kept)."""
        s = self.settings
        if self._knots[0] is not state or self._knots[1] is not s:
            self._knots = (state, s, {})
        table = self._knots[2]
        conditions = table.get(j)
        if conditions is None:
            stamp = j * step
            conditions = self._exact_conditions(stamp, state, self.utc(stamp))
            self.knots_evaluated += 1
            if len(table) >= KNOTS_KEPT:
                del table[next(iter(table))]
            table[j] = conditions
        return conditions

    def prepare(self, stamp: float) -> bool:
        """Compute ahead what an attitude expected at ``stamp`` [s] would wait for.

        A GNC loop stamps its attitudes at a fixed interval, so the ROS node calls this right
        after publishing a wrench, with the stamp the next message most likely has (the latest
        plus the latest interval, :func:`next_regular_stamp`). With ``conditions_step`` > 0 (the
        default) that is the knots around the stamp, NRLMSISE-00 and the Earth's orientation
        evaluated there (:meth:`_knot`), and, if they needed no new evaluation, the knot
        KNOT_LOOKAHEAD steps on, one interval before any stamp needs it: attitudes that queued up
        and are served together (:meth:`on_attitudes`) then cross into the next interval without
        an NRLMSISE-00 evaluation among them. The conditions at the stamp itself are interpolated
        when the message comes (a few microseconds, less than keeping them). At most one knot is
        evaluated per call in a regular stream: the knots it needs anyway, one interval earlier.
        With ``conditions_step`` = 0 the exact conditions at the stamp are computed and kept for
        exactly that stamp. Either way the message's numbers are the ones it would have had
        without this. Nothing is counted or raised here; the attitude that comes at the stamp
        counts in :attr:`prepared_used`.

        Returns
        -------
        bool
            Whether it was prepared (False without a state, for a stamp not after the latest
            attitude or that the state time-out would reject, or outside the atmosphere).
        """
        state, last = self._state, self._last_attitude_stamp
        if state is None or not math.isfinite(stamp) or (last is not None and stamp <= last):
            return False
        if abs(stamp - state.stamp) > self.settings.state_timeout:
            return False
        step = self.settings.conditions_step
        try:
            if step > 0.0:
                evaluated = self.knots_evaluated
                j = self._knots_around(state, stamp, step)[0]
                if self.knots_evaluated == evaluated:
                    try:
                        self._knot(state, j + KNOT_LOOKAHEAD, step)
                    except ValueError:  # (e.g. above the atmosphere model: the stamp itself is not)
                        pass
            else:
                self._conditions_at(stamp, state)
        except ValueError:
            return False
        self._prepared = (stamp, state, self.settings)
        return True

    def _wrench_request(self, stamp, utc, rotation: tuple, conditions: FlightConditions, flow, t0):
        """The sample of a stamp whose conditions are known, or what the panel method needs for it."""
        s = self.settings
        ref = self.method.reference
        speed = conditions.speed
        if (
            speed < s.min_relative_speed or flow is None
        ):  # at rest in the air: no free stream, no force
            zero = np.zeros(3)
            return WrenchSample(
                stamp,
                utc,
                zero,
                zero.copy(),
                zero.copy(),
                zero.copy(),
                ref.area,
                ref.length,
                0.0,
                conditions,
                None,
                zero.copy(),
                None,
                time.perf_counter() - t0,
            )
        # gas motion relative to the body, body axes: u = -R^T v_rel / |R^T v_rel|, in floats (a unit
        # vector as the panel method takes it: PanelMethod._unit_coefficients)
        vx, vy, vz = conditions.relative_velocity_floats(s.state_frame)
        m = rotation
        gx = -(m[0] * vx + m[3] * vy + m[6] * vz)
        gy = -(m[1] * vx + m[4] * vy + m[7] * vz)
        gz = -(m[2] * vx + m[5] * vy + m[8] * vz)
        norm = math.sqrt(gx * gx + gy * gy + gz * gz)  # the speed, to rounding (R is a rotation)
        u_body = np.array([gx / norm, gy / norm, gz / norm])
        q = flow.dynamic_pressure()
        if self._database is not None:
            try:
                cf, cm = self._database.body_coefficients(u_body)
            except ValueError as exc:
                self._reject("outside_database", str(exc))
            return WrenchSample(
                stamp=stamp,
                time=utc,
                force=q * ref.area * cf,
                torque=(q * ref.area * ref.length) * cm,
                force_coefficients=cf,
                moment_coefficients=cm,
                reference_area=ref.area,
                reference_length=ref.length,
                dynamic_pressure=q,
                conditions=conditions,
                coefficients=None,
                flow_direction_body=u_body,
                shading_cache_hit=None,
                compute_seconds=time.perf_counter() - t0,
            )
        lighting, hit = self._shading.lighting(u_body)
        surface = None
        if s.accommodation_model != "fixed":
            surface = self.method.surface_with(alpha=conditions.alpha, alpha_n=conditions.alpha)
        return _PanelRequest(stamp, utc, conditions, flow, u_body, q, lighting, hit, surface)

    def _coefficients(self, request: "_PanelRequest") -> AeroCoefficients:
        try:
            return self.method.coefficients(
                request.flow,
                flow_direction=request.flow_direction,
                lighting=request.lighting,
                surface=request.surface,
            )
        except ValueError as exc:
            self._reject("compute_error", str(exc))

    def _panel_sample(
        self, request: "_PanelRequest", coeffs: AeroCoefficients, compute_seconds: float
    ) -> WrenchSample:
        ref = self.method.reference
        q = request.dynamic_pressure
        return WrenchSample._made(
            request.stamp,
            request.utc,
            coeffs.force(q),
            coeffs.torque(q),
            coeffs.Cf_G,
            coeffs.Cm_G,
            ref.area,
            ref.length,
            q,
            request.conditions,
            coeffs,
            request.flow_direction,
            request.hit,
            compute_seconds,
        )


class _PanelRequest(NamedTuple):
    """An attitude message's inputs to the panel method (AeroWrenchEstimator._wrench_request)."""

    stamp: float
    utc: _dt.datetime
    conditions: FlightConditions
    flow: FreeStream
    flow_direction: np.ndarray  # unit gas motion relative to the body, body frame
    dynamic_pressure: float  # [Pa]
    lighting: object  # PanelLighting or None
    hit: bool | None  # whether the shading came from the cache
    surface: object  # PanelSurface or None (the materials')
