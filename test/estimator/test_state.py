"""Accepting states: quaternion checks, state checks and the Odometry frame rules."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.parameters import (
    DEFAULT_ECEF_FRAME_IDS,
    DEFAULT_ECI_FRAME_IDS,
    PARAMETER_DEFAULTS,
)
from adbsat_ros.estimator.samples import OrbitalState, Rejection
from adbsat_ros.estimator.settings import FrameIds, WrenchSettings
from adbsat_ros.estimator.state import checked_rotation, checked_state, odometry_inputs
from adbsat_ros.messages.cdr import Stamp
from adbsat_ros.messages.decoding import OdometryFields

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


FRAME_IDS = FrameIds(eci=DEFAULT_ECI_FRAME_IDS, ecef=DEFAULT_ECEF_FRAME_IDS)


@pytest.mark.parametrize("child", ["", "eci", "ECI", "/eci", "gcrf", "j2000"])
def test_a_twist_in_the_state_frame_is_taken_as_it_is(child):
    stamp, position, velocity, in_body, orientation = odometry_inputs(
        odometry(child=child), "eci", "body", FRAME_IDS
    )
    assert stamp == 12.5 and position == [R, 0.0, 1e3] and velocity == [0.0, V, 0.0]
    assert not in_body and orientation == list(QUARTER_TURN_Z)


@pytest.mark.parametrize("state_frame", ["eci", "ecef"])
def test_the_frame_of_a_state_is_read_from_its_names(state_frame):
    """Every default name of the expected frame is taken (any case, a leading slash); a name of
    the other frame is refused as that frame; a name of neither is refused with the name."""
    own = FRAME_IDS.eci if state_frame == "eci" else FRAME_IDS.ecef
    other = FRAME_IDS.ecef if state_frame == "eci" else FRAME_IDS.eci
    other_name = "ECEF" if state_frame == "eci" else "ECI"
    for name in own:
        for spelling in (name, name.upper(), "/" + name):
            assert not odometry_inputs(odometry(frame=spelling), state_frame, "body", FRAME_IDS)[3]
    for name in other:
        with pytest.raises(Rejection, match=f"frame_id '{name}' is {other_name}") as rejected:
            odometry_inputs(odometry(frame=name), state_frame, "body", FRAME_IDS)
        assert rejected.value.reason == "bad_state_frame"
    for name in ("", "sim_world", "map", "odom", "teme"):
        with pytest.raises(Rejection, match=f"unknown frame_id '{name}'") as rejected:
            odometry_inputs(odometry(frame=name), state_frame, "body", FRAME_IDS)
        assert rejected.value.reason == "bad_state_frame"
        assert "eci_frame_ids" in rejected.value.message


def test_frame_names_are_settings_and_the_twist_frame_rules():
    custom = FrameIds(eci=("sim_inertial",), ecef=("sim_earth",))
    assert not odometry_inputs(odometry(frame="sim_inertial"), "eci", "body", custom)[3]
    with pytest.raises(Rejection, match="unknown frame_id 'eci'"):
        odometry_inputs(odometry(frame="eci"), "eci", "body", custom)
    assert odometry_inputs(odometry(child="/body"), "eci", "body", FRAME_IDS)[3]
    assert not odometry_inputs(odometry(frame="gcrf", child="eci"), "eci", "body", FRAME_IDS)[3]
    for child in ("camera", "itrf"):
        with pytest.raises(Rejection, match="neither the body frame 'body' nor the state frame"):
            odometry_inputs(odometry(child=child), "eci", "body", FRAME_IDS)
    settings = WrenchSettings.from_parameters(
        dict(PARAMETER_DEFAULTS, eci_frame_ids=["Sim_Inertial"], ecef_frame_ids=["sim_earth"])
    )
    assert settings.frame_ids == FrameIds(eci=("sim_inertial",), ecef=("sim_earth",))
    for eci, ecef, text in (
        (["eci", "itrf"], ["itrf"], "'itrf' names both frames"),
        ([], ["itrf"], "eci_frame_ids must name at least one frame"),
        (["eci"], ["ecef", ""], "ecef_frame_ids: names must be non-empty"),
    ):
        with pytest.raises(ValueError, match=text):
            WrenchSettings.from_parameters(
                dict(PARAMETER_DEFAULTS, eci_frame_ids=eci, ecef_frame_ids=ecef)
            )


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
    assert est.rejections == {"bad_state_frame": 2} and est.state is state


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


def test_an_attitude_frame_must_name_the_state_frame():
    """A QuaternionStamped's frame_id is the frame its orientation is given in: a name of the state
    frame (any case, a leading slash) or an empty one is taken; the other state frame, the body
    frame or an unknown name is refused as bad_attitude_frame, named and counted."""
    est = AeroWrenchEstimator(
        WrenchSettings.from_parameters(
            dict(PARAMETER_DEFAULTS, mesh="example", shading="none", time_mode="epoch")
        )
    )
    est.on_odometry(odometry())
    stamp = 12.5
    for frame in ("eci", "/GCRF", "j2000", ""):
        stamp += 0.01
        assert est.on_attitude(stamp, QUARTER_TURN_Z, frame).stamp == stamp
    for frame, text in (
        ("ecef", "attitude frame_id 'ecef' is ECEF but parameter state_frame is eci"),
        ("base_link", "attitude frame_id 'base_link' is the body frame, not the state frame"),
        ("body", "attitude frame_id 'body' is the body frame"),
        ("map", "unknown frame_id 'map' of an attitude: not among the names of eci_frame_ids"),
    ):
        with pytest.raises(Rejection, match=text) as refused:
            est.on_attitude(stamp + 0.01, QUARTER_TURN_Z, frame)
        assert refused.value.reason == "bad_attitude_frame"
    assert est.rejections == {"bad_attitude_frame": 4} and est.published == 4
