"""AeroWrenchEstimator without ROS: reuse of flight conditions between attitudes at one stamp."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.samples import Rejection, WrenchSample
from adbsat_ros.estimator.settings import PARAMETER_DEFAULTS, WrenchSettings

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
    """prepare(stamp): with knots, the knots around the stamp are evaluated then, and the attitude
    at that stamp evaluates none; without (conditions_step 0), its exact conditions are computed
    then and taken by the attitude. Either way the wrench is that of an estimator never prepared,
    and only an attitude at exactly that stamp counts as prepared."""
    est = estimator(conditions_step=step)
    assert not est.prepare(1.0)  # no state yet
    est.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    est.on_attitude(1.01, TILTED)
    assert not est.prepare(1.01)  # not after the latest attitude
    knots = est.knots_evaluated
    assert est.prepare(1.0125)
    assert est.knots_evaluated == knots + (1 if step else 0)  # the knot at 1.02 s
    ready = est._conditions_memo[-1]
    regular = est.on_attitude(1.0125, TILTED)
    assert est.knots_evaluated == knots + (1 if step else 0)  # nothing evaluated for the message
    assert est.prepared_used == 1
    if not step:
        assert regular.conditions is ready.conditions  # taken from the prepared conditions
    reference = fresh_sample(1.0125, 1.0, TILTED, conditions_step=step)
    np.testing.assert_array_equal(regular.force, reference.force)
    np.testing.assert_array_equal(regular.torque, reference.torque)
    assert est.prepare(1.015)
    irregular = est.on_attitude(1.0143, TILTED)  # not the prepared stamp: computed as usual
    assert est.prepared_used == 1
    np.testing.assert_array_equal(
        irregular.force, fresh_sample(1.0143, 1.0, TILTED, conditions_step=step).force
    )
    assert not est.prepare(2.5)  # beyond the state time-out
    assert sum(est.rejections.values()) == 0  # preparing counts nothing


def test_prepare_evaluates_the_knot_after_next_so_that_a_burst_into_the_next_interval_needs_none():
    """prepare() evaluates, when the prepared stamp needed no new knot, the knot two steps on: a
    burst of 1 kHz attitudes crossing the knot at 1.01 s into [1.01, 1.02] then evaluates no
    NRLMSISE-00 knot among its messages, where an estimator fed the same without prepare() must
    evaluate the knot at 1.02 s in the burst; the wrenches are the same bit for bit, since a knot
    depends on the state and its stamp only."""
    prepared, plain = estimator(), estimator()
    for est in (prepared, plain):
        est.on_state(1.0, [R, 0.0, 1e3], [0.0, V, 10.0])
    for k in range(
        6
    ):  # 1.000 .. 1.005, each followed by prepare of the next stamp, as the node does
        stamp = 1.0 + 0.001 * k
        prepared.on_attitude(stamp, TILTED)
        plain.on_attitude(stamp, TILTED)
        assert prepared.prepare(stamp + 0.001)
    assert (
        prepared.knots_evaluated == 3 and plain.knots_evaluated == 2
    )  # knots 100, 101 (+102 ahead)
    burst = [(1.006 + 0.001 * k, TILTED) for k in range(8)]  # 1.006 .. 1.013
    before = prepared.knots_evaluated, plain.knots_evaluated
    together, reference = prepared.on_attitudes(burst), plain.on_attitudes(burst)
    assert prepared.knots_evaluated == before[0]  # the knot at 1.02 s was ready
    assert plain.knots_evaluated == before[1] + 1  # evaluated among the burst
    for a, b in zip(together, reference):
        np.testing.assert_array_equal(a.force, b.force)
        np.testing.assert_array_equal(a.torque, b.torque)
    assert (
        prepared.prepare(1.014) and prepared.knots_evaluated == before[0] + 1
    )  # the next one ahead: 103


@pytest.mark.parametrize("period_ns", [10_000_000, 1_000_000, 3_333_333, 999_999_999])
@pytest.mark.parametrize("start_s", [0, 7, 1_700_000_000])
def test_next_regular_stamp_is_bit_equal_to_the_next_message_stamp(period_ns, start_s):
    from types import SimpleNamespace as Time  # a builtin_interfaces/Time's two fields

    from adbsat_ros.messages.stamps import next_regular_stamp, stamp_seconds

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
    assert list(est._knots[2]) == [102]  # one exact evaluation, no interpolation partner
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
    from collections import deque

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
    the knots (within KNOT_SNAP_S), one exact evaluation per message as without knots, with the
    exact numbers to 1e-9; a stamp 5 ms off the grid is interpolated."""
    t0 = 1_767_225_600.0
    knots, exact = estimator(time_mode="unix"), estimator(time_mode="unix", conditions_step=0.0)
    for est in (knots, exact):
        est.on_state(t0, [R, 0.0, 1e3], [0.0, V, 10.0])
    for k in range(1, 10):
        stamp = (
            1_767_225_600_000_000_000 + k * 10_000_000
        ) * 1e-9  # as stamp_seconds() of a 10 ms stream
        a, b = knots.on_attitude(stamp, TILTED), exact.on_attitude(stamp, TILTED)
        assert len(knots._knots[2]) == min(k, 4)  # a new knot per message, none beside it
        # the knot is evaluated at j x 10 ms, the exact path at the stamp itself: both the same
        # instant up to the float stamp's 0.24 us (2 mm of orbit)
        np.testing.assert_allclose(a.force, b.force, rtol=1e-9, atol=1e-9 * np.linalg.norm(b.force))
        assert a.conditions.time == b.conditions.time == a.time
    off = knots.on_attitude(t0 + 0.095, TILTED)  # between knots 9 and 10
    reference = exact.on_attitude(t0 + 0.095, TILTED).force
    np.testing.assert_allclose(
        off.force, reference, rtol=2e-9, atol=2e-9 * np.linalg.norm(reference)
    )
    assert len(knots._knots[2]) == 4


