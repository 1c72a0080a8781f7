"""AeroWrenchEstimator without ROS: flight conditions on knots, prepare, rejections, counters."""

from __future__ import annotations

import datetime as _dt
import math
from collections import deque
from types import SimpleNamespace as Time  # a builtin_interfaces/Time's two fields

import numpy as np
import pytest

from adbsat_ros.environment.knots import KNOTS_KEPT
from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS
from adbsat_ros.estimator.samples import Rejection
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.messages.stamps import next_regular_stamp, stamp_seconds

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


def conditions_numbers(conditions) -> dict:
    return conditions.as_dict()


def test_attitudes_at_one_stamp_share_the_knots_and_equal_a_fresh_estimator():
    """Two attitudes at one stamp and state (a simulator publishing attitude and state at every
    step): the second evaluates no flight conditions, gets the same ones, and its wrench is that
    of an estimator that never saw the first."""
    est = estimator()
    est.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    first = est.on_attitude(1.0, (0.0, 0.0, 0.0, 1.0))
    evaluations = est.knots.evaluations
    second = est.on_attitude(1.0, TILTED)
    assert est.knots.evaluations == evaluations  # nothing evaluated for the second
    assert conditions_numbers(second.conditions) == conditions_numbers(first.conditions)
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
    assert b.conditions.mass_density != a.conditions.mass_density
    assert b.conditions.position_eci[1] == pytest.approx(V * 0.05)
    np.testing.assert_array_equal(b.force, fresh_sample(1.05, 1.0, TILTED).force)
    est.on_state(1.05, [R, 0.0, 1e3], [0.0, V, 10.0])  # a new state at that very stamp
    evaluations = est.knots.evaluations
    c = est.on_attitude(1.05, TILTED)
    assert est.knots.evaluations == evaluations + 1  # the new state's own knot at 1.05 s
    assert c.conditions.position_eci[1] == 0.0  # the new state's position, not the propagated one
    np.testing.assert_array_equal(c.force, fresh_sample(1.05, 1.05, TILTED).force)


def test_a_settings_change_recomputes_the_conditions():
    est = estimator()
    est.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    quiet = est.on_attitude(1.0, TILTED)
    est.apply_settings(
        WrenchSettings.from_parameters(dict(est.settings.as_parameters(), f107=250.0, f107a=250.0))
    )
    active = est.on_attitude(1.0, TILTED)
    assert active.conditions.mass_density > 1.5 * quiet.conditions.mass_density
    np.testing.assert_array_equal(
        active.force, fresh_sample(1.0, 1.0, TILTED, f107=250.0, f107a=250.0).force
    )


@pytest.mark.parametrize("step", [0.01, 0.0])
def test_prepare_readies_that_stamp_only_and_changes_no_result(step):
    """prepare(stamp): with knots, the knots around the stamp are evaluated then; without
    (conditions_step 0), the exact conditions at the stamp. The attitude at that stamp evaluates
    nothing, its wrench is that of an estimator never prepared, and only an attitude at exactly
    that stamp counts as prepared."""
    est = estimator(conditions_step=step)
    assert not est.prepare(1.0)  # no state yet
    est.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    est.on_attitude(1.01, TILTED)
    assert not est.prepare(1.01)  # not after the latest attitude
    evaluations = est.knots.evaluations
    assert est.prepare(1.0125)
    assert est.knots.evaluations == evaluations + 1  # the knot at 1.02 s, or the stamp itself
    regular = est.on_attitude(1.0125, TILTED)
    assert est.knots.evaluations == evaluations + 1  # nothing evaluated for the message
    assert est.knots.prepared_used == 1
    reference = fresh_sample(1.0125, 1.0, TILTED, conditions_step=step)
    np.testing.assert_array_equal(regular.force, reference.force)
    np.testing.assert_array_equal(regular.torque, reference.torque)
    assert est.prepare(1.015)
    irregular = est.on_attitude(1.0143, TILTED)  # not the prepared stamp: computed as usual
    assert est.knots.prepared_used == 1
    np.testing.assert_array_equal(
        irregular.force, fresh_sample(1.0143, 1.0, TILTED, conditions_step=step).force
    )
    assert not est.prepare(2.5)  # beyond the state time-out
    assert sum(est.rejections.values()) == 0  # preparing counts nothing
    assert est.diagnostic_values(None, [])["conditions_prepared_used"] == 1


