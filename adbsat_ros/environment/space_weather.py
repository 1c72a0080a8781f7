"""Space-weather sources: the indices NRLMSISE-00 and NRLMSIS 2.x take at a UTC time.

``fixed``: one :class:`~.atmosphere.SpaceWeather` for every time (its ``at`` returns itself).
``historical``: :class:`HistoricalWeather`, CelesTrak's record as the ``spaceweather`` package
reads it (the copy in its wheel, or a file named). Conventions, sources and the rule for times
outside the record: docs/physics.md, section 5.2.
"""

from __future__ import annotations

import datetime as _dt
import functools
import warnings

import numpy as np

from adbsat_ros.environment.atmosphere import SpaceWeather
from adbsat_ros.environment.time_scales import utc_datetime

#: The names of the space-weather sources.
SPACE_WEATHER_SOURCES = ("fixed", "historical")
#: Days of record a stamp needs before its own: the previous day's F10.7 and 57 h of ap.
_DAYS_BEFORE = 3
#: A daily F10.7 above this is a solar radio burst, taken as the 81-day average (as pymsis does).
_BURST_SFU = 400.0
_AP_COLUMNS = [f"Ap{h}" for h in range(0, 24, 3)]


@functools.cache
def _shipped_record() -> dict:
    """The record in the ``spaceweather`` package, read on first use (it does not change)."""
    return _record("")


def _record(path: str) -> dict:
    """The daily rows of a record as arrays (``path`` "" for the copy in ``spaceweather``)."""
    import spaceweather

    try:
        with warnings.catch_warnings():  # (the range is said by ours; a bad file by the error)
            warnings.filterwarnings("ignore", message="Local data files are older")
            warnings.filterwarnings("ignore", message="genfromtxt: Empty input")
            table = spaceweather.read_sw(path) if path else spaceweather.sw_daily(update=False)
    except (OSError, ValueError, IndexError) as exc:
        raise ValueError(f"space_weather_file {path!r}: not a CelesTrak SW file ({exc})") from None
    days = table.index.values.astype("datetime64[D]")
    gaps = np.flatnonzero(np.diff(days) != np.timedelta64(1, "D"))  # the monthly predictions
    rows = slice(0, gaps[0] + 1 if gaps.size else len(days))
    table, days = table.iloc[rows], days[rows]
    ap = table[_AP_COLUMNS].to_numpy(dtype=float)
    observed = np.flatnonzero((table["Q"].to_numpy() >= 0) & (ap.min(axis=1) >= 0))
    if observed.size < _DAYS_BEFORE + 1:
        raise ValueError(f"space_weather_file {path!r}: no observed days")
    f107 = table["f107_obs"].to_numpy(dtype=float)
    f107a = table["f107_81ctr_obs"].to_numpy(dtype=float)
    f107 = np.where((f107 > 0.0) & (f107 <= _BURST_SFU), f107, f107a)
    return {
        "first": days[0].astype(_dt.date),
        "observed_last": int(observed[-1]),
        "f107": f107,
        "f107a": f107a,
        "Ap": table["Apavg"].to_numpy(dtype=float),
        "ap": ap.ravel(),
        "path": path or "the record in the spaceweather package",
    }


class HistoricalWeather:
    """The indices at a UTC time from a CelesTrak SW record (``path``, or "" for the copy in
    ``spaceweather``), NRLMSISE-00's definitions; ``history`` False: daily Ap only (switch 9 = 1).
    ``at(time)``: a SpaceWeather; ValueError naming the time and the record's range outside it, a
    warning naming the prediction in its predicted days.
    """

    def __init__(self, path: str = "", history: bool = True):
        record = _record(str(path)) if path else _shipped_record()
        self.path = record["path"]
        self.history = bool(history)
        self._record = record
        self._first = record["first"].toordinal()
        last = len(record["Ap"]) - 1
        first = record["first"]
        self.usable = (first + _dt.timedelta(days=_DAYS_BEFORE), first + _dt.timedelta(days=last))
        self.observed_last = first + _dt.timedelta(days=record["observed_last"])

    def __repr__(self) -> str:
        return f"HistoricalWeather({self.path!r}, history={self.history})"

    @property
    def range_text(self) -> str:
        """The dates the record serves, in words."""
        start, end = self.usable
        return (
            f"{start.isoformat()} to {self.observed_last.isoformat()} observed, "
            f"predicted to {end.isoformat()} ({self.path})"
        )

    def at(self, time) -> SpaceWeather:
        """The indices in force at UTC ``time``."""
        time = utc_datetime(time)
        k = (time.toordinal() - self._first) * 8 + time.hour // 3  # the 3-hour bin
        day = k // 8
        date = time.date()
        if not self.usable[0] <= date <= self.usable[1]:
            raise ValueError(
                f"time {time.isoformat()} is outside the space-weather record: {self.range_text}"
            )
        if date > self.observed_last:
            warnings.warn(
                f"space weather of {date.isoformat()} is the record's prediction, not an "
                f"observation (observed to {self.observed_last.isoformat()})",
                stacklevel=2,
            )
        r = self._record
        history = None
        if self.history:
            ap = r["ap"][k - 19 : k + 1].tolist()  # 57 h before the bin to the bin
            history = (float(r["Ap"][day]), *ap[:-5:-1], sum(ap[8:16]) / 8, sum(ap[:8]) / 8)
        return SpaceWeather(r["f107"][day - 1], r["f107a"][day], r["Ap"][day], history)


def weather_source(name: str, fixed: SpaceWeather, path: str = "", history: bool = True):
    """The source ``name`` (``fixed``: ``fixed`` itself; ``historical``: the record at ``path``,
    or the copy in ``spaceweather``); ValueError naming an unknown name."""
    if name == "fixed":
        return fixed
    if name == "historical":
        return HistoricalWeather(path, history)
    raise ValueError(
        f"space_weather must be one of {', '.join(SPACE_WEATHER_SOURCES)}, got {name!r}"
    )
