"""AeroWrenchEstimator without ROS: reuse of flight conditions between attitudes at one stamp."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbsat_ros.aero_wrench import AeroWrenchEstimator
from adbsat_ros.wrench_settings import PARAMETER_DEFAULTS, WrenchSettings

R = 6378137.0 + 300e3
V = math.sqrt(3.986004418e14 / R)
TILTED = (0.0, math.sin(0.2), 0.0, math.cos(0.2))  # 23 deg about body y


def estimator(**overrides) -> AeroWrenchEstimator:
    params = dict(PARAMETER_DEFAULTS, mesh="example", shading="none", time_mode="epoch")
    params.update(overrides)
    return AeroWrenchEstimator(WrenchSettings.from_parameters(params))


def fresh_sample(stamp, state_stamp, quaternion, **overrides):
    est = estimator(**overrides)
    est.on_state(state_stamp, [R, 0.0, 1e3], [0.0, V, 10.0])
    return est.on_attitude(stamp, quaternion)


def test_attitudes_at_one_stamp_share_the_flight_conditions_and_equal_a_fresh_estimator():
    est = estimator()
    est.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    first = est.on_attitude(1.0, (0.0, 0.0, 0.0, 1.0))
    second = est.on_attitude(1.0, TILTED)
    assert second.conditions is first.conditions  # reused, not recomputed
    assert second.time == first.time
    reference = fresh_sample(1.0, 1.0, TILTED)
    np.testing.assert_array_equal(second.force, reference.force)
    np.testing.assert_array_equal(second.torque, reference.torque)
    assert not np.allclose(second.force, first.force)  # the attitude did change the wrench


def test_a_new_stamp_or_a_new_state_recomputes_the_conditions():
    est = estimator()
    est.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    a = est.on_attitude(1.0, TILTED)
    b = est.on_attitude(1.05, TILTED)  # later stamp: propagated position, other conditions
    assert b.conditions is not a.conditions
    assert b.conditions.position_eci[1] == pytest.approx(V * 0.05)
    np.testing.assert_array_equal(b.force, fresh_sample(1.05, 1.0, TILTED).force)
    est.on_state(1.05, [R, 0.0, 1e3], [0.0, V, 10.0])  # a new state at that very stamp
    c = est.on_attitude(1.05, TILTED)
    assert c.conditions is not b.conditions
    assert c.conditions.position_eci[1] == 0.0  # the new state's position, not the propagated one
    np.testing.assert_array_equal(c.force, fresh_sample(1.05, 1.05, TILTED).force)


def test_a_settings_change_recomputes_the_conditions():
    est = estimator()
    est.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    quiet = est.on_attitude(1.0, TILTED)
    est.apply_settings(WrenchSettings.from_parameters(
        dict(est.settings.as_parameters(), f107=250.0, f107a=250.0)))
    active = est.on_attitude(1.0, TILTED)
    assert active.conditions.mass_density > 1.5 * quiet.conditions.mass_density
    np.testing.assert_array_equal(active.force, fresh_sample(1.0, 1.0, TILTED, f107=250.0, f107a=250.0).force)


def test_prepare_next_computes_the_next_regular_stamp_ahead_and_changes_no_result():
    est = estimator()
    est.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    assert not est.prepare_next()  # one attitude: no interval yet
    est.on_attitude(1.00, TILTED)
    est.on_attitude(1.01, TILTED)
    assert est.prepare_next()
    ready = est._conditions_memo[-1]
    assert ready[1] == 1.01 + (1.01 - 1.00)
    regular = est.on_attitude(1.01 + (1.01 - 1.00), TILTED)
    assert regular.conditions is ready[4]  # taken from the prepared conditions
    np.testing.assert_array_equal(regular.force, fresh_sample(1.01 + (1.01 - 1.00), 1.0, TILTED).force)
    np.testing.assert_array_equal(regular.torque, fresh_sample(1.01 + (1.01 - 1.00), 1.0, TILTED).torque)
    assert est.prepare_next()
    irregular = est.on_attitude(1.0275, TILTED)  # not the predicted stamp: computed as usual
    assert irregular.conditions is not est._conditions_memo[0][4]
    np.testing.assert_array_equal(irregular.force, fresh_sample(1.0275, 1.0, TILTED).force)
    # nothing is prepared beyond the state time-out, and nothing is counted as rejected
    est.on_attitude(1.9, TILTED)
    assert not est.prepare_next()  # 1.9 + 0.8725 is more than state_timeout from the state
    assert sum(est.rejections.values()) == 0
