"""UTC instants as the Earth-orientation and atmosphere models take them.

Naive UTC datetimes, two-part Julian dates (UTC, TT, UT1) through ERFA's leap-second table, day
of year and seconds of day; a day's constants are cached by :func:`utc_day` (``lru_cache``).
"""

from __future__ import annotations

import datetime as _dt
import functools
import warnings

import erfa

_MJD_ZERO_ORDINAL = _dt.date(1858, 11, 17).toordinal()  # proleptic ordinal of MJD 0
_MJD_TO_JD = 2400000.5
_TT_MINUS_TAI = 32.184  # [s]
#: Seconds in a day of 86400 SI seconds (Julian dates count such days).
SECONDS_PER_DAY = 86400.0


_UTC = _dt.timezone.utc


# ------------------------------------------------------------------------------------------ time
def utc_datetime(time) -> _dt.datetime:
    """Return ``time`` as a naive :class:`datetime.datetime` in UTC.

    An aware ``time`` is converted to UTC, a naive one is taken to be UTC; ValueError for
    anything but a :class:`datetime.datetime` (a plain ``date`` is refused too).
    """
    if not isinstance(time, _dt.datetime):
        raise ValueError(
            f"time must be a datetime.datetime (timezone-aware, or naive meaning UTC), "
            f"got {type(time).__name__} {time!r}"
        )
    if time.tzinfo is _UTC:
        time = time.replace(tzinfo=None)
    elif time.tzinfo is not None and time.utcoffset() is not None:
        time = time.astimezone(_UTC).replace(tzinfo=None)
    elif time.tzinfo is not None:
        time = time.replace(tzinfo=None)
    return time


@functools.lru_cache(maxsize=512)
def _tai_minus_utc(year: int, month: int, day: int) -> float:
    """TAI - UTC [s] on the given UTC day, from ERFA's table (0 before 1960, as ERFA)."""
    with warnings.catch_warnings():
        # ERFA flags years before 1960 or well past its table as "dubious"; the value it returns
        # (the last known offset) is what we want, and only TT depends on it.
        warnings.simplefilter("ignore", erfa.ErfaWarning)
        return float(erfa.dat(year, month, day, 0.5))


def julian_dates(time, ut1_minus_utc: float = 0.0):
    """Two-part Julian dates ``(utc, tt, ut1)`` of a UTC datetime, each (integer-and-a-half
    day, day fraction) as ERFA expects, with ``ut1_minus_utc`` [s] (IERS DUT1)."""
    time = utc_datetime(time)
    jd1, tt_offset, _ = utc_day(time.year, time.month, time.day)
    day_fraction = seconds_of_day(time) / SECONDS_PER_DAY
    return (
        (jd1, day_fraction),
        (jd1, day_fraction + tt_offset),
        (jd1, day_fraction + float(ut1_minus_utc) / SECONDS_PER_DAY),
    )


@functools.lru_cache(maxsize=512)
def utc_day(year: int, month: int, day: int) -> tuple:
    """Constants of a UTC calendar day, memoised: ``(jd1, tt_minus_utc, day_of_year)``.

    ``jd1`` = 2400000.5 + MJD of the day's 0 h UTC (the first part of ERFA's two-part dates),
    TT - UTC [day] (TAI - UTC from ERFA's leap-second table + 32.184 s), day of year 1..366.
    """
    ordinal = _dt.date(year, month, day).toordinal()
    return (
        _MJD_TO_JD + (ordinal - _MJD_ZERO_ORDINAL),
        (_tai_minus_utc(year, month, day) + _TT_MINUS_TAI) / SECONDS_PER_DAY,
        ordinal - _dt.date(year, 1, 1).toordinal() + 1,
    )


def seconds_of_day(time: _dt.datetime) -> float:
    """Seconds since 0 h of ``time``'s day [s] (of a UTC datetime: UTC seconds of the day)."""
    return time.hour * 3600.0 + time.minute * 60.0 + time.second + time.microsecond * 1e-6
