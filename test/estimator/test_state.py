"""Accepting states: quaternion checks, state checks and the Odometry frame rules."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.samples import OrbitalState, Rejection
from adbsat_ros.estimator.settings import PARAMETER_DEFAULTS, WrenchSettings
from adbsat_ros.estimator.state import (
    STATE_FRAME_NAMES,
    checked_rotation,
    checked_state,
    odometry_inputs,
)
from adbsat_ros.messages.cdr import OdometryFields, Stamp

R = 6378137.0 + 300e3
V = math.sqrt(3.986004418e14 / R)
QUARTER_TURN_Z = (0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4))  # body x -> state y


def odometry(frame="eci", child="", velocity=(0.0, V, 0.0), orientation=QUARTER_TURN_Z):
    return OdometryFields(
        Stamp(12, 500_000_000), frame, child, (R, 0.0, 1e3), tuple(orientation), velocity
    )


def test_a_quaternion_is_normalised_within_the_tolerance_and_refused_beyond_it():
    m = checked_rotation((0.0, 0.0, 0.0, 1.0 + 5e-7), "attitude quaternion", 1e-6)
    np.testing.assert_array_equal(np.array(m).reshape(3, 3), np.eye(3))
    rotated = np.array(checked_rotation(QUARTER_TURN_Z, "q", 1e-6)).reshape(3, 3)
    quarter_turn = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]  # about z: x -> y
    np.testing.assert_allclose(rotated, quarter_turn, atol=1e-15)
    for bad, reason in (
        ((0.0, 0.0, 0.0, 1.1), "bad_quaternion"),
        ((math.nan, 0.0, 0.0, 1.0), "non_finite"),
        ((0.0, 0.0, 1.0), "non_finite"),
        ("wxyz", "non_finite"),
    ):
        with pytest.raises(Rejection) as rejected:
            checked_rotation(bad, "attitude quaternion", 1e-6)
        assert rejected.value.reason == reason and "attitude quaternion" in rejected.value.message


def test_a_state_velocity_in_the_body_frame_is_rotated_into_the_state_frame():
    state = checked_state(1.0, [R, 0.0, 0.0], [V, 0.0, 0.0], True, QUARTER_TURN_Z, 1e-6)
    np.testing.assert_allclose(state.velocity, [0.0, V, 0.0], atol=1e-9)
    plain = checked_state(1.0, [R, 0.0, 0.0], [V, 0.0, 0.0], False, None, 1e-6)
    np.testing.assert_array_equal(plain.velocity, [V, 0.0, 0.0])
    with pytest.raises(Rejection, match="NaN or Inf") as rejected:
        checked_state(math.inf, [R, 0.0, 0.0], [V, 0.0, 0.0], False, None, 1e-6)
    assert rejected.value.reason == "non_finite"
    with pytest.raises(Rejection) as rejected:
        checked_state(1.0, [R, 0.0, 0.0], [V, 0.0, 0.0], True, (0.0, 0.0, 0.0, 3.0), 1e-6)
    assert rejected.value.reason == "bad_quaternion"


@pytest.mark.parametrize("child", [*STATE_FRAME_NAMES, "ECI", "/eci"])
def test_a_twist_in_the_state_frame_is_taken_as_it_is(child):
    stamp, position, velocity, in_body, orientation = odometry_inputs(
        odometry(child=child), "eci", "body"
    )
    assert stamp == 12.5 and position == [R, 0.0, 1e3] and velocity == [0.0, V, 0.0]
    assert not in_body and orientation == list(QUARTER_TURN_Z)


def test_a_twist_in_the_body_frame_or_the_header_frame_and_the_frame_rules():
    assert odometry_inputs(odometry(child="/body"), "eci", "body")[3]
    assert not odometry_inputs(odometry(frame="sim_world", child="sim_world"), "eci", "body")[3]
    for message, text in (
        (odometry(frame="ecef"), "state_frame is eci"),
        (odometry(child="camera"), "neither the body frame 'body' nor the state frame"),
    ):
        with pytest.raises(Rejection, match=text) as rejected:
            odometry_inputs(message, "eci", "body")
        assert rejected.value.reason == "bad_state"


def test_the_estimator_counts_odometry_rejections_and_rotates_a_body_twist():
    est = AeroWrenchEstimator(
        WrenchSettings.from_parameters(
            dict(PARAMETER_DEFAULTS, mesh="example", shading="none", time_mode="epoch")
        )
    )
    state, orientation = est.on_odometry(odometry(child="body", velocity=(V, 0.0, 0.0)))
    np.testing.assert_allclose(state.velocity, [0.0, V, 0.0], atol=1e-9)
    assert state.stamp == 12.5 and orientation == list(QUARTER_TURN_Z) and est.state is state
    for message in (odometry(frame="ecef"), odometry(child="camera")):
        with pytest.raises(Rejection):
            est.on_odometry(message)
    assert est.rejections == {"bad_state": 2} and est.state is state


def test_orbital_states_are_equal_by_value():
    """Two states with the same stamp, position and velocity are equal (the knots' key); any
    difference makes them unequal; a state is not hashable (it holds arrays)."""
    a = OrbitalState(1.5, np.array([7e6, 0.0, 0.0]), np.array([0.0, 7.5e3, 0.0]))
    assert a == OrbitalState(1.5, np.array([7e6, 0.0, 0.0]), np.array([0.0, 7.5e3, 0.0]))
    assert a != OrbitalState(1.5, np.array([7e6, 0.0, 1e-9]), np.array([0.0, 7.5e3, 0.0]))
    assert a != OrbitalState(1.5, np.array([7e6, 0.0, 0.0]), np.array([0.0, 7.5e3, 1e-9]))
    assert a != OrbitalState(1.25, a.position, a.velocity) and a != None  # noqa: E711
    with pytest.raises(TypeError):
        hash(a)
