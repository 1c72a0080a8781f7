"""ROS 2 node: attitude and orbital state in, aerodynamic WrenchStamped out.

Topics (relative names, remappable):

* ``attitude`` (geometry_msgs/QuaternionStamped, subscribed): orientation of the body (mesh)
  frame in the state's frame, quaternion x, y, z, w.
* ``state`` (nav_msgs/Odometry, subscribed): position in ``header.frame_id`` (ECI or ECEF per the
  ``state_frame`` parameter); twist per the Odometry convention in ``child_frame_id``: a twist in
  the body frame is rotated with the pose orientation, one whose child_frame_id names the state
  frame (or is empty) is taken as is.
* ``wrench`` (geometry_msgs/WrenchStamped, published): force [N] and torque about the centre of
  mass [N m] in the body frame (``body_frame_id``), stamp copied from the attitude message.
* ``coefficients`` (geometry_msgs/WrenchStamped, published with every wrench while it has a subscriber): force
  coefficients in ``force`` and moment coefficients in ``torque``, body frame, about the centre of
  mass, normalised by the read-only parameters ``reference_area`` and ``reference_length``.
* ``/diagnostics`` (diagnostic_msgs/DiagnosticArray, every ``diagnostics_period`` s).

Both subscriptions take the CDR bytes and read them with :mod:`adbsat_ros.messages.cdr` (rclpy's
deserialiser for anything but plain CDR); bytes that are neither message are counted as
``undecodable``. Wrenches and /diagnostics go out as CDR bytes too. Rejected inputs are logged at
most once per reason every ``LOG_THROTTLE_S``.

Before computing an attitude's wrench the callback takes the attitudes waiting behind it (and, if
there are any, the waiting states) and serves them all in arrival order, the attitudes between two
states computed together (:meth:`AdbsatNode._serve`; each wrench is bit for bit the one it would have had alone).
The number taken so is the diagnostic value ``attitudes_taken_waiting``.

Parameters: see :data:`adbsat_ros.estimator.settings.PARAMETERS` and ``config/adbsat.yaml``.
"""

from __future__ import annotations

import gc
import io
import os
import sys
import time

import numpy as np
import rclpy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import QuaternionStamped, WrenchStamped
from nav_msgs.msg import Odometry
from rcl_interfaces.msg import ParameterDescriptor, SetParametersResult
from rclpy.event_handler import PublisherEventCallbacks
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message

from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.samples import Rejection, WrenchSample
from adbsat_ros.messages.stamps import next_regular_stamp, stamp_seconds
from adbsat_ros.estimator.settings import PARAMETERS, READ_ONLY_PARAMETERS, WrenchSettings
from adbsat_ros.geometry.mesh import MeshError
from adbsat_ros.messages.cdr import (
    DiagnosticFields,
    OdometryFields,
    Stamp,
    diagnostic_array_cdr,
    odometry_fields,
    quaternion_stamped_fields,
    wrench_stamped_cdr,
)

NODE_NAME = "adbsat_node"
#: Compute times kept for the p50/p99/max of /diagnostics (the latest this many messages).
COMPUTE_WINDOW = 2000
#: Times one attitude callback takes and serves what waits in the queues before it returns.
SERVE_ROUNDS = 4
#: Seconds between two log lines about the same kind of rejected input.
LOG_THROTTLE_S = 5.0


class LogThrottle:
    """At most one log line per key every ``period`` seconds, decided before the logger is called.

    rclpy's own ``throttle_duration_sec`` finds its caller with ``inspect`` on every call, also on
    the calls it then suppresses: about 0.6 ms each on this machine, more than a whole wrench. A
    stream of bad input at 1 kHz would then take more CPU than the node has, and it would fall
    behind for good. This check costs a dictionary lookup.
    """

    def __init__(self, logger, period: float = LOG_THROTTLE_S, clock=time.monotonic):
        self._logger = logger
        self._period = period
        self._clock = clock
        self._last: dict = {}

    def __call__(self, level: str, key: str, text: str) -> bool:
        """Log ``text`` at ``level`` ("warning", "error", ...) unless ``key`` was logged less than
        ``period`` seconds ago; return whether it was logged."""
        now = self._clock()
        last = self._last.get(key)
        if last is not None and now - last < self._period:
            return False
        self._last[key] = now
        getattr(self._logger, level)(text)
        return True


