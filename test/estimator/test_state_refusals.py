"""A refused state leaves the latest good one in place: at either end of every range a state is
checked against, the refusal is counted by its reason and the next attitude still gets the wrench
of the good state (the same numbers as if the refused state had never come), until that state
is stale."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS
from adbsat_ros.estimator.samples import Rejection
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.messages.cdr import Stamp
from adbsat_ros.messages.decoding import OdometryFields

EARTH = 6378137.0
R = EARTH + 300e3
V = math.sqrt(3.986004418e14 / R)
LEVEL = (0.0, 0.0, 0.0, 1.0)
YEAR = 365.25 * 86400.0

#: (what, stamp, position, velocity, reason) of states refused at either end of each range;
#: the good state is at stamp 1 s (time_mode epoch: 2026-01-01), 300 km up.
BAD_STATES = [
    ("below min_altitude", 1.02, [EARTH + 110e3, 0.0, 0.0], [0.0, V, 0.0], "altitude_out_of_range"),
    ("below the ground", 1.02, [1e3, 0.0, 0.0], [0.0, V, 0.0], "altitude_out_of_range"),
    ("above the atmosphere model", 1.02, [EARTH + 1500e3, 0.0, 0.0], [0.0, V, 0.0],
     "altitude_out_of_range"),
    ("500 m above the model's top", 1.02, [EARTH + 1000.5e3, 0.0, 0.0], [0.0, 7000.0, 0.0],
     "altitude_out_of_range"),
    ("|r| = 1e10 m", 1.02, [1e10, 0.0, 0.0], [0.0, V, 0.0], "altitude_out_of_range"),
    ("|r| = 1e300 m", 1.02, [1e300, 0.0, 0.0], [0.0, V, 0.0], "altitude_out_of_range"),
    ("|r| = 1.4e200 m", 1.02, [1e200, 1e200, 0.0], [0.0, V, 0.0], "altitude_out_of_range"),
    ("faster than any orbit", 1.02, [R, 0.0, 0.0], [0.0, 25e3, 0.0], "bad_state"),
    ("a huge velocity", 1.02, [R, 0.0, 0.0], [1e300, 1e300, 0.0], "bad_state"),
    ("NaN in the position", 1.02, [math.nan, 0.0, 0.0], [0.0, V, 0.0], "non_finite"),
    ("Inf in the velocity", 1.02, [R, 0.0, 0.0], [0.0, math.inf, 0.0], "non_finite"),
    ("a stamp after 2100", 80 * YEAR, [R, 0.0, 0.0], [0.0, V, 0.0], "bad_state"),
    ("a stamp before 1958", -70 * YEAR, [R, 0.0, 0.0], [0.0, V, 0.0], "bad_state"),
    ("a stamp beyond any date", 1e300, [R, 0.0, 0.0], [0.0, V, 0.0], "bad_state"),
    ("a late stamp", 0.99, [R, 1.0, 0.0], [0.0, V, 0.0], "out_of_order"),
    ("a second state at the stamp", 1.0, [R, 1.0, 0.0], [0.0, V, 0.0], "conflicting_state"),
]  # fmt: skip


def estimator(**overrides) -> AeroWrenchEstimator:
    params = dict(PARAMETER_DEFAULTS, mesh="example", shading="none", time_mode="epoch")
    params.update(overrides)
    return AeroWrenchEstimator(WrenchSettings.from_parameters(params))


@pytest.mark.parametrize(
    "stamp, position, velocity, reason", [case[1:] for case in BAD_STATES],
    ids=[case[0] for case in BAD_STATES],
)  # fmt: skip
def test_a_refused_state_keeps_the_last_good_one(stamp, position, velocity, reason):
    est, reference = estimator(), estimator()
    for target in (est, reference):
        good = target.on_state(1.0, [R, 0.0, 0.0], [0.0, V, 0.0])
        target.on_attitude(1.01, LEVEL)
    with pytest.raises(Rejection) as refused:
        est.on_state(stamp, position, velocity)
    assert refused.value.reason == reason
    assert est.rejections == {reason: 1} and est.state == good
    for t in (1.03, 1.5, 1.99):  # still within state_timeout (1 s) of the good state
        np.testing.assert_array_equal(
            est.on_attitude(t, LEVEL).force, reference.on_attitude(t, LEVEL).force
        )
    with pytest.raises(Rejection) as stale:  # the existing staleness rule still holds
        est.on_attitude(2.01, LEVEL)
    assert stale.value.reason == "stale_state"
    assert est.rejections == {reason: 1, "stale_state": 1}
    assert est.on_state(2.0, [R, 10.0, 0.0], [0.0, V, 0.0]).stamp == 2.0  # a good one is taken
    assert est.on_attitude(2.01, LEVEL) is not None


def test_a_refused_odometry_keeps_the_last_good_state():
    """A state refused for its frames or its body-frame orientation leaves the state too."""
    est = estimator()
    good = est.on_state(1.0, [R, 0.0, 0.0], [0.0, V, 0.0])
    for frame, child, orientation, reason in (
        ("ecef", "", LEVEL, "bad_state_frame"),
        ("camera", "", LEVEL, "bad_state_frame"),
        ("eci", "body", (0.0, 0.0, 0.0, 3.0), "bad_quaternion"),
    ):
        odometry = OdometryFields(
            Stamp(1, 20_000_000), frame, child, (R, 5.0, 0.0), orientation, (0.0, V, 0.0)
        )
        with pytest.raises(Rejection) as refused:
            est.on_odometry(odometry)
        assert refused.value.reason == reason and est.state == good
    assert est.rejections == {"bad_state_frame": 2, "bad_quaternion": 1}
    assert est.on_attitude(1.03, LEVEL).stamp == 1.03


def test_a_state_just_inside_the_atmosphere_model_is_taken():
    """The ceiling is the model's own (1000 km): a state 10 m under it is taken."""
    est = estimator()
    top = est.on_state(1.0, [EARTH + 1000e3 - 10.0, 0.0, 0.0], [0.0, 7000.0, 0.0])
    assert est.state == top and est.rejections == {}
    assert est.on_attitude(1.0, LEVEL) is not None
