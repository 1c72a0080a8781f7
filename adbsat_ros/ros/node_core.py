"""The wrench node's parameters, interfaces and callbacks, mixed into a Node or LifecycleNode."""

from __future__ import annotations

import functools
import time
from typing import NamedTuple

from builtin_interfaces.msg import Time
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import AccelStamped, QuaternionStamped, WrenchStamped
from nav_msgs.msg import Odometry
from rcl_interfaces.msg import ParameterDescriptor, SetParametersResult
from rclpy.serialization import deserialize_message
from sensor_msgs.msg import JointState
from visualization_msgs.msg import Marker

from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.handling import MessageHandler, Outcome
from adbsat_ros.estimator.health import OK, WARN, Health, StampGaps
from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS, READ_ONLY_PARAMETERS
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.geometry.mesh import MeshError
from adbsat_ros.messages.decoding import (
    UndecodableMessage,
    decode_attitude,
    decode_joint_state,
    decode_odometry,
)
from adbsat_ros.messages.encoding import encode_wrench
from adbsat_ros.messages.stamps import stamp_seconds
from adbsat_ros.physics.knudsen import knudsen_number
from adbsat_ros.ros.log_throttle import LogThrottle
from adbsat_ros.ros.message_info import LostMessages
from adbsat_ros.ros.parameter_values import declare_typed_parameters
from adbsat_ros.ros.qos import OVERRIDES, check_qos_overrides, check_qos_values, input_qos
from adbsat_ros.ros.readers import Readers


class DiagnosticFields(NamedTuple):
    """The fields of the node's DiagnosticStatus; ``values`` as (key, value) string pairs."""

    level: int
    name: str
    message: str
    hardware_id: str
    values: tuple