def test_prepare_evaluates_the_knot_after_next_so_that_the_next_interval_needs_none():
    """prepare() evaluates, when the prepared stamp needed no new knot, the knot two steps on:
    1 kHz attitudes crossing the knot at 1.01 s into [1.01, 1.02] then evaluate no NRLMSISE-00
    knot among them, where an estimator fed the same without prepare() must evaluate the knot at
    1.02 s on the way; the wrenches are the same bit for bit, since a knot depends on the state
    and its stamp only."""
    prepared, plain = estimator(), estimator()
    for est in (prepared, plain):
        est.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    for k in range(6):  # 1.000 .. 1.005, each followed by prepare of the next stamp (the node)
        stamp = 1.0 + 0.001 * k
        prepared.on_attitude(stamp, TILTED)
        plain.on_attitude(stamp, TILTED)
        assert prepared.prepare(stamp + 0.001)
    assert (prepared.knots.evaluations, plain.knots.evaluations) == (3, 2)  # 100, 101 (+102)
    queued = [1.006 + 0.001 * k for k in range(8)]  # 1.006 .. 1.013, served as they come
    before = prepared.knots.evaluations, plain.knots.evaluations
    for stamp in queued:
        a, b = prepared.on_attitude(stamp, TILTED), plain.on_attitude(stamp, TILTED)
        np.testing.assert_array_equal(a.force, b.force)
        np.testing.assert_array_equal(a.torque, b.torque)
    assert prepared.knots.evaluations == before[0]  # the knot at 1.02 s was ready
    assert plain.knots.evaluations == before[1] + 1  # evaluated among them
    assert prepared.prepare(1.014) and prepared.knots.evaluations == before[0] + 1  # 103 ahead


@pytest.mark.parametrize("period_ns", [10_000_000, 1_000_000, 3_333_333, 999_999_999])
@pytest.mark.parametrize("start_s", [0, 7, 1_700_000_000])
def test_next_regular_stamp_is_bit_equal_to_the_next_message_stamp(period_ns, start_s):
    stamps = [
        Time(
            sec=(start_s * 10**9 + k * period_ns) // 10**9,
            nanosec=(start_s * 10**9 + k * period_ns) % 10**9,
        )
        for k in range(300)
    ]
    for previous, latest, following in zip(stamps, stamps[1:], stamps[2:]):
        assert next_regular_stamp(previous, latest) == stamp_seconds(following)
    assert next_regular_stamp(stamps[1], stamps[1]) is None
    assert next_regular_stamp(stamps[2], stamps[1]) is None


def test_conditions_between_knots_are_interpolated_within_1e_9_of_the_exact_ones():
    """conditions_step 0.01 (the default): exact conditions at the stamps j 10 ms, linear
    in between; against conditions_step 0 (exact at every stamp) at 350 km, clear of NRLMSISE-00's
    300 km step. The wrench follows the conditions: rho, the speed ratio and alpha."""
    r = 6378137.0 + 350e3
    v = math.sqrt(3.986004418e14 / r)
    knots, exact = estimator(), estimator(conditions_step=0.0)
    for est in (knots, exact):
        est.on_state(10.0, [r, 0.0, 1e3], [0.0, v, 40.0])
    for stamp in (10.0, 10.0013, 10.0137, 10.0555, 10.09999, 9.9963):
        a = knots.on_attitude(stamp, TILTED)
        b = exact.on_attitude(stamp, TILTED)
        knots.reset(), exact.reset()
        for est in (knots, exact):
            est.on_state(10.0, [r, 0.0, 1e3], [0.0, v, 40.0])
        assert a.time == b.time
        assert a.conditions.mass_density == pytest.approx(b.conditions.mass_density, rel=1e-9)
        assert a.conditions.speed_ratio == pytest.approx(b.conditions.speed_ratio, rel=1e-10)
        np.testing.assert_allclose(a.force, b.force, rtol=2e-9)
        np.testing.assert_allclose(
            a.torque, b.torque, rtol=2e-9, atol=1e-9 * np.abs(b.torque).max()
        )
        np.testing.assert_allclose(
            a.conditions.position_eci, b.conditions.position_eci, rtol=0, atol=1e-6
        )


def test_interpolated_conditions_depend_on_the_stamp_and_state_only():
    """A stamp gets the same numbers whatever came before (live, or replayed from a bag in another
    order): the knots are fixed stamps, not set by the messages."""
    ordered, shuffled = estimator(), estimator()
    for est in (ordered, shuffled):
        est.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    for stamp in (1.001, 1.002, 1.0155, 1.03):
        ordered.on_attitude(stamp, TILTED)
    lone = shuffled.on_attitude(1.03, TILTED)
    last = ordered.on_attitude(1.0375, TILTED)
    shuffled.on_attitude(1.0375, (0.0, 0.0, 0.0, 1.0))
    again = shuffled.on_attitude(1.0375, TILTED)
    np.testing.assert_array_equal(again.force, last.force)
    np.testing.assert_array_equal(lone.force, fresh_sample(1.03, 1.0, TILTED).force)


