"""The health levels of the diagnostics (node and bag analysis), and what Health keeps."""

import numpy as np
import pytest

from adbsat_ros.estimator.health import (
    ERROR,
    OK,
    WARN,
    Health,
    SequenceGaps,
    StampGaps,
    health_level,
)
from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS
from adbsat_ros.estimator.settings import WrenchSettings


def test_levels_and_messages():
    assert health_level(None, None, 0, 1.0, 1.0) == (ERROR, "no orbital state")
    # stale beyond the larger of the state time-out and the diagnostics period
    assert health_level(2.04, None, 0, 2.0, 1.0) == (ERROR, "state is stale (2.0 s old)")
    assert health_level(2.04, None, 0, 1.0, 2.0) == (ERROR, "state is stale (2.0 s old)")
    assert health_level(2.0, None, 0, 2.0, 1.0) == (OK, "ok")  # at the limit: not yet
    assert health_level(1.5, None, 0, 1.0, 2.0) == (OK, "ok")
    # the latest rejection a state too far from the attitudes: ERROR whatever the counts
    assert health_level(0.1, "stale_state", 3, 1.0, 1.0) == (
        ERROR,
        "state is stale relative to the attitude stamps",
    )
    assert health_level(0.1, "no_state", 3, 1.0, 1.0) == (
        WARN,
        "3 inputs rejected so far (latest: no_state)",
    )
    # the refusal that left no usable state leads the message
    assert health_level(None, "no_state", 3, 1.0, 1.0, "bad_state_frame") == (
        ERROR,
        "bad_state_frame: no orbital state",
    )
    assert health_level(3.0, "no_state", 3, 1.0, 1.0, "bad_state_frame") == (
        ERROR,
        "bad_state_frame: state is stale (3.0 s old)",
    )
    assert health_level(0.1, None, 0, 1.0, 1.0) == (OK, "ok")
    assert (OK, WARN, ERROR) == (0, 1, 2)  # diagnostic_msgs/DiagnosticStatus levels


def test_health_follows_states_rejections_and_samples():
    settings = WrenchSettings.from_parameters(
        dict(PARAMETER_DEFAULTS, state_timeout=1.0, diagnostics_period=1.0)
    )
    health = Health()
    assert health.state_age(10.0) is None and health.level(10.0, settings, 0)[0] == ERROR
    health.state_accepted(10.0)
    assert health.state_age(10.25) == 0.25
    assert health.level(10.25, settings, 0) == (OK, "ok")
    assert health.level(11.5, settings, 0) == (ERROR, "state is stale (1.5 s old)")
    health.rejected("bad_quaternion")
    assert health.last_rejection_reason == "bad_quaternion"
    latest = "1 inputs rejected so far (latest: bad_quaternion)"
    assert health.level(10.5, settings, 1) == (WARN, latest)
    health.rejected("stale_state")
    assert health.level(10.5, settings, 2)[0] == ERROR
    # a state refused for its frame, then attitudes refused for want of a state: the frame leads
    health.rejected("bad_state_frame")
    health.rejected("no_state")
    assert health.level(12.0, settings, 4) == (ERROR, "bad_state_frame: state is stale (2.0 s old)")
    health.state_accepted(12.0)  # a state taken: the cause goes
    assert health.level(14.0, settings, 4) == (ERROR, "state is stale (2.0 s old)")
    sample = object()
    health.sample_computed(0.002, sample)
    assert health.last_sample is sample and health.computed == 1
    assert health.compute_ms().tolist() == [2.0]


def test_integer_nanosecond_ticks_are_subtracted_exactly():
    health = Health(ticks_per_second=1_000_000_000)
    t = 1_767_225_600_123_456_789
    health.state_accepted(t)
    assert health.state_age(t + 1_500_000_001) == 1_500_000_001 / 1e9


def test_the_compute_window_keeps_the_latest_times():
    health = Health(window=5)
    assert health.compute_ms().size == 0
    for k in range(1, 13):
        health.sample_computed(k * 1e-3, None)
    assert sorted(health.compute_ms().tolist()) == pytest.approx([8.0, 9.0, 10.0, 11.0, 12.0])
    assert health.computed == 12 and isinstance(health.compute_ms(), np.ndarray)


def test_stamp_gaps_count_the_messages_missing_from_a_regular_stream():
    gaps = StampGaps()
    for k in [0, 1, 2, 3, 7, 8, 9, 10, 12, 13]:  # 4, 5, 6 and 11 missing
        gaps.stamp(1.0 + 0.01 * k)
    assert gaps.missing == 4 and gaps.interval == pytest.approx(0.01)
    gaps.stamp(1.13)  # a repeat and a stamp back in time are no gap
    gaps.stamp(1.05)
    gaps.stamp(float("nan"))
    gaps.stamp(float("inf"))
    assert gaps.missing == 4
    gaps.stamp(1.14)
    assert gaps.missing == 4
    faster = StampGaps()  # a faster stream is followed at once
    for t in [0.0, 0.01, 0.02, 0.03, 0.035, 0.04, 0.045]:
        faster.stamp(t)
    assert faster.missing == 0 and faster.interval == pytest.approx(0.005)
    slower = StampGaps()  # a slower one costs one count, then is followed
    for t in [0.0, 0.005, 0.01, 0.015, 0.025, 0.035, 0.045, 0.055]:
        slower.stamp(t)
    assert slower.missing == 1 and slower.interval == pytest.approx(0.01)


def test_sequence_gaps_count_the_numbers_a_single_publisher_skipped():
    gaps = SequenceGaps()
    for n in [41, 42, 43, 47, 48, 60]:  # the first number starts the count; 44-46, 49-59 lost
        gaps.number(n, lambda: True)
    assert gaps.counted == 14 and gaps.lost == 14
    gaps.number(3, lambda: True)  # a number back: the publisher restarted, a new count
    gaps.number(5, lambda: True)
    assert gaps.counted == 15
    gaps.restart()  # a publisher came or went
    gaps.number(900, lambda: True)
    assert gaps.counted == 15
    gaps.reported(4)  # the middleware saw some of the same losses: the larger count
    assert gaps.lost == 15 and gaps.middleware == 4
    gaps.reported(20)
    assert gaps.lost == 24


def test_sequence_gaps_count_nothing_while_several_publishers_interleave():
    asked = []

    def two():
        asked.append(1)
        return False

    gaps = SequenceGaps()
    for n in [500, 10, 501, 11, 502, 12, 520, 13]:  # two publishers, each skipping
        gaps.number(n, two)
    assert gaps.counted == 0 and asked
    gaps.number(14, lambda: True)  # one left: consecutive numbers ask nothing
    gaps.number(30, lambda: True)  # the first skip after several publishers is not counted
    assert gaps.counted == 0
    gaps.number(35, lambda: True)
    assert gaps.counted == 4
