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
* ``coefficients`` (geometry_msgs/WrenchStamped, published with every wrench while it has a
  subscriber): force coefficients in ``force`` and moment coefficients in ``torque``, body
  frame, about the centre of mass, normalised by the read-only parameters ``reference_area`` and
  ``reference_length``.
* ``wrench_inertial`` (geometry_msgs/WrenchStamped, published with every wrench while it has a
  subscriber): the force [N] in the state frame (frame_id ``eci`` or ``ecef``, the
  ``state_frame``), the torque [N m] in the body frame, as torques are applied.
* ``acceleration`` (geometry_msgs/AccelStamped, likewise, with a ``mass``): force / mass
  [m/s^2] in the state frame and, with an ``inertia``, inertia^-1 torque [rad/s^2] in the body
  frame.
* ``/diagnostics`` (diagnostic_msgs/DiagnosticArray, every ``diagnostics_period`` s).

The node is a shell around the per-message path it shares with the bag analysis
(:class:`adbsat_ros.estimator.handling.MessageHandler`): each callback takes one message as CDR
bytes, decodes it (:mod:`adbsat_ros.messages.decoding`, rclpy's deserialiser for anything but
plain CDR), hands it to the handler and publishes the wrench bytes it returns. Attitudes that
queue while the node computes are served by the executor, one callback each, in order. Bytes
that are neither message are counted as ``undecodable``; rejected inputs are logged at most once
per reason every ``LOG_THROTTLE_S``. After each attitude the node prepares what the next regular
stamp will need (:meth:`MessageHandler.prepare_next`).