class AdbsatNode(Node):
    """The aerodynamic wrench node; raises MeshError/ValueError at construction on bad set-up."""

    def __init__(self, **node_kwargs):
        super().__init__(NODE_NAME, **node_kwargs)
        for name, default, text in PARAMETERS:
            self.declare_parameter(
                name,
                default,
                ParameterDescriptor(description=text, read_only=name in READ_ONLY_PARAMETERS),
            )
        settings = WrenchSettings.from_parameters(self._parameter_values())
        self.estimator = AeroWrenchEstimator(settings)
        ref = self.estimator.method.reference
        for name, value, text in (
            (
                "reference_area",
                ref.area,
                "A_ref of the coefficients topic [m^2] (half the wetted area)",
            ),
            ("reference_length", ref.length, "L_ref of the coefficients topic [m] (mesh x extent)"),
        ):
            self.declare_parameter(
                name, value, ParameterDescriptor(description=text, read_only=True)
            )
        self.add_on_set_parameters_callback(self._on_set_parameters)

        qos = QoSProfile(depth=settings.qos_depth, reliability=ReliabilityPolicy.RELIABLE)
        self.wrench_pub = self.create_publisher(WrenchStamped, "wrench", qos)
        # its subscribers counted by the middleware's matched events, not asked for per message
        # (get_subscription_count costs 4-10 us, a few per cent of a wrench)
        self._coefficient_readers = 0
        self.coefficients_pub = self.create_publisher(
            WrenchStamped,
            "coefficients",
            qos,
            event_callbacks=PublisherEventCallbacks(matched=self._on_coefficients_matched),
        )
        self._coefficient_readers = self.coefficients_pub.get_subscription_count()
        self.diagnostics_pub = self.create_publisher(DiagnosticArray, "/diagnostics", 10)
        # states and attitudes come in and wrenches go out as CDR bytes (module stamped_cdr):
        # building rclpy message objects would cost more than the wrench itself.
        # State first: when a state and an attitude are waiting together, the executor takes them
        # in the order the subscriptions were made, and the attitude wants the newest state.
        self._state_sub = self.create_subscription(Odometry, "state", self._on_state, qos, raw=True)
        self._attitude_sub = self.create_subscription(
            QuaternionStamped, "attitude", self._on_attitude, qos, raw=True
        )
        # attitudes an attitude callback took from the queue behind its own (a burst)
        self.attitudes_taken_waiting = 0
        # compute times [ms] of the latest COMPUTE_WINDOW wrenches, a ring written in place
        self._compute_ms = np.zeros(COMPUTE_WINDOW)
        self._computed = 0
        self._last_state_wall = None
        self._last_sample: WrenchSample | None = None
        self._stamps = (None, None)  # header stamps of the two latest wrenches published
        self._sample_listeners: list = []
        self._last_rejection: Rejection | None = None
        self._log_throttled = LogThrottle(self.get_logger())
        self._diag_timer = self.create_timer(settings.diagnostics_period, self._publish_diagnostics)
        mesh = self.estimator.mesh
        source = (
            f"coefficients from database {settings.database_path}"
            if settings.coefficients_source == "database"
            else f"shading {settings.shading}"
        )
        self.get_logger().info(
            f"mesh {mesh.source}: {mesh.n_panels} panels; model {settings.gsi_model}, {source}; "
            f"publishing '{self.resolve_topic_name('wrench')}' in frame '{settings.body_frame_id}'"
        )

    def _on_coefficients_matched(self, info) -> None:
        self._coefficient_readers = info.current_count

    # ----------------------------------------------------------------------------- parameters
    def _parameter_values(self, changes=()) -> dict:
        values = {name: self.get_parameter(name).value for name, _, _ in PARAMETERS}
        for p in changes:
            values[p.name] = p.value
        return values

    def _on_set_parameters(self, params) -> SetParametersResult:
        known = {name for name, _, _ in PARAMETERS}
        relevant = [p for p in params if p.name in known]
        if not relevant:
            return SetParametersResult(successful=True)
        try:
            settings = WrenchSettings.from_parameters(self._parameter_values(relevant))
            self.estimator.apply_settings(settings)
        except (ValueError, MeshError) as exc:
            self.get_logger().warning(f"parameter change rejected: {exc}")
            return SetParametersResult(successful=False, reason=str(exc))
        if settings.diagnostics_period != self._diag_timer.timer_period_ns * 1e-9:
            self._diag_timer.cancel()
            self.destroy_timer(self._diag_timer)
            self._diag_timer = self.create_timer(
                settings.diagnostics_period, self._publish_diagnostics
            )
        self.get_logger().info(
            "parameters changed: " + ", ".join(f"{p.name}={p.value}" for p in relevant)
        )
        return SetParametersResult(successful=True)

    # ----------------------------------------------------------------------------- inputs
    def _rejected(self, exc: Rejection) -> None:
        self._last_rejection = exc
        self._log_throttled("warning", exc.reason, f"input rejected ({exc.reason}): {exc.message}")

    def _undecodable(self, what: str, exc: Exception) -> None:
        self.estimator.rejections["undecodable"] += 1
        self._rejected(Rejection("undecodable", f"{what}: {exc!r}"))

    def _on_state(self, raw: bytes) -> None:
        """A state as the CDR bytes of a nav_msgs/Odometry."""
        try:
            odom = odometry_fields(raw)
        except (
            ValueError
        ):  # not plain CDR (e.g. XCDR2 from another RMW): the typesupport decodes it
            try:
                odom = OdometryFields.of_message(deserialize_message(raw, Odometry))
            except Exception as exc:
                self._undecodable("state message not an Odometry", exc)
                return
        try:
            self._handle_state(odom)
        except Rejection as exc:
            self._rejected(exc)
        except Exception as exc:  # never let a message take the node down
            self.estimator.rejections["compute_error"] += 1
            self._log_throttled("error", "state_failed", f"state message failed: {exc!r}")

    def _handle_state(self, odom: OdometryFields) -> None:
        _, orientation = self.estimator.on_odometry(odom)
        self._last_state_wall = time.monotonic()
        if self.estimator.settings.attitude_source == "odometry":
            self._compute_and_publish(odom.stamp, orientation)
            self._prepare_next()

    def _attitude_fields(self, raw: bytes):
        """(stamp, quaternion x y z w) of the CDR bytes of a QuaternionStamped, or None (counted)."""
        try:
            return quaternion_stamped_fields(raw)
        except (
            ValueError
        ):  # not plain CDR (e.g. XCDR2 from another RMW): the typesupport decodes it
            try:
                msg = deserialize_message(raw, QuaternionStamped)
            except Exception as exc:
                self._undecodable("attitude message not a QuaternionStamped", exc)
                return None
            q = msg.quaternion
            return Stamp(msg.header.stamp.sec, msg.header.stamp.nanosec), [q.x, q.y, q.z, q.w]

    def _on_attitude(self, raw: bytes) -> None:
        """An attitude as the CDR bytes of a QuaternionStamped, with the messages waiting behind it
        (:meth:`_serve`); then what the next stamp needs ahead (:meth:`_prepare_next`)."""
        if self.estimator.settings.attitude_source != "attitude_topic":
            return
        fields = self._attitude_fields(raw)
        waiting = self._waiting()
        if waiting:
            self._serve([] if fields is None else [fields], waiting)
        elif fields is not None:  # the usual case: nothing behind it
            self._compute_and_publish(*fields)
        self._prepare_next()

    def _waiting(self) -> list:
        """:meth:`_take_waiting`, or nothing if the middleware fails (never take the node down)."""
        try:
            return self._take_waiting()
        except Exception as exc:  # e.g. a subscription destroyed at shutdown
            self._log_throttled(
                "error", "take_failed", f"taking the waiting messages failed: {exc!r}"
            )
            return []

    def _take_waiting(self) -> list:
        """The attitudes waiting in their subscription and, if there are any, the states waiting
        in theirs (at most ``qos_depth`` of each, all that a queue holds), as (received time [ns],
        is_attitude, CDR bytes) in the order they arrived, a state first on a tie (an attitude
        wants the newest state). With no attitude waiting the states are left to the executor,
        which serves them in order anyway: on the usual path this is one take, that finds nothing.

        The handles are used without ``with``: this runs in the node's own callback, and nothing
        destroys a subscription meanwhile (an InvalidHandle at shutdown is caught by the caller).
        """
        first = self._attitude_sub.handle.take_message(QuaternionStamped, True)
        if first is None:
            return []
        waiting = [(first[1].get("received_timestamp", 0), True, first[0])]
        self._take_more(self._attitude_sub, QuaternionStamped, True, waiting)
        self._take_more(self._state_sub, Odometry, False, waiting)
        waiting.sort(key=lambda item: item[:2])
        return waiting

    def _take_more(self, sub, msg_type, is_attitude: bool, taken: list) -> None:
        handle = sub.handle
        for _ in range(self.estimator.settings.qos_depth):
            message = handle.take_message(msg_type, True)
            if message is None:
                return
            raw, info = message
            taken.append((info.get("received_timestamp", 0), is_attitude, raw))

    def _serve(self, attitudes: list, waiting: list) -> None:
        """Answer ``attitudes`` [(stamp, quaternion)] and the ``waiting`` messages behind them
        (from :meth:`_take_waiting`).

        At 1 kHz a hold-up of the machine (another process, the middleware's threads) lets a few
        attitudes queue; answered one callback each, the last of them waits for all the others'
        whole computation. Taken from the subscription instead, the attitudes between two states
        are computed together (:meth:`AeroWrenchEstimator.on_attitudes`: each message's own
        result, bit for bit, for less time per message) and published in order; a state that came
        in between them is applied in its place, as the executor would have. What came in while
        those were computed is served the same way, up to SERVE_ROUNDS rounds in all, then the
        executor has its turn (timers, parameter services).
        """
        for round_ in range(SERVE_ROUNDS):
            for _, is_attitude, raw in waiting:
                if is_attitude:
                    self.attitudes_taken_waiting += 1
                    fields = self._attitude_fields(raw)
                    if fields is not None:
                        attitudes.append(fields)
                    continue
                self._compute_together(attitudes)
                attitudes = []
                self._on_state(raw)
            self._compute_together(attitudes)
            attitudes = []
            if round_ == SERVE_ROUNDS - 1:
                return  # (what came meanwhile stays queued for the executor)
            waiting = self._waiting()
            if not waiting:
                return

    def _compute_together(self, attitudes: list) -> None:
        """Compute and publish the wrenches of (stamp, quaternion) attitudes taken together."""
        if not attitudes:
            return
        try:
            results = self.estimator.on_attitudes(
                [(stamp_seconds(stamp), q) for stamp, q in attitudes]
            )
        except Exception as exc:  # never let a message take the node down
            self.estimator.rejections["compute_error"] += len(attitudes)
            self._log_throttled("error", "compute_failed", f"wrench computation failed: {exc!r}")
            return
        for (stamp, _), result in zip(attitudes, results):
            if isinstance(result, Rejection):
                self._rejected(result)
            else:
                self._publish(stamp, result)

    def _compute_and_publish(self, stamp_msg, quaternion) -> None:
        """Compute and publish the wrench of one attitude; ``stamp_msg`` has ``sec``, ``nanosec``."""
        try:
            sample = self.estimator.on_attitude(stamp_seconds(stamp_msg), quaternion)
        except Rejection as exc:
            self._rejected(exc)
            return
        except Exception as exc:  # never let a message take the node down
            self.estimator.rejections["compute_error"] += 1
            self._log_throttled("error", "compute_failed", f"wrench computation failed: {exc!r}")
            return
        self._publish(stamp_msg, sample)

    def _publish(self, stamp_msg, sample: WrenchSample) -> None:
        """Publish the wrench (and coefficients) of ``sample`` with the attitude's stamp.

        The CDR bytes go to the publishers' handles directly, as the takes come from the
        subscriptions' (:meth:`_take_waiting`): ``Publisher.publish`` would enter the handle's
        context and test the message's type for every message (1-2 us).
        """
        frame = self.estimator.settings.body_frame_id
        sec, nanosec = stamp_msg.sec, stamp_msg.nanosec
        self.wrench_pub.handle.publish_raw(
            wrench_stamped_cdr(sec, nanosec, frame, sample.force.tolist(), sample.torque.tolist())
        )
        if self._coefficient_readers:  # nobody listening: skip the serialisation
            self.coefficients_pub.handle.publish_raw(
                wrench_stamped_cdr(
                    sec,
                    nanosec,
                    frame,
                    sample.force_coefficients.tolist(),
                    sample.moment_coefficients.tolist(),
                )
            )
        self._compute_ms[self._computed % COMPUTE_WINDOW] = 1e3 * sample.compute_seconds
        self._computed += 1
        self._last_sample = sample
        for listener in self._sample_listeners:
            listener(sample)
        self._stamps = (self._stamps[1], stamp_msg)

    def _prepare_next(self) -> None:
        """What the next regular attitude would wait for (AeroWrenchEstimator.prepare: the knots of its
        flight conditions), now that the wrenches are out."""
        previous, latest = self._stamps
        if previous is None:
            return
        try:
            expected = next_regular_stamp(previous, latest)
            if expected is not None:
                self.estimator.prepare(expected)
        except Exception as exc:  # never let it take the node down
            self._log_throttled(
                "error", "prepare_failed", f"preparing the next message failed: {exc!r}"
            )

    def add_sample_listener(self, callback) -> None:
        """Call ``callback(sample)`` with every :class:`WrenchSample` published (in-process users:
        the full flight conditions and coefficients behind each wrench, e.g. for a live table)."""
        self._sample_listeners.append(callback)

    # ----------------------------------------------------------------------------- diagnostics
    def diagnostic_fields(self) -> DiagnosticFields:
        """The node's health and latest values: level, name, message, hardware id, key/values."""
        est = self.estimator
        s = est.settings
        values = est.diagnostic_values(
            self._last_sample, self._compute_ms[: min(self._computed, COMPUTE_WINDOW)]
        )
        values["attitudes_taken_waiting"] = self.attitudes_taken_waiting
        age = None if self._last_state_wall is None else time.monotonic() - self._last_state_wall
        rejected = sum(est.rejections.values())
        if age is None or age > max(s.state_timeout, s.diagnostics_period):
            level = DiagnosticStatus.ERROR
            message = "no orbital state" if age is None else f"state is stale ({age:.1f} s old)"
        elif self._last_rejection is not None and self._last_rejection.reason == "stale_state":
            level, message = (
                DiagnosticStatus.ERROR,
                "state is stale relative to the attitude stamps",
            )
        elif rejected:
            level, message = DiagnosticStatus.WARN, f"{rejected} inputs rejected so far"
        else:
            level, message = DiagnosticStatus.OK, "ok"
        return DiagnosticFields(
            level=ord(level),
            name=f"{self.get_name()}: aerodynamic wrench",
            message=message,
            hardware_id=est.mesh.source,
            values=tuple((k, str(v)) for k, v in values.items()),
        )

    def _publish_diagnostics(self) -> None:
        # as CDR bytes: rclpy message objects for ~20 key/values cost 0.3-0.5 ms to build and
        # serialise, up to 2 ms right after the process slept; a hold-up for the attitudes at 1 kHz
        try:
            sec, nanosec = self.get_clock().now().seconds_nanoseconds()
            self.diagnostics_pub.publish(
                diagnostic_array_cdr(sec, nanosec, "", [self.diagnostic_fields()])
            )
        except Exception as exc:  # diagnostics must never take the node down
            self._log_throttled("error", "diagnostics_failed", f"diagnostics failed: {exc!r}")