class WrenchNodeCore:
    """The wrench node's core; once set up, its ``estimator``, ``handler`` and ``health``."""

    #: Whether messages are served (a managed node serves them only while active).
    serving = True
    #: Whether set-up parameters change while unconfigured (else they are read-only).
    managed = False
    #: The lifecycle state's label (a managed node's), or None.
    lifecycle_state = None

    def declare_wrench_parameters(self) -> None:
        """Declare every parameter, typed (ValueError otherwise), and the change callback."""
        declare_typed_parameters(self, self.managed)
        self.estimator = None
        self._publishers_made, self._subscriptions_made = [], []
        self._lost: dict = {}  # LostMessages by topic, once set up
        self._diag_timer = self._marker_timer = None
        self.add_on_set_parameters_callback(self._on_set_parameters)
        check_qos_values(self)
        # /diagnostics from the start, also while a managed node is not configured or not active
        self.diagnostics_pub = self.create_publisher(
            DiagnosticArray, "/diagnostics", 10, qos_overriding_options=OVERRIDES
        )
        period = self.get_parameter("diagnostics_period").value
        valid = isinstance(period, float) and 0.0 < period < 1e6
        self._retime_diagnostics(period if valid else PARAMETER_DEFAULTS["diagnostics_period"])

    def set_up(self, create_publisher) -> None:
        """Load the set-up (MeshError, ValueError) and make the interfaces and timers."""
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
            if not self.has_parameter(name):
                self.declare_parameter(
                    name, value, ParameterDescriptor(description=text, read_only=True)
                )
        qos = settings.qos_depth  # (outputs: RELIABLE, which BEST_EFFORT readers take too)
        create_publisher = functools.partial(create_publisher, qos_overriding_options=OVERRIDES)
        self.wrench_pub = create_publisher(WrenchStamped, "wrench", qos)
        # the optional outputs' readers, counted by matched events (ros/readers.py)
        self.readers = readers = Readers(create_publisher)
        self.coefficients_pub = readers.publisher(WrenchStamped, "coefficients", qos)
        # for a propagator, while subscribed: the force in the state frame, and the acceleration
        self.inertial_pub = readers.publisher(WrenchStamped, "wrench_inertial", qos)
        self.acceleration_pub = readers.publisher(AccelStamped, "acceleration", qos)
        # with solar_pressure on: the solar radiation wrench, and the sum of both
        self.solar_pub = create_publisher(WrenchStamped, "solar_wrench", qos)
        self.total_pub = create_publisher(WrenchStamped, "total_wrench", qos)
        self.marker_pub = readers.publisher(Marker, "panel_marker", 1)
        # messages come in as CDR bytes (messages.decoding). State first: the single-threaded
        # executor takes waiting messages in subscription order, and an attitude wants the
        # newest state.
        self._odometry_message = functools.partial(deserialize_message, message_type=Odometry)
        self._attitude_message = functools.partial(
            deserialize_message, message_type=QuaternionStamped
        )
        # messages lost on the way (LostMessages) and attitudes missing by their stamps
        # (StampGaps), for /diagnostics
        self._lost = {"state": LostMessages(), "attitude": LostMessages()}
        self.attitude_gaps = StampGaps()
        subscriptions = [
            self._counted_subscription(Odometry, "state", self._on_state, input_qos(qos)),
            self._counted_subscription(
                QuaternionStamped, "attitude", self._on_attitude, input_qos(qos)
            ),
        ]
        self.joint_torques_pub = None
        if self.estimator.body is not None:  # an articulated body: its joints in and out
            self._joint_state_message = functools.partial(
                deserialize_message, message_type=JointState
            )
            subscriptions.append(
                self.create_subscription(
                    JointState,
                    "joint_states",
                    self._on_joint_state,
                    input_qos(qos),
                    raw=True,
                    qos_overriding_options=OVERRIDES,
                )
            )
            self.joint_torques_pub = readers.publisher(JointState, "joint_torques", qos)
        self._sample_listeners: list = []
        self._log_throttled = LogThrottle(self.get_logger())
        self._retime_diagnostics(settings.diagnostics_period)
        self._marker_timer = self.create_timer(settings.marker_period, self._publish_marker)
        self._publishers_made = [
            self.wrench_pub,
            self.coefficients_pub,
            self.inertial_pub,
            self.acceleration_pub,
            self.solar_pub,
            self.total_pub,
            self.marker_pub,
        ] + ([self.joint_torques_pub] if self.joint_torques_pub is not None else [])
        self._subscriptions_made = subscriptions
        check_qos_overrides(self)
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

    def tear_down(self, destroy_publisher) -> None:
        """Destroy the publishers, subscriptions and timers, and drop the set-up."""
        for publisher in self._publishers_made:
            destroy_publisher(publisher)
        for subscription in self._subscriptions_made:
            self.destroy_subscription(subscription)
        self._publishers_made, self._subscriptions_made = [], []
        if self._marker_timer is not None:
            self.destroy_timer(self._marker_timer)
        self._marker_timer = None
        self.estimator = None

    @property
    def coefficient_readers(self) -> int:
        """Subscribers of the coefficients topic (published only while there is one)."""
        return self.readers.counts.get("coefficients", 0)

    @property
    def joint_torque_readers(self) -> int:
        """Subscribers of the joint_torques topic (published only while there is one)."""
        return self.readers.counts.get("joint_torques", 0)

    # ----------------------------------------------------------------------------- parameters
    def _parameter_values(self, changes=()) -> dict:
        values = {name: self.get_parameter(name).value for name in PARAMETER_DEFAULTS}
        for p in changes:
            values[p.name] = p.value
        return values

    def _on_set_parameters(self, params) -> SetParametersResult:
        relevant = [p for p in params if p.name in PARAMETER_DEFAULTS]
        if not relevant:
            return SetParametersResult(successful=True)
        fixed = [p.name for p in relevant if p.name in READ_ONLY_PARAMETERS]
        if fixed and self.estimator is not None:  # (a managed node while configured)
            reason = f"parameter {fixed[0]}: changes only while the node is unconfigured"
            return SetParametersResult(successful=False, reason=reason)
        try:
            settings = WrenchSettings.from_parameters(self._parameter_values(relevant))
            if self.estimator is not None:  # (else not set up yet: checked, used at set-up)
                self.estimator.apply_settings(settings)
        except (ValueError, MeshError) as exc:
            self.get_logger().warning(f"parameter change rejected: {exc}")
            return SetParametersResult(successful=False, reason=str(exc))
        if self._diag_timer is not None:  # (None while the parameters are declared)
            self._retime_diagnostics(settings.diagnostics_period)
        if self.estimator is None:
            return SetParametersResult(successful=True)
        if settings.marker_period != self._marker_timer.timer_period_ns * 1e-9:
            self._marker_timer.cancel()
            self.destroy_timer(self._marker_timer)
            self._marker_timer = self.create_timer(settings.marker_period, self._publish_marker)
        self.get_logger().info(
            "parameters changed: " + ", ".join(f"{p.name}={p.value}" for p in relevant)
        )
        return SetParametersResult(successful=True)

    def _retime_diagnostics(self, period: float) -> None:
        """Publish /diagnostics every ``period`` s."""
        timer = self._diag_timer
        if timer is not None and timer.timer_period_ns == round(period * 1e9):
            return
        if timer is not None:
            timer.cancel()
            self.destroy_timer(timer)
        self._diag_timer = self.create_timer(period, self._publish_diagnostics)

    # ----------------------------------------------------------------------------- messages
    def _on_state(self, raw: bytes) -> None:
        """A state as the CDR bytes of a nav_msgs/Odometry."""
        if not self.serving:
            return
        try:
            odometry = decode_odometry(raw, self._odometry_message)
        except UndecodableMessage as exc:
            self._serve(self.handler.undecodable("state", exc))
            return
        outcome = self.handler.on_state(odometry)
        self._serve(outcome)
        if outcome.triggered:
            self._prepare_next()

    def _on_attitude(self, raw: bytes) -> None:
        """An attitude as the CDR bytes of a QuaternionStamped; then what the next stamp needs."""
        handler = self.handler
        if not (self.serving and handler.uses_attitude_topic):
            return
        try:
            attitude = decode_attitude(raw, self._attitude_message)
        except UndecodableMessage as exc:
            self._serve(handler.undecodable("attitude", exc))
        else:
            self.attitude_gaps.stamp(stamp_seconds(attitude.stamp))
            self._serve(handler.on_attitude(attitude))
        self._prepare_next()

    def _on_joint_state(self, raw: bytes) -> None:
        """Joint positions as the CDR bytes of a sensor_msgs/JointState."""
        if not self.serving:
            return
        try:
            joint_state = decode_joint_state(raw, self._joint_state_message)
        except UndecodableMessage as exc:
            self._serve(self.handler.undecodable("joint_states", exc))
            return
        self._serve(self.handler.on_joint_state(joint_state))

    def _counted_subscription(self, msg_type, topic: str, callback, qos):
        """A raw subscription whose lost messages are counted in ``self._lost[topic]``."""
        lost = self._lost[topic]
        subscription = self.create_subscription(
            msg_type,
            topic,
            lost.callback(callback),
            qos,
            raw=True,
            event_callbacks=lost.event_callbacks(),
            qos_overriding_options=OVERRIDES,
        )
        lost.attach(subscription)
        return subscription

    @property
    def messages_lost(self) -> int:
        """State and attitude messages lost on the way to the node (:class:`LostMessages`)."""
        return sum(lost.lost for lost in self._lost.values())

    def _serve(self, outcome: Outcome) -> None:
        """Publish ``outcome``'s messages, keep its health, log a rejection or failure."""
        if outcome.state_accepted:
            self.health.state_accepted(time.monotonic())
        sample = outcome.sample
        if sample is not None:
            readers = self.readers
            messages = encode_wrench(
                outcome.stamp,
                sample,
                self.estimator.settings,
                coefficients=readers.coefficients,
                inertial=readers.inertial,
                joint_torques=readers.joint_torques,
            )
            self.wrench_pub.publish(messages.wrench)
            if messages.coefficients is not None:
                self.coefficients_pub.publish(messages.coefficients)
            if messages.inertial is not None:
                self.inertial_pub.publish(messages.inertial)
            if messages.acceleration is not None:
                self.acceleration_pub.publish(messages.acceleration)
            if messages.solar is not None:
                self.solar_pub.publish(messages.solar)
                self.total_pub.publish(messages.total)
            if messages.joint_torques is not None:
                self.joint_torques_pub.publish(messages.joint_torques)
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
        """Call ``callback(sample)`` with every :class:`WrenchSample` published (in-process use)."""
        self._sample_listeners.append(callback)

    # ----------------------------------------------------------------------------- diagnostics
    def diagnostic_fields(self) -> DiagnosticFields:
        """The node's health and latest values: level, name, message, hardware id, key/values;
        a managed node's lifecycle state too (WARN while not active; only it while unconfigured)."""
        est, label = self.estimator, self.lifecycle_state
        name = f"{self.get_name()}: aerodynamic wrench"
        if est is None:
            message = f"lifecycle state {label}: not configured"
            return DiagnosticFields(WARN, name, message, "", (("lifecycle_state", label),))
        health = self.health
        values = est.diagnostic_values(health.last_sample, health.compute_ms())
        values["messages_lost"] = self.messages_lost
        values["attitudes_lost"] = self._lost["attitude"].lost
        values["states_lost"] = self._lost["state"].lost
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
        if label is not None:
            values["lifecycle_state"] = label
            if label != "active":
                level, message = WARN, f"lifecycle state {label}: not serving"
        return DiagnosticFields(
            level=level,
            name=name,
            message=message,
            hardware_id=est.mesh.source,
            values=tuple((k, str(v)) for k, v in values.items()),
        )

    def _publish_marker(self) -> None:
        """The panels coloured by the latest wrench's pressures, while someone subscribes."""
        sample = self.health.last_sample
        if not (self.serving and self.readers.marker) or sample is None:
            return
        if sample.coefficients is None:  # (at rest, or coefficients from a database)
            return
        try:
            from adbsat_ros.ros.panel_marker import panel_marker  # (matplotlib: when first asked)

            sec, nanosec = divmod(round(sample.stamp * 1e9), 1_000_000_000)
            stamp = Time(sec=int(sec), nanosec=int(nanosec))
            est, joints = self.estimator, sample.joints
            mesh = (
                est.mesh
                if joints is None
                else est.body.mesh(dict(zip(joints.names, joints.positions)))
            )
            frame = est.settings.body_frame_id
            self.marker_pub.publish(panel_marker(mesh, sample.coefficients, frame, stamp))
        except Exception as exc:  # the picture must never take the node down
            self._log_throttled("error", "marker_failed", f"panel marker failed: {exc!r}")

    def _publish_diagnostics(self) -> None:
        try:
            fields = self.diagnostic_fields()
            array = DiagnosticArray()
            array.header.stamp = self.get_clock().now().to_msg()
            array.status = [
                DiagnosticStatus(
                    level=bytes([fields.level]),
                    name=fields.name,
                    message=fields.message,
                    hardware_id=fields.hardware_id,
                    values=[KeyValue(key=k, value=v) for k, v in fields.values],
                )
            ]
            self.diagnostics_pub.publish(array)
        except Exception as exc:  # diagnostics must never take the node down
            self._log_throttled("error", "diagnostics_failed", f"diagnostics failed: {exc!r}")