def test_a_stamp_on_a_knot_needs_that_knot_only():
    est = estimator()
    est.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    on_knot = est.on_attitude(1.02, TILTED)  # 102 x 10 ms
    assert est.knots.knot_stamps == (pytest.approx(1.02),)  # no interpolation partner
    assert est.knots.evaluations == 1
    reference = fresh_sample(1.02, 1.0, TILTED, conditions_step=0.0)
    np.testing.assert_array_equal(on_knot.force, reference.force)


def test_a_knot_outside_the_atmosphere_falls_back_to_the_stamp_itself():
    """A knot 10 ms ahead may lie above 1000 km while the stamp does not: the stamp is then
    evaluated exactly instead of rejected."""
    top = 6378137.0 + 1000e3 - 20.0  # 20 m below the model's ceiling, climbing at 3 km/s
    knots, exact = estimator(), estimator(conditions_step=0.0)
    for est in (knots, exact):
        est.on_state(1.0, [top, 0.0, 0.0], [3000.0, 7000.0, 0.0])
    sample = knots.on_attitude(1.005, TILTED)  # 15 m higher: inside; the knot at 1.01 is 10 m out
    reference = exact.on_attitude(1.005, TILTED)
    np.testing.assert_array_equal(sample.force, reference.force)
    assert sample.conditions.mass_density == reference.conditions.mass_density
    assert sum(knots.rejections.values()) == 0
    with pytest.raises(Rejection) as above:  # and a stamp outside is rejected as before
        knots.on_attitude(1.02, TILTED)
    assert above.value.reason == "altitude_out_of_range"


@pytest.mark.parametrize("value", [-0.01, 0.2, float("nan"), "fast"])
def test_a_bad_conditions_step_is_refused_naming_it(value):
    with pytest.raises(ValueError, match="conditions_step"):
        WrenchSettings.from_parameters(dict(PARAMETER_DEFAULTS, conditions_step=value))


def test_compute_time_percentiles_are_nearest_rank_from_arrays_and_sequences():
    """p-th percentile = the ceil(p n)-th smallest (nearest rank): for 1..100 ms, 50, 99 and 100."""
    est = estimator()
    times = np.random.default_rng(3).permutation(np.arange(1.0, 101.0))
    for given in (times, deque(times.tolist(), maxlen=2000), times[:1]):
        values = est.diagnostic_values(None, given)
        expected = (50.0, 99.0, 100.0) if len(given) == 100 else (times[0],) * 3
        assert (
            values["compute_ms_p50"],
            values["compute_ms_p99"],
            values["compute_ms_max"],
        ) == expected
    assert "compute_ms_p50" not in est.diagnostic_values(None, np.zeros(0))
    np.testing.assert_array_equal(
        times, np.random.default_rng(3).permutation(np.arange(1.0, 101.0))
    )  # untouched


def test_unix_stamps_on_whole_steps_land_on_knots():
    """UNIX stamps as float seconds resolve 0.24 us: a 100 Hz stream stamped on whole 10 ms is on
    the knots (within KNOT_SNAP_S = 1 us), one exact evaluation per message as without knots,
    with the exact numbers to 1e-9; a stamp 5 ms off the grid is interpolated."""
    t0 = 1_767_225_600.0
    knots, exact = estimator(time_mode="unix"), estimator(time_mode="unix", conditions_step=0.0)
    for est in (knots, exact):
        est.on_state(t0, [R, 0.0, 1e3], [0.0, V, 10.0])
    for k in range(1, 10):
        stamp = (
            1_767_225_600_000_000_000 + k * 10_000_000
        ) * 1e-9  # as stamp_seconds() of a 10 ms stream
        a, b = knots.on_attitude(stamp, TILTED), exact.on_attitude(stamp, TILTED)
        assert len(knots.knots) == min(k, KNOTS_KEPT)  # a new knot per message, none beside it
        assert knots.knots.evaluations == k
        # the knot is evaluated at j x 10 ms, the exact path at the stamp itself: both the same
        # instant up to the float stamp's 0.24 us (2 mm of orbit)
        np.testing.assert_allclose(a.force, b.force, rtol=1e-9, atol=1e-9 * np.linalg.norm(b.force))
        assert a.conditions.time == b.conditions.time == a.time
    off = knots.on_attitude(t0 + 0.095, TILTED)  # between knots 9 and 10
    reference = exact.on_attitude(t0 + 0.095, TILTED).force
    np.testing.assert_allclose(
        off.force, reference, rtol=2e-9, atol=2e-9 * np.linalg.norm(reference)
    )
    assert len(knots.knots) == KNOTS_KEPT