def make_executor(kind: str = "events", context=None):
    """An rclpy executor: ``"events"`` or ``"single_threaded"``.

    ``events`` is rclpy.experimental.EventsExecutor (C++ event queue: callbacks in arrival order,
    about half the per-message overhead of the SingleThreadedExecutor, which rebuilds a wait set
    in Python for every wait; see docs/benchmarks.md). An rclpy without it gets the
    SingleThreadedExecutor, and so does a process whose sys.stderr is not a file. Spin either
    with :func:`spin_until_shutdown`: the EventsExecutor's own ``spin()`` in the Jazzy 7.1
    wheels busy-waits and does not return on SIGINT/SIGTERM, its ``spin_once(timeout)`` sleeps
    and returns.
    """
    if kind == "events":
        try:
            from rclpy.experimental import EventsExecutor
        except ImportError:
            return SingleThreadedExecutor(context=context)
        try:
            return EventsExecutor(context=context)
        except (io.UnsupportedOperation, AttributeError, ValueError):
            # it enables faulthandler on sys.stderr, which needs a real file (not so in a notebook
            # or under pytest's capsys)
            return SingleThreadedExecutor(context=context)
    if kind == "single_threaded":
        return SingleThreadedExecutor(context=context)
    raise ValueError(f"executor must be events or single_threaded, got {kind!r}")