def _wrench_fields(result):
    """What a message's result publishes, for exact comparison (a Rejection by its reason)."""
    if isinstance(result, Rejection):
        return ("rejected", result.reason)
    return (
        "wrench",
        result.stamp,
        result.force.tolist(),
        result.torque.tolist(),
        result.force_coefficients.tolist(),
        result.moment_coefficients.tolist(),
        result.shading_cache_hit,
    )


@pytest.mark.parametrize(
    "overrides, stacked",
    [
        (dict(shading="raycast"), True),  # sentman, facets, cached shading
        (
            dict(shading="raycast", accommodation_model="sesam", gsi_model="maxwell"),
            True,
        ),  # alpha per stamp
        (dict(gsi_model="schaaf", conditions_step=0.0), True),
        (dict(gsi_model="cll"), False),  # a species model: one coefficients call per message
    ],
)
def test_attitudes_taken_together_give_each_message_its_own_result_bit_for_bit(overrides, stacked):
    """on_attitudes over bursts equals on_attitude message by message: samples, rejections
    (a NaN, a non-unit quaternion, time going back, which resets the state) and counters."""
    rng = np.random.default_rng(7)
    messages = []
    for k in range(60):
        angle = 0.3 * math.sin(0.1 * k) + 0.01 * k
        q = [0.0, math.sin(angle / 2), 0.05 * rng.standard_normal(), math.cos(angle / 2)]
        norm = math.sqrt(sum(v * v for v in q))
        messages.append((1.0 + 0.001 * k, [v / norm for v in q]))
    messages[7] = (messages[7][0], [math.nan, 0.0, 0.0, 1.0])
    messages[19] = (messages[19][0], [0.0, 0.0, 0.0, 2.0])
    messages[41] = (
        1.0,
        messages[41][1],
    )  # back in time: history reset, the next ones have no state
    states = {0: 1.0, 30: 1.03, 50: 1.05}  # message index -> state stamp, given before that message

    def state(est, stamp):
        est.on_state(stamp, [R, 1e3 * stamp, 1e3], [0.0, V, 10.0 + stamp])

    one_by_one, together = estimator(**overrides), estimator(**overrides)
    single_calls = []
    single = together.method.coefficients  # one direction's panel method
    together.method.coefficients = lambda *a, **kw: single_calls.append(1) or single(*a, **kw)
    expected = []
    for k, (stamp, q) in enumerate(messages):
        if k in states:
            state(one_by_one, states[k])
        try:
            expected.append(one_by_one.on_attitude(stamp, q))
        except Rejection as exc:
            expected.append(exc)
    got, k = [], 0
    sizes = iter(rng.integers(1, 9, size=len(messages)))
    while k < len(messages):
        if k in states:
            state(together, states[k])
        end = min(len(messages), k + int(next(sizes)), *(i for i in states if i > k))
        got.extend(together.on_attitudes(messages[k:end]))
        k = end
    assert [_wrench_fields(r) for r in got] == [_wrench_fields(r) for r in expected]
    assert together.rejections == one_by_one.rejections
    assert (
        together.published
        == one_by_one.published
        == sum(isinstance(r, Rejection) is False for r in expected)
    )
    assert {r.reason for r in expected if isinstance(r, Rejection)} == {
        "non_finite",
        "bad_quaternion",
        "time_backwards",
        "no_state",
    }
    assert sum(isinstance(r, Rejection) for r in expected) < 20  # most messages made wrenches
    assert len(single_calls) == together.published  # the panel method once per message


def test_fast_sample_construction_is_the_dataclass():
    """WrenchSample._made (the per-message path) gives what WrenchSample(...) gives: every field,
    in order, and a frozen object."""
    import dataclasses

    values = [object() for _ in dataclasses.fields(WrenchSample)]
    made, built = WrenchSample._made(*values), WrenchSample(*values)
    for field in dataclasses.fields(WrenchSample):
        assert getattr(made, field.name) is getattr(built, field.name)
    assert type(made) is WrenchSample
    with pytest.raises(dataclasses.FrozenInstanceError):
        made.stamp = 0.0
