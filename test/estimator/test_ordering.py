"""Messages out of order and time jumping back: one late message is refused alone and the state
kept; only a jump back beyond ``time_jump_reset`` (a looping bag) resets the history."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS
from adbsat_ros.estimator.samples import Rejection
from adbsat_ros.estimator.settings import WrenchSettings

R = 6378137.0 + 300e3
V = math.sqrt(3.986004418e14 / R)
LEVEL = (0.0, 0.0, 0.0, 1.0)


def estimator(**overrides) -> AeroWrenchEstimator:
    params = dict(PARAMETER_DEFAULTS, mesh="example", shading="none", time_mode="epoch")
    params.update(overrides)
    return AeroWrenchEstimator(WrenchSettings.from_parameters(params))


def state_at(stamp):
    """A circular orbit in the x-y plane, sampled at ``stamp`` [s]."""
    w = V / R
    c, s = math.cos(w * stamp), math.sin(w * stamp)
    return [R * c, R * s, 0.0], [-V * s, V * c, 0.0]


def test_a_1khz_stream_with_one_late_attitude_loses_that_attitude_only():
    """Attitudes at 1 kHz, states at 10 Hz, two attitudes swapped (the later one arrives first):
    the late one is refused as out_of_order and every other attitude gets its wrench, equal to
    the one of the same stream without the late message."""
    stamps = [1.0 + 1e-3 * k for k in range(400)]
    order = list(range(400))
    order[250], order[251] = 251, 250  # attitude 250 arrives 1 ms late
    est, reference = estimator(), estimator()
    forces, expected = {}, {}
    for target, sequence in ((est, order), (reference, [k for k in range(400) if k != 250])):
        out = forces if target is est else expected
        for k in sequence:
            stamp = stamps[k]
            if k % 100 == 0:
                target.on_state(stamp, *state_at(stamp))
            try:
                out[k] = target.on_attitude(stamp, LEVEL).force
            except Rejection as exc:
                out[k] = exc.reason
    assert forces.pop(250) == "out_of_order"
    assert all(isinstance(f, np.ndarray) for f in forces.values()) and len(forces) == 399
    assert est.rejections == {"out_of_order": 1} and est.published == 399
    for k, force in expected.items():
        np.testing.assert_array_equal(forces[k], force)


def test_an_attitude_jumping_back_beyond_the_limit_resets_the_history():
    """A step back larger than time_jump_reset (the bag started again) is time_backwards: the
    state goes, and the next attitude has none; a step back within it is out_of_order only."""
    est = estimator(time_jump_reset=0.5)
    est.on_state(10.0, *state_at(10.0))
    est.on_attitude(10.2, LEVEL)
    with pytest.raises(Rejection) as late:
        est.on_attitude(9.75, LEVEL)  # 0.45 s back: within the limit
    assert late.value.reason == "out_of_order" and "0.450 s" in late.value.message
    assert est.state is not None and est.on_attitude(10.21, LEVEL) is not None
    with pytest.raises(Rejection) as back:
        est.on_attitude(9.6, LEVEL)  # 0.61 s back
    assert back.value.reason == "time_backwards" and est.state is None
    with pytest.raises(Rejection) as none:
        est.on_attitude(9.61, LEVEL)
    assert none.value.reason == "no_state"
    assert est.rejections == {"out_of_order": 1, "time_backwards": 1, "no_state": 1}


def test_a_late_state_is_refused_alone_and_a_state_far_back_starts_a_new_history():
    est = estimator(time_jump_reset=1.0)
    newer = est.on_state(5.0, *state_at(5.0))
    with pytest.raises(Rejection) as late:
        est.on_state(4.95, *state_at(4.95))
    assert late.value.reason == "out_of_order" and est.state is newer
    assert est.on_attitude(5.01, LEVEL).conditions is not None
    with pytest.raises(Rejection) as back:
        est.on_state(3.5, *state_at(3.5))
    assert back.value.reason == "time_backwards" and est.state.stamp == 3.5
    assert est.on_attitude(3.51, LEVEL) is not None  # the new history goes on from there
    assert est.rejections == {"out_of_order": 1, "time_backwards": 1}


@pytest.mark.parametrize("value", [0.0, -1.0, math.inf, math.nan, "soon"])
def test_time_jump_reset_must_be_a_positive_number_of_seconds(value):
    with pytest.raises(ValueError, match=r"^parameter time_jump_reset: "):
        WrenchSettings.from_parameters(dict(PARAMETER_DEFAULTS, time_jump_reset=value))


def test_two_states_at_one_stamp_must_agree():
    """The same state sent twice is taken (and keeps its knots); a second state at that stamp
    with other numbers is refused as conflicting_state and the first one kept."""
    est = estimator()
    position, velocity = state_at(5.0)
    first = est.on_state(5.0, position, velocity)
    est.on_state(5.0, list(position), list(velocity))
    assert est.rejections == {} and est.state == first
    with pytest.raises(Rejection) as caught:
        est.on_state(5.0, position, [velocity[0], velocity[1] + 1.0, velocity[2]])
    assert caught.value.reason == "conflicting_state" and "5.0 s" in caught.value.message
    assert est.state == first and est.rejections == {"conflicting_state": 1}
    assert est.on_attitude(5.01, LEVEL) is not None


def test_a_state_below_min_altitude_is_refused():
    """Below min_altitude (default 120 km) the flow about a metre-sized body is not
    free-molecular: such a state is refused and counted; the limit is a setting."""
    est = estimator()
    low = [6378137.0 + 110e3, 0.0, 0.0], [0.0, V, 0.0]
    with pytest.raises(Rejection, match="state altitude 110.0 km is below min_altitude 120 km"):
        est.on_state(1.0, *low)
    assert est.rejections == {"altitude_out_of_range": 1} and est.state is None
    est.on_state(1.0, [6378137.0 + 125e3, 0.0, 0.0], [0.0, V, 0.0])
    assert estimator(min_altitude=100e3).on_state(1.0, *low).stamp == 1.0