def spin_until_shutdown(executor, context=None) -> None:
    """Spin ``executor`` until its context shuts down (SIGINT/SIGTERM, or rclpy.shutdown)."""
    while rclpy.ok(context=context):
        executor.spin_once(timeout_sec=0.5)


def main(args=None) -> int:
    """Console script ``adbsat_node``: ``adbsat_node --ros-args --params-file config/adbsat.yaml``."""
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    rclpy.init(args=sys.argv if args is None else args)
    node = None
    try:
        try:
            node = AdbsatNode()
        except (MeshError, ValueError, OSError) as exc:
            print(f"{NODE_NAME}: error: {exc}", file=sys.stderr)
            return 1
        except Exception as exc:  # e.g. a parameter of the wrong type in the params file
            print(f"{NODE_NAME}: error: {type(exc).__name__}: {exc}", file=sys.stderr)
            return 1
        executor = make_executor(node.estimator.settings.executor)
        executor.add_node(node)
        # everything made so far (mesh, shading structures, imported modules) lives as long as the
        # process: move it out of the collector's generations, so that no collection the message
        # traffic triggers walks it (a full one over it takes about 35 ms)
        gc.collect()
        gc.freeze()
        try:
            spin_until_shutdown(executor)
        except (KeyboardInterrupt, ExternalShutdownException):
            pass
        return 0
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    sys.exit(main())