Parameters: see :data:`adbsat_ros.estimator.settings.PARAMETERS` and ``config/adbsat.yaml``.
"""

from __future__ import annotations

import functools
import gc
import os
import sys
import time

import rclpy
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import AccelStamped, QuaternionStamped, WrenchStamped
from nav_msgs.msg import Odometry
from rcl_interfaces.msg import ParameterDescriptor, SetParametersResult
from rclpy.event_handler import PublisherEventCallbacks, SubscriptionEventCallbacks
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from rclpy.signals import SignalHandlerOptions

from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.handling import MessageHandler, Outcome
from adbsat_ros.estimator.health import OK, WARN, Health, StampGaps
from adbsat_ros.estimator.parameters import (
    PARAMETERS,
    READ_ONLY_PARAMETERS,
    parameter_range_text,
)
from adbsat_ros.estimator.settings import WrenchSettings, settings_from_file
from adbsat_ros.geometry.mesh import MeshError
from adbsat_ros.messages.cdr import DiagnosticFields, diagnostic_array_cdr
from adbsat_ros.messages.decoding import UndecodableMessage, decode_attitude, decode_odometry
from adbsat_ros.messages.stamps import stamp_seconds
from adbsat_ros.physics.knudsen import knudsen_number
from adbsat_ros.processes import stop_on_signals
from adbsat_ros.ros.executors import make_executor, spin_until_shutdown
from adbsat_ros.ros.log_throttle import LogThrottle
from adbsat_ros.ros.node_help import NODE_NAME, help_text


class AdbsatNode(Node):
    """The aerodynamic wrench node; raises MeshError/ValueError at construction on bad set-up.

    Parameters
    ----------
    **node_kwargs
        Passed to ``rclpy.node.Node`` (e.g. ``context``, ``parameter_overrides``).

    Attributes
    ----------
    estimator : AeroWrenchEstimator
        The node's logic without ROS.
    handler : MessageHandler
        The per-message path around it.
    health : Health
        What /diagnostics reports (latest state, rejection and sample; compute times).
    """

    def __init__(self, **node_kwargs):
        super().__init__(NODE_NAME, **node_kwargs)
        for name, default, text in PARAMETERS:
            self.declare_parameter(
                name,
                default,
                ParameterDescriptor(
                    description=text,
                    additional_constraints=parameter_range_text(name),
                    read_only=name in READ_ONLY_PARAMETERS,
                    # a number parameter takes an integer too (f107: 150 in a YAML file); the
                    # settings check every value whatever its type
                    dynamic_typing=_is_number(default),
                ),
            )
        settings = WrenchSettings.from_parameters(self._parameter_values())
        self.estimator = AeroWrenchEstimator(settings)
        self.handler = MessageHandler(self.estimator)
        self.health = Health()
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
        # for a propagator, while subscribed: the force in the state frame, and the acceleration
        self._inertial_readers = {"wrench_inertial": 0, "acceleration": 0}
        self.inertial_pub = self.create_publisher(
            WrenchStamped,
            "wrench_inertial",
            qos,
            event_callbacks=PublisherEventCallbacks(
                matched=functools.partial(self._on_inertial_matched, "wrench_inertial")
            ),
        )
        self.acceleration_pub = self.create_publisher(
            AccelStamped,
            "acceleration",
            qos,
            event_callbacks=PublisherEventCallbacks(
                matched=functools.partial(self._on_inertial_matched, "acceleration")
            ),
        )
        self._inertial_readers["wrench_inertial"] = self.inertial_pub.get_subscription_count()
        self._inertial_readers["acceleration"] = self.acceleration_pub.get_subscription_count()
        self._inertial = any(self._inertial_readers.values())
        self.diagnostics_pub = self.create_publisher(DiagnosticArray, "/diagnostics", 10)
        # the messages come in as CDR bytes, read by the struct codec (messages.cdr): rclpy
        # message objects would cost more than the wrench itself; rclpy's deserialiser reads the
        # rest. State first: when a state and an attitude wait together, the single-threaded
        # executor takes them in the order the subscriptions were made, and the attitude wants
        # the newest state.
        self._odometry_message = functools.partial(deserialize_message, message_type=Odometry)
        self._attitude_message = functools.partial(
            deserialize_message, message_type=QuaternionStamped
        )
        # messages the middleware reports lost (where the RMW reports it), and attitudes missing
        # from the stream by its stamps (StampGaps): both in /diagnostics
        self.messages_lost = 0
        self.attitude_gaps = StampGaps()
        lost = SubscriptionEventCallbacks(message_lost=self._on_message_lost)
        self.create_subscription(
            Odometry, "state", self._on_state, qos, raw=True, event_callbacks=lost
        )
        self.create_subscription(
            QuaternionStamped, "attitude", self._on_attitude, qos, raw=True, event_callbacks=lost
        )
        self._sample_listeners: list = []
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

    @property
    def coefficient_readers(self) -> int:
        """Subscribers of the coefficients topic, as the middleware's matched events count them
        (the topic is published only while there is one)."""
        return self._coefficient_readers

    def _on_coefficients_matched(self, info) -> None:
        self._coefficient_readers = info.current_count

    def _on_inertial_matched(self, topic: str, info) -> None:
        self._inertial_readers[topic] = info.current_count
        self._inertial = any(self._inertial_readers.values())

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

    # ----------------------------------------------------------------------------- messages
    def _on_state(self, raw: bytes) -> None:
        """A state as the CDR bytes of a nav_msgs/Odometry."""
        try:
            odometry = decode_odometry(raw, self._odometry_message)
        except UndecodableMessage as exc:
            self._serve(self.handler.undecodable("state", exc))
            return
        outcome = self.handler.on_state(odometry, self._coefficient_readers > 0, self._inertial)
        self._serve(outcome)
        if outcome.triggered:
            self._prepare_next()

    def _on_attitude(self, raw: bytes) -> None:
        """An attitude as the CDR bytes of a QuaternionStamped; then what the next stamp needs."""
        handler = self.handler
        if not handler.uses_attitude_topic:
            return
        try:
            attitude = decode_attitude(raw, self._attitude_message)
        except UndecodableMessage as exc:
            self._serve(handler.undecodable("attitude", exc))
        else:
            self.attitude_gaps.stamp(stamp_seconds(attitude.stamp))
            self._serve(
                handler.on_attitude(attitude, self._coefficient_readers > 0, self._inertial)
            )
        self._prepare_next()

    def _on_message_lost(self, status) -> None:
        self.messages_lost += status.total_count_change

    def _serve(self, outcome: Outcome) -> None:
        """Publish what ``outcome`` holds, keep its health, log its rejection or failure."""
        if outcome.state_accepted:
            self.health.state_accepted(time.monotonic())
        sample = outcome.sample
        if sample is not None:
            self.wrench_pub.publish(outcome.wrench_cdr)
            if outcome.coefficients_cdr is not None:
                self.coefficients_pub.publish(outcome.coefficients_cdr)
            if outcome.inertial_cdr is not None:
                self.inertial_pub.publish(outcome.inertial_cdr)
            if outcome.acceleration_cdr is not None:
                self.acceleration_pub.publish(outcome.acceleration_cdr)
            self.health.sample_computed(sample.compute_seconds, sample)
            for listener in self._sample_listeners:
                listener(sample)
        elif outcome.rejection is not None:
            exc = outcome.rejection
            self.health.rejected(exc.reason)
            self._log_throttled(
                "warning", exc.reason, f"input rejected ({exc.reason}): {exc.message}"
            )
        elif outcome.error is not None:
            if outcome.triggered:
                key, text = "compute_failed", "wrench computation failed"
            else:
                key, text = "state_failed", "state message failed"
            self._log_throttled("error", key, f"{text}: {outcome.error!r}")

    def _prepare_next(self) -> None:
        """What the next regular attitude would wait for, now that the wrench is out."""
        try:
            self.handler.prepare_next()
        except Exception as exc:  # never let it take the node down
            self._log_throttled(
                "error", "prepare_failed", f"preparing the next message failed: {exc!r}"
            )

    def add_sample_listener(self, callback) -> None:
        """Call ``callback(sample)`` with every :class:`WrenchSample` published (in-process
        users: the full flight conditions and coefficients behind each wrench, e.g. for a live
        table)."""
        self._sample_listeners.append(callback)

    # ----------------------------------------------------------------------------- diagnostics
    def diagnostic_fields(self) -> DiagnosticFields:
        """The node's health and latest values: level, name, message, hardware id, key/values."""
        est = self.estimator
        health = self.health
        values = est.diagnostic_values(health.last_sample, health.compute_ms())
        values["messages_lost"] = self.messages_lost
        values["attitudes_missing"] = self.attitude_gaps.missing
        level, message = health.level(time.monotonic(), est.settings, sum(est.rejections.values()))
        sample = health.last_sample
        if sample is not None and sample.conditions.speed > 0.0:
            kn = knudsen_number(
                sample.conditions.atmosphere.total_number_density, est.method.reference.length
            )
            values["knudsen_number"] = kn
            if kn < est.settings.knudsen_warning and level == OK:
                level = WARN
                message = (
                    f"flow not free-molecular: Kn {kn:.3g} < knudsen_warning "
                    f"{est.settings.knudsen_warning:g}"
                )
        return DiagnosticFields(
            level=level,
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


def _is_number(default) -> bool:
    """Whether a parameter's default is a float or a list of floats."""
    if isinstance(default, list):
        return bool(default) and all(isinstance(x, float) for x in default)
    return isinstance(default, float)


def params_files(argv) -> list:
    """The files given with ``--params-file`` among the ROS arguments of ``argv``."""
    files, ros, tokens = [], False, iter(argv)
    for token in tokens:
        if token == "--ros-args":
            ros = True
        elif token == "--":
            ros = False
        elif ros and token == "--params-file":
            files.append(next(tokens, ""))
    return files


def main(args=None) -> int:
    """Console script ``adbsat_node``: ``adbsat_node --ros-args --params-file config/adbsat.yaml``.

    ``--help`` (before ``--ros-args``) prints :func:`help_text` and exits. Returns the exit
    status: 0 after a shutdown or the help, 1 (one line on stderr) if the node cannot be set up.
    """
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    argv = sys.argv if args is None else args
    own = argv[1 : argv.index("--ros-args")] if "--ros-args" in argv else argv[1:]
    if "--help" in own or "-h" in own:
        print(help_text())
        return 0
    for path in params_files(argv):  # checked here: rclpy ignores unknown names, and a missing
        try:  # file fails its init with a traceback
            settings_from_file(path, NODE_NAME)
        except ValueError as exc:
            print(f"{NODE_NAME}: error: {exc}", file=sys.stderr)
            return 1
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    with stop_on_signals() as stop:  # (a signal while the node is made stops it once made)
        return _run(stop)


def _run(stop) -> int:
    """Make the node, spin it until ``stop`` or a shutdown, and take everything down in order;
    the exit status."""
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
            spin_until_shutdown(executor, stop=stop)
        except ExternalShutdownException:
            pass
        finally:
            executor.shutdown()
        return 0
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    sys.exit(main())
