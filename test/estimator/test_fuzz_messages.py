"""Random message streams through the node's per-message path (the handler the node and bag
analysis share): it never raises, every wrench it gives is finite and is the estimator's own
result for the same messages, and every message without a wrench is counted."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from adbsat_ros.bags import io as bag_io
from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.handling import MessageHandler
from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS
from adbsat_ros.estimator.samples import Rejection
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.messages.cdr import AttitudeFields, Stamp
from adbsat_ros.messages.decoding import OdometryFields
from adbsat_ros.messages.encoding import encode_wrench
from adbsat_ros.messages.stamps import stamp_seconds

R = 6378137.0 + 300e3
V = math.sqrt(3.986004418e14 / R)

#: Numbers as they may come in a message: ordinary, extreme, and not numbers at all.
EXTREME = st.sampled_from(
    [0.0, -0.0, 1e-300, -1e-300, 1e300, -1e300, math.inf, -math.inf, math.nan]
)
NUMBER = st.one_of(st.floats(-1e4, 1e4), EXTREME, st.floats(allow_nan=True, allow_infinity=True))


def good_state(k: int) -> OdometryFields:
    """The k-th state of a circular orbit at 300 km, every 0.1 s."""
    w = V / R
    c, s = math.cos(w * 0.1 * k), math.sin(w * 0.1 * k)
    return OdometryFields(
        Stamp(*divmod(100_000_000 * k, 1_000_000_000)),
        "eci",
        "eci",
        (R * c, R * s, 0.0),
        (0.0, 0.0, 0.0, 1.0),
        (-V * s, V * c, 0.0),
    )


def good_attitude(k: int) -> AttitudeFields:
    """The k-th attitude, every 0.02 s, turning slowly about z."""
    h = 0.005 * k
    stamp = Stamp(*divmod(20_000_000 * k, 1_000_000_000))
    return AttitudeFields(stamp, [0.0, 0.0, math.sin(h), math.cos(h)])


STATE_FIELDS = [None, "stamp", "frame_id", "child_frame_id", "position", "orientation_xyzw"]
STATE_FIELDS += ["linear_velocity"]
NAMES = st.sampled_from(["", "map", "ITRF", "camera", "x" * 300])


@st.composite
def message(draw):
    """A message of a good stream (in order or not) with at most one field replaced by
    anything at all."""
    k = draw(st.integers(0, 60))
    if draw(st.booleans()):
        msg, field = good_state(k // 5), draw(st.sampled_from(STATE_FIELDS))
    else:
        msg = good_attitude(k)
        field = draw(st.sampled_from([None, None, "stamp", "quaternion_xyzw"]))
    if field == "stamp":
        sec, nanosec = draw(st.integers(0, 2**31 - 1)), draw(st.integers(0, 999_999_999))
        return msg._replace(stamp=Stamp(sec, nanosec))
    if field in ("frame_id", "child_frame_id"):
        return msg._replace(**{field: draw(NAMES)})
    if field is not None:
        values = list(getattr(msg, field))
        values[draw(st.integers(0, len(values) - 1))] = draw(NUMBER)
        return msg._replace(**{field: values if field == "quaternion_xyzw" else tuple(values)})
    return msg


@st.composite
def stream(draw):
    """Up to 40 such messages, most often in stamp order (as a simulator sends them)."""
    messages = draw(st.lists(message(), min_size=1, max_size=40))
    if draw(st.integers(0, 3)):
        messages.sort(key=lambda m: (stamp_seconds(m.stamp), isinstance(m, AttitudeFields)))
    return messages


@pytest.fixture(scope="module")
def setup():
    params = dict(PARAMETER_DEFAULTS, mesh="example", shading="none", time_mode="epoch")
    wrench_settings = WrenchSettings.from_parameters(params)
    return wrench_settings, AeroWrenchEstimator(wrench_settings).mesh


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(messages=stream())
def test_any_stream_gives_finite_wrenches_equal_to_the_estimators_or_counted_rejections(
    setup, messages
):
    wrench_settings, mesh = setup
    handler = MessageHandler(AeroWrenchEstimator(wrench_settings, mesh))
    reference = AeroWrenchEstimator(wrench_settings, mesh)
    wrenches = 0
    for msg in messages:
        if isinstance(msg, OdometryFields):
            outcome = handler.on_state(msg)
            try:
                reference.on_odometry(msg)
            except Rejection:
                pass
            assert outcome.sample is None
            continue
        outcome = handler.on_attitude(msg)
        try:
            expected = reference.on_attitude(stamp_seconds(msg.stamp), msg.quaternion_xyzw)
        except Rejection as exc:
            expected = exc
        if outcome.sample is None:
            assert outcome.reason is not None
            assert isinstance(expected, Rejection) and expected.reason == outcome.reason
            continue
        wrenches += 1
        raw = encode_wrench(outcome.stamp, outcome.sample, wrench_settings).wrench
        wrench = bag_io.deserialize(raw, bag_io.WRENCH_STAMPED).wrench
        force = [wrench.force.x, wrench.force.y, wrench.force.z]
        torque = [wrench.torque.x, wrench.torque.y, wrench.torque.z]
        assert all(math.isfinite(x) for x in force + torque)
        np.testing.assert_array_equal(force, expected.force)
        np.testing.assert_array_equal(torque, expected.torque)
    event(f"wrenches: {min(wrenches, 3)}{'+' if wrenches > 3 else ''}")
    estimator = handler.estimator
    attitudes = sum(isinstance(m, AttitudeFields) for m in messages)
    states = len(messages) - attitudes
    assert estimator.published == wrenches
    # every attitude has its wrench or a counted reason; states are counted when refused
    rejected = sum(estimator.rejections.values())
    assert wrenches + rejected >= attitudes
    assert wrenches + rejected <= attitudes + states
    assert dict(estimator.rejections) == dict(reference.rejections)
