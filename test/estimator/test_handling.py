"""The per-message path shared by the node and the bag analysis, without ROS: decoded fields in,
an Outcome out (sample or why there is none, the counters), and the sample's messages as bytes."""

import dataclasses
import math

import numpy as np
import pytest

from adbsat_ros.bags import io as bag_io
from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.handling import IGNORED, MessageHandler
from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.messages.cdr import AttitudeFields, Stamp
from adbsat_ros.messages.decoding import OdometryFields, UndecodableMessage, decode_attitude
from adbsat_ros.messages.encoding import encode_wrench
from adbsat_ros.messages.stamps import stamp_seconds

R = 6378137.0 + 300e3
V = math.sqrt(3.986004418e14 / R)
TILTED = [0.0, math.sin(0.2), 0.0, math.cos(0.2)]


def settings(**overrides) -> WrenchSettings:
    params = dict(PARAMETER_DEFAULTS, mesh="example", shading="none", time_mode="epoch")
    params.update(overrides)
    return WrenchSettings.from_parameters(params)


def state(stamp: Stamp, orientation=(0.0, 0.0, 0.0, 1.0)) -> OdometryFields:
    return OdometryFields(stamp, "eci", "eci", (R, 0.0, 1e3), tuple(orientation), (0.0, V, 10.0))


def attitude(sec: int, nanosec: int, q=TILTED) -> AttitudeFields:
    return AttitudeFields(Stamp(sec, nanosec), list(q))


def wrench_of(raw):
    msg = bag_io.deserialize(raw, bag_io.WRENCH_STAMPED)
    f, m = msg.wrench.force, msg.wrench.torque
    return msg.header, [f.x, f.y, f.z], [m.x, m.y, m.z]


@pytest.fixture(scope="module")
def mesh():
    return AeroWrenchEstimator(settings()).mesh


def test_an_attitude_gives_the_estimators_sample_and_its_message_bytes(mesh):
    handler = MessageHandler(AeroWrenchEstimator(settings(body_frame_id="sat"), mesh))
    reference = AeroWrenchEstimator(settings(body_frame_id="sat"), mesh)
    accepted = handler.on_state(state(Stamp(1, 0)))
    assert accepted.state_accepted and not accepted.triggered and accepted.status is None
    assert accepted.sample is None and accepted.rejection is None and accepted.error is None
    reference.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])

    outcome = handler.on_attitude(attitude(1, 250_000_000))
    expected = reference.on_attitude(1.25, TILTED)
    assert outcome.triggered and outcome.status == "ok" and outcome.reason is None
    assert outcome.stamp == Stamp(1, 250_000_000)
    assert outcome.sample.force.tolist() == expected.force.tolist()
    messages = encode_wrench(outcome.stamp, outcome.sample, handler.estimator.settings)
    header, force, torque = wrench_of(messages.wrench)
    assert (header.stamp.sec, header.stamp.nanosec, header.frame_id) == (1, 250_000_000, "sat")
    assert force == expected.force.tolist() and torque == expected.torque.tolist()
    _, cf, cm = wrench_of(messages.coefficients)
    assert cf == expected.force_coefficients.tolist()
    assert cm == expected.moment_coefficients.tolist()
    assert np.linalg.norm(force) > 0.0
    assert messages.inertial is messages.acceleration is messages.solar is None
    without = encode_wrench(
        outcome.stamp, outcome.sample, handler.estimator.settings, coefficients=False
    )
    assert without.wrench == messages.wrench and without.coefficients is None
    assert handler.estimator.published == 1
    with pytest.raises(dataclasses.FrozenInstanceError):
        outcome.sample = None


def test_the_state_frame_wrench_and_acceleration_are_encoded_when_asked_for(mesh):
    """wrench_inertial: R force in the state frame, the torque in the body frame; acceleration:
    force / mass and inertia^-1 torque; none without a mass."""
    inertia = [2.0, 0.1, 0.0, 0.1, 3.0, 0.0, 0.0, 0.0, 4.0]
    handler = MessageHandler(
        AeroWrenchEstimator(settings(mass=50.0, inertia=inertia, state_frame="eci"), mesh)
    )
    handler.on_state(state(Stamp(1, 0)))
    outcome = handler.on_attitude(attitude(1, 250_000_000))
    sample = outcome.sample
    messages = encode_wrench(
        outcome.stamp, sample, handler.estimator.settings, coefficients=False, inertial=True
    )
    rotation = np.array(sample.rotation).reshape(3, 3)
    header, force, torque = wrench_of(messages.inertial)
    assert header.frame_id == "eci" and (header.stamp.sec, header.stamp.nanosec) == (1, 250_000_000)
    np.testing.assert_allclose(force, rotation @ sample.force, rtol=1e-15, atol=0.0)
    assert torque == sample.torque.tolist()
    accel = bag_io.deserialize(messages.acceleration, "geometry_msgs/msg/AccelStamped")
    linear = [accel.accel.linear.x, accel.accel.linear.y, accel.accel.linear.z]
    angular = [accel.accel.angular.x, accel.accel.angular.y, accel.accel.angular.z]
    np.testing.assert_allclose(linear, np.array(force) / 50.0, rtol=1e-15, atol=0.0)
    np.testing.assert_allclose(
        np.array(inertia).reshape(3, 3) @ angular,
        sample.torque,
        rtol=0.0,
        atol=1e-12 * np.linalg.norm(sample.torque),
    )
    assert np.linalg.norm(angular) > 0.0
    massless = settings(state_frame="eci")
    alone = encode_wrench(outcome.stamp, sample, massless, coefficients=False, inertial=True)
    assert alone.inertial == messages.inertial and alone.acceleration is None


