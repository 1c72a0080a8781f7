"""Message stamps to UTC: ``time_mode`` ``unix`` reads a stamp as UNIX time [s] (leap seconds not
counted, as ROS clocks), ``epoch`` as seconds since ``epoch_utc`` (a simulation clock)."""

from __future__ import annotations

import datetime as _dt


def stamp_utc(stamp: float, time_mode: str, epoch_utc: _dt.datetime) -> _dt.datetime:
    """The aware UTC instant (microsecond resolution) of a finite stamp [s]; ValueError for another
    ``time_mode``."""
    if time_mode == "unix":
        return _dt.datetime.fromtimestamp(stamp, tz=_dt.timezone.utc)
    if time_mode == "epoch":
        return epoch_utc + _dt.timedelta(seconds=stamp)
    raise ValueError(f"time_mode must be unix or epoch, got {time_mode!r}")