def test_rejections_are_counted_by_reason_and_time_going_back_resets_the_history():
    """A NaN quaternion, a non-unit one, an attitude before any state, a stale state, a late
    attitude and time going back are each rejected with their reason and counted; the late one
    alone, while going back beyond time_jump_reset forgets the state (the next attitudes have
    none) until a new state comes, whose wrenches are those of a fresh estimator."""
    est = estimator(time_jump_reset=0.002)
    reasons = []

    def attitude(stamp, q=TILTED):
        try:
            return est.on_attitude(stamp, q)
        except Rejection as exc:
            reasons.append(exc.reason)
            return None

    attitude(0.9)
    est.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    assert attitude(1.001) is not None
    attitude(1.002, [math.nan, 0.0, 0.0, 1.0])
    attitude(1.003, [0.0, 0.0, 0.0, 2.0])
    attitude(2.5)  # 1.5 s after the state: stale
    assert attitude(1.004) is not None  # (a stale attitude is not a stamp seen)
    attitude(1.0035)  # 0.5 ms before the latest attitude: out of order, refused alone
    assert attitude(1.0041) is not None
    attitude(1.0015)  # 2.6 ms back, beyond time_jump_reset: back in time
    attitude(1.005)  # the history was reset: no state
    assert reasons == ["no_state", "non_finite", "bad_quaternion", "stale_state"] + [
        "out_of_order",
        "time_backwards",
        "no_state",
    ]
    assert est.state is None and est.published == 3
    assert est.rejections == {
        "no_state": 2,
        "non_finite": 1,
        "bad_quaternion": 1,
        "stale_state": 1,
        "out_of_order": 1,
        "time_backwards": 1,
    }
    est.on_state(1.006, [R, 0.0, 1e3], [0.0, V, 10.0])
    sample = attitude(1.007)
    np.testing.assert_array_equal(sample.force, fresh_sample(1.007, 1.006, TILTED).force)
    with pytest.raises(Rejection) as back:  # a state back in time: history reset, state kept
        est.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    assert back.value.reason == "time_backwards" and est.state.stamp == 1.0
    assert est.rejections["time_backwards"] == 2
    values = est.diagnostic_values(None, [])
    assert values["rejected_time_backwards"] == 2 and values["published"] == 4
    assert values["rejected_out_of_order"] == 1
    assert values["conditions_evaluations"] == est.knots.evaluations > 0
    assert values["conditions_knot_hits"] + values["conditions_knot_misses"] > 0


def test_settings_change_keeps_the_knot_counters_and_evaluates_new_knots():
    est = estimator()
    est.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    est.on_attitude(1.0013, TILTED)
    evaluations = est.knots.evaluations
    est.apply_settings(
        WrenchSettings.from_parameters(dict(est.settings.as_parameters(), f107=250.0))
    )
    assert est.knots.evaluations == evaluations and len(est.knots) == 0
    active = est.on_attitude(1.0014, TILTED)
    assert est.knots.evaluations == evaluations + 2
    np.testing.assert_array_equal(active.force, fresh_sample(1.0014, 1.0, TILTED, f107=250.0).force)


def test_a_stamp_that_is_no_utc_time_is_a_counted_rejection():
    """A UNIX stamp beyond the year 9999 has no UTC time: the state is rejected as bad_state and
    counted, not raised as another error; an attitude past the model's last year (2100) after a
    state just before it is rejected as bad_state too."""
    est = estimator(time_mode="unix")
    with pytest.raises(Rejection) as caught:
        est.on_state(1e12, [R, 0.0, 1e3], [0.0, V, 10.0])
    assert caught.value.reason == "bad_state" and "1000000000000.0" in caught.value.message
    assert est.rejections == {"bad_state": 1} and est.state is None
    end = _dt.datetime(2101, 1, 1, tzinfo=_dt.timezone.utc).timestamp()
    est.on_state(end - 0.5, [R, 0.0, 1e3], [0.0, V, 10.0])
    with pytest.raises(Rejection) as caught:
        est.on_attitude(end + 0.01, [0.0, 0.0, 0.0, 1.0])
    assert caught.value.reason == "bad_state" and "2101-01-01" in caught.value.message
    assert est.rejections == {"bad_state": 2}
