"""Message stamps to UTC: how the estimator reads a header stamp as an instant.

``time_mode`` ``unix``: the stamp is UNIX time [s] (seconds since 1970-01-01T00:00:00 UTC, leap
seconds not counted, as ROS clocks and ``datetime.fromtimestamp`` count them). ``epoch``: the
stamp is seconds since ``epoch_utc`` (a simulation clock starting at 0).
"""

from __future__ import annotations

import datetime as _dt


def stamp_utc(stamp: float, time_mode: str, epoch_utc: _dt.datetime) -> _dt.datetime:
    """The UTC instant of a message stamp.

    Parameters
    ----------
    stamp : float
        Message stamp [s], finite.
    time_mode : {"unix", "epoch"}
        How the stamp is read (module notes).
    epoch_utc : datetime.datetime
        UTC of stamp 0 for ``epoch`` (aware, UTC); unused for ``unix``.

    Returns
    -------
    datetime.datetime
        Timezone-aware UTC instant (microsecond resolution).

    Raises
    ------
    ValueError
        For a time mode other than unix and epoch.
    """
    if time_mode == "unix":
        return _dt.datetime.fromtimestamp(stamp, tz=_dt.timezone.utc)
    if time_mode == "epoch":
        return epoch_utc + _dt.timedelta(seconds=stamp)
    raise ValueError(f"time_mode must be unix or epoch, got {time_mode!r}")
