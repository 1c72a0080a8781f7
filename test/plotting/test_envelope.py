"""The min/max envelope bag analysis draws its plots from: bounded whatever the flight's length,
holding every bin's exact extremes (spikes kept), exact where bins hold one or two samples."""

import numpy as np
import pytest

from adbsat_ros.plotting import figures as figures_module
from adbsat_ros.plotting import time_series
from adbsat_ros.plotting.envelope import BINS, MinMaxEnvelope


def filled(times, values, **options):
    envelope = MinMaxEnvelope(values.shape[1], **options)
    for t, row in zip(times.tolist(), values.tolist()):
        envelope.add(t, row)
    return envelope


def noisy_flight(n, rng, period=0.01):
    """n samples of three series 10 ms apart: a slow wave with noise, noise with NaN gaps and
    one spike, a constant; a few samples out of order."""
    t = np.arange(n) * period
    swap = rng.choice(n - 1, size=max(n // 1000, 1), replace=False)
    t[swap], t[swap + 1] = t[swap + 1].copy(), t[swap].copy()
    values = np.stack(
        [np.sin(t / 50) + 0.05 * rng.standard_normal(n), rng.standard_normal(n), np.ones(n)], 1
    )
    values[n // 3, 1] = 40.0  # a spike
    values[n // 2 : n // 2 + n // 50, 1] = np.nan  # no samples here
    values[7, 0] = np.inf  # never a value to plot
    return t, values


def bin_of(envelope, t):
    start = envelope.summary()[0]
    return np.searchsorted(start, t, side="right") - 1, start


@pytest.mark.parametrize("n", [3_000, 200_000])
def test_every_bin_holds_its_samples_exact_min_and_max(n):
    rng = np.random.default_rng(n)
    t, values = noisy_flight(n, rng)
    envelope = filled(t, values)
    assert len(envelope) == n
    start, low, t_low, high, t_high = envelope.summary()
    k, _ = bin_of(envelope, t)
    assert np.all(k >= 0) and np.all(t < start[k] + envelope.width)  # every sample in a bin
    for c in range(values.shape[1]):
        v = values[:, c]
        ok = np.isfinite(v)
        want_low = np.full(len(start), np.inf)
        want_high = np.full(len(start), -np.inf)
        np.minimum.at(want_low, k[ok], v[ok])
        np.maximum.at(want_high, k[ok], v[ok])
        np.testing.assert_array_equal(low[:, c], want_low)
        np.testing.assert_array_equal(high[:, c], want_high)
        has = np.isfinite(low[:, c])
        # each extreme's time is that of a sample with that value, in that bin
        for b in np.flatnonzero(has)[:: max(len(start) // 200, 1)]:
            for value, when in ((low[b, c], t_low[b, c]), (high[b, c], t_high[b, c])):
                assert np.any((t == when) & (v == value) & (k == b))
    # the spike is in the plotted line, the gap is a gap
    x, y = envelope.series(1)
    assert np.nanmax(y) == 40.0 and np.isnan(y).any()
    x, y = envelope.series(0)
    assert np.all(np.diff(x) >= 0)  # in time order, bin by bin


def test_the_summary_is_bounded_by_the_bins_whatever_the_flight():
    rng = np.random.default_rng(1)
    lengths = []
    for n in (20_000, 400_000):
        t, values = noisy_flight(n, rng)
        envelope = filled(t, values)
        start = envelope.summary()[0]
        assert BINS // 2 <= len(start) <= BINS
        for c in range(values.shape[1]):
            x, y = envelope.series(c)
            assert len(x) == len(y) <= 2 * BINS
        lengths.append(len(envelope.series(0)[0]))
        # what it holds does not grow with the flight: the bins, and a buffer of samples
        held = [a.nbytes for a in vars(envelope).values() if isinstance(a, np.ndarray)]
        assert sum(held) <= BINS * values.shape[1] * 4 * 8 + BINS * 8
    assert lengths[1] <= 2 * BINS and lengths[0] <= 2 * BINS


def test_few_samples_are_kept_exactly():
    """While the bins are finer than the samples, the line is the samples themselves."""
    rng = np.random.default_rng(2)
    t = np.arange(500) * 0.06 + rng.uniform(0, 0.01, 500)  # 30 s: bins of 16 ms
    values = rng.standard_normal((500, 2))
    values[100:110, 1] = np.nan
    envelope = filled(t, values, width=1e-3)
    x, y = envelope.series(0)
    np.testing.assert_array_equal(x, t)
    np.testing.assert_array_equal(y, values[:, 0])
    x, y = envelope.series(1)
    finite = np.isfinite(y)
    np.testing.assert_array_equal(y[finite], values[np.isfinite(values[:, 1]), 1])
    assert np.isnan(y).sum() == 10


def test_samples_before_the_first_and_far_after_it():
    """Times going back before the first sample, and a jump far ahead: still every extreme."""
    t = np.array([100.0, 101.0, 50.0, 102.0, 1e6, 103.0])
    values = np.array([[1.0], [5.0], [-3.0], [2.0], [7.0], [0.5]])
    envelope = filled(t, values, bins=4, buffer=2)
    start, low, _, high, _ = envelope.summary()
    assert len(start) <= 4
    assert low.min() == -3.0 and high.max() == 7.0
    x, y = envelope.series(0)
    assert {-3.0, 7.0} <= set(y.tolist())


def test_line_figures_from_an_envelope_are_bounded(tmp_path):
    """The figures bag analysis draws: every line at most two points a bin, however long the
    flight, and time in hours for a long one."""
    rng = np.random.default_rng(3)
    n = 100_000
    t = np.arange(n) * 0.2  # 5.5 h
    values = rng.standard_normal((n, 8))
    envelope = filled(t, values)
    series = [envelope.series(j) for j in range(8)]
    lines = {
        "m": {
            "force": series[0:3],
            "torque": series[3:6],
            "density": [(series[6][0], np.abs(series[6][1]))],
            "drag_coefficient": series[7:8],
        }
    }
    figures = time_series.make_line_figures(lines)
    for figure in figures.values():
        for ax in figure.axes:
            for line in ax.get_lines():
                assert len(line.get_xdata()) <= 2 * BINS
    assert "[h]" in figures["force"].axes[-1].get_xlabel()
    paths = figures_module.save_figures(figures, tmp_path)
    assert [p.name for p in paths] == [
        "force.png",
        "torque.png",
        "density.png",
        "drag_coefficient.png",
    ]


def test_bad_arguments():
    with pytest.raises(ValueError, match="columns 0"):
        MinMaxEnvelope(0)
    envelope = MinMaxEnvelope(2)
    envelope.add(0.0, [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="each sample needs 2 values"):
        envelope.flush()
