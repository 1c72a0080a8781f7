"""UTC instants as ERFA and NRLMSISE-00 take them: naive UTC datetimes, two-part Julian dates
(UTC, TT, UT1) through ERFA's leap-second table, day of year, seconds of day."""

from __future__ import annotations

import datetime as _dt

import erfa

_MJD_ZERO_ORDINAL = _dt.date(1858, 11, 17).toordinal()  # proleptic ordinal of MJD 0
_MJD_TO_JD = 2400000.5
_TT_MINUS_TAI = 32.184  # [s]
#: Seconds in a day of 86400 SI seconds (Julian dates count such days).
SECONDS_PER_DAY = 86400.0


_UTC = _dt.timezone.utc


# ------------------------------------------------------------------------------------------ time
def utc_datetime(time) -> _dt.datetime:
    """``time`` (aware, or naive meaning UTC) as a naive UTC datetime; ValueError if no
    :class:`datetime.datetime`."""
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


def julian_dates(time, ut1_minus_utc: float = 0.0):
    """Two-part Julian dates ``(utc, tt, ut1)`` of a UTC datetime; ``ut1_minus_utc`` [s]."""
    time = utc_datetime(time)
    jd1, tt_offset, _ = utc_day(time.year, time.month, time.day)
    day_fraction = seconds_of_day(time) / SECONDS_PER_DAY
    return (
        (jd1, day_fraction),
        (jd1, day_fraction + tt_offset),
        (jd1, day_fraction + float(ut1_minus_utc) / SECONDS_PER_DAY),
    )


def utc_day(year: int, month: int, day: int) -> tuple:
    """``(jd1, tt_minus_utc [day], day_of_year)`` of a UTC day; jd1 at 0 h UTC."""
    ordinal = _dt.date(year, month, day).toordinal()
    # TAI - UTC [s] from ERFA's table (0 before 1960, as ERFA); its status, "dubious" before
    # 1960 or well past the table, is not read: the value (the last known offset) is what we want
    tai_minus_utc = float(erfa.ufunc.dat(year, month, day, 0.5)[0])
    return (
        _MJD_TO_JD + (ordinal - _MJD_ZERO_ORDINAL),
        (tai_minus_utc + _TT_MINUS_TAI) / SECONDS_PER_DAY,
        ordinal - _dt.date(year, 1, 1).toordinal() + 1,
    )


def seconds_of_day(time: _dt.datetime) -> float:
    """Seconds since 0 h of ``time``'s day [s]."""
    return time.hour * 3600.0 + time.minute * 60.0 + time.second + time.microsecond * 1e-6
