"""A bounded min/max envelope of long time series for plotting: per time bin, each series' extremes
and their times (a one-sample spike stays visible); bins double in width when outrun.
"""

from __future__ import annotations

import array

import numpy as np

#: Bins at most; between half and all of them are in use once the samples span many widths
#: (the figures are about 700 pixels wide).
BINS = 2048


class MinMaxEnvelope:
    """Samples of ``columns`` series in at most ``bins`` bins; non-finite values left out."""

    def __init__(self, columns: int, bins: int = BINS, width: float = 1e-3, buffer: int = 4096):
        if columns < 1 or bins < 2 or not width > 0 or buffer < 1:
            raise ValueError(
                f"columns {columns}, bins {bins}, width {width}, buffer {buffer}: expected "
                "columns >= 1, bins >= 2, width > 0, buffer >= 1"
            )
        self.columns, self.bins, self.width = int(columns), int(bins), float(width)
        self.origin = None  # the time of the first sample: bin k holds [origin + k w, + w)
        self._binned = 0  # samples binned
        self._lo = self._hi = 0  # the bins in use, [lo, hi], by index from the origin
        self._buffer = int(buffer)
        self._times, self._values = array.array("d"), array.array("d")
        self._reset()

    def _reset(self) -> None:
        shape = (self.bins, self.columns)
        self._rows = np.zeros(self.bins, dtype=np.int64)
        self._min, self._max = np.full(shape, np.inf), np.full(shape, -np.inf)
        self._t_min, self._t_max = np.full(shape, np.nan), np.full(shape, np.nan)

    def __len__(self) -> int:
        """Samples taken."""
        return self._binned + len(self._times)

    def add(self, time: float, values) -> None:
        """One sample: its time and one value per series."""
        self._times.append(time)
        self._values.extend(values)
        if len(self._times) == self._buffer:
            self.flush()

    def flush(self) -> None:
        """Bin the samples taken so far (done by :meth:`add` when its buffer is full)."""
        n = len(self._times)
        if n == 0:
            return
        if len(self._values) != n * self.columns:
            raise ValueError(f"each sample needs {self.columns} values")
        t = np.array(self._times, dtype=float)
        v = np.array(self._values, dtype=float).reshape(n, self.columns)
        del self._times[:], self._values[:]
        if self.origin is None:
            self.origin = float(t[0])
        k = np.floor((t - self.origin) / self.width).astype(np.int64)
        lo, hi = int(k.min()), int(k.max())
        if self._binned:
            lo, hi = min(lo, self._lo), max(hi, self._hi)
        shift = 0
        while (hi >> shift) - (lo >> shift) >= self.bins:
            shift += 1
        if self._binned and (shift or lo != self._lo):
            self._rebin(shift, lo >> shift)
        self._lo, self._hi = lo >> shift, hi >> shift
        self.width *= 2**shift
        column = t[:, None]
        self._merge((k >> shift) - self._lo, np.ones(n, dtype=np.int64), v, column, v, column)
        self._binned += n

    def _rebin(self, shift: int, lo: int) -> None:
        """Move the bins to ``2**shift`` times their width, the first in use at index ``lo``."""
        used = slice(0, self._hi - self._lo + 1)
        old = (self._rows[used], self._min[used], self._t_min[used])
        old += (self._max[used], self._t_max[used])
        index = ((self._lo + np.arange(len(old[0]))) >> shift) - lo
        self._reset()
        keep = old[0] > 0
        self._merge(index[keep], *(a[keep] for a in old))

    def _merge(self, index, rows, low, t_low, high, t_high) -> None:
        """Take candidates into the bins ``index``."""
        order = np.argsort(index, kind="stable")
        index = index[order]
        starts = np.flatnonzero(np.r_[True, index[1:] != index[:-1]])
        bins = index[starts]
        self._rows[bins] += np.add.reduceat(rows[order], starts)
        segment = np.repeat(np.arange(len(starts)), np.diff(np.r_[starts, len(index)]))
        for values, times, best, best_t, ufunc, none in (
            (low, t_low, self._min, self._t_min, np.minimum, np.inf),
            (high, t_high, self._max, self._t_max, np.maximum, -np.inf),
        ):
            values = values[order]
            values = np.where(np.isfinite(values), values, none)
            found = ufunc.reduceat(values, starts, axis=0)
            # the earliest time at which a bin's extreme came
            times = np.broadcast_to(times, (len(order), self.columns))[order]
            times = np.where(values == found[segment], times, np.inf)
            found_t = np.minimum.reduceat(times, starts, axis=0)
            better = ufunc(found, best[bins]) != best[bins]
            rows_, cols = np.nonzero(better)
            best[bins[rows_], cols] = found[rows_, cols]
            best_t[bins[rows_], cols] = found_t[rows_, cols]

    def summary(self):
        """Per bin in use: start time, each series' min and max with times (bins, columns)."""
        self.flush()
        if not self._binned:
            none = np.empty((0, self.columns))
            return np.empty(0), none, none, none, none
        used = np.nonzero(self._rows[: self._hi - self._lo + 1])[0]
        start = self.origin + (self._lo + used) * self.width
        return start, self._min[used], self._t_min[used], self._max[used], self._t_max[used]

    def series(self, column: int) -> tuple[np.ndarray, np.ndarray]:
        """Times and values of series ``column`` (bin minima and maxima), NaN in gaps."""
        start, *bins = self.summary()
        low, t_low, high, t_high = (a[:, column] for a in bins)
        finite = np.isfinite(low)
        low_first = t_low <= t_high
        x = np.stack([np.where(low_first, t_low, t_high), np.where(low_first, t_high, t_low)], 1)
        y = np.stack([np.where(low_first, low, high), np.where(low_first, high, low)], 1)
        x[~finite, 0] = start[~finite] + 0.5 * self.width
        y[~finite, 0] = np.nan
        keep = np.ones(x.shape, dtype=bool)
        keep[:, 1] = finite & (t_low != t_high)
        return x[keep], y[keep]