def test_rejections_are_counted_and_say_why(mesh):
    handler = MessageHandler(AeroWrenchEstimator(settings(), mesh))
    rejections = handler.estimator.rejections
    outcome = handler.on_attitude(attitude(1, 0))
    assert outcome.triggered and outcome.sample is None and outcome.error is None
    assert outcome.status == outcome.reason == outcome.rejection.reason == "no_state"
    assert rejections["no_state"] == 1
    handler.on_state(state(Stamp(1, 0)))
    outcome = handler.on_attitude(attitude(1, 1, (math.nan, 0.0, 0.0, 1.0)))
    assert outcome.status == "non_finite" and rejections["non_finite"] == 1
    bad = handler.on_state(
        state(Stamp(2, 0), orientation=(0.0, 0.0, 0.0, 1.0))._replace(frame_id="ecef")
    )
    assert bad.status is None and bad.reason == "bad_state_frame" and not bad.state_accepted
    assert rejections["bad_state_frame"] == 1


def test_a_failure_is_counted_as_compute_error_and_never_raised(mesh):
    handler = MessageHandler(AeroWrenchEstimator(settings(), mesh))
    broken_state = state(Stamp(1, 0))._replace(position=("one", 0.0, 0.0))
    outcome = handler.on_state(broken_state)
    assert outcome.error is not None and outcome.rejection is None
    assert outcome.reason == "compute_error" and outcome.status is None
    handler.on_state(state(Stamp(1, 0)))
    outcome = handler.on_attitude(AttitudeFields(Stamp("one", 0), TILTED))
    assert outcome.triggered and outcome.status == "compute_error" and outcome.error is not None
    assert handler.estimator.rejections["compute_error"] == 2


def test_undecodable_bytes_are_counted(mesh):
    handler = MessageHandler(AeroWrenchEstimator(settings(), mesh))
    with pytest.raises(UndecodableMessage) as info:
        decode_attitude(b"\x00\x01\x00\x00" + b"\xff" * 12, bag_io.deserialize_attitude)
    outcome = handler.undecodable("attitude", info.value)
    assert outcome.reason == "undecodable" and outcome.stamp is None
    assert outcome.rejection.message.startswith("attitude message not a geometry_msgs")
    assert handler.estimator.rejections["undecodable"] == 1


def test_with_the_attitude_from_the_odometry_pose_a_state_is_the_trigger(mesh):
    handler = MessageHandler(AeroWrenchEstimator(settings(attitude_source="odometry"), mesh))
    reference = AeroWrenchEstimator(settings(), mesh)
    assert not handler.uses_attitude_topic
    assert handler.on_attitude(attitude(1, 0)) is IGNORED and IGNORED.status is None
    outcome = handler.on_state(state(Stamp(1, 0), orientation=TILTED))
    assert outcome.state_accepted and outcome.triggered and outcome.status == "ok"
    reference.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    assert outcome.sample.force.tolist() == reference.on_attitude(1.0, TILTED).force.tolist()
    assert sum(handler.estimator.rejections.values()) == 0


def test_the_next_regular_stamp_is_prepared_without_changing_any_number(mesh):
    handler = MessageHandler(AeroWrenchEstimator(settings(), mesh))
    reference = AeroWrenchEstimator(settings(), mesh)
    handler.on_state(state(Stamp(1, 0)))
    reference.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    assert handler.next_stamp() is None and not handler.prepare_next()
    for k in range(1, 6):
        fields = attitude(1, 3_000_000 * k)
        outcome = handler.on_attitude(fields)
        if k >= 2:
            assert handler.next_stamp() == stamp_seconds(Stamp(1, 3_000_000 * (k + 1)))
            assert handler.prepare_next()
        expected = reference.on_attitude(stamp_seconds(fields.stamp), TILTED)
        assert outcome.sample.force.tolist() == expected.force.tolist()
        assert outcome.sample.torque.tolist() == expected.torque.tolist()
    handler.on_attitude(attitude(1, 3_000_000))  # time went back: rejected, no wrench
    assert handler.next_stamp() == stamp_seconds(Stamp(1, 18_000_000))
