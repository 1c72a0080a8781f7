"""The health of the wrench computation: the level and message of its diagnostic status.

Written once for the node's /diagnostics and the bag analysis's (which measures the state's age
in bag time): ERROR when there is no orbital state or the latest is older than the state time-out
(or the diagnostics period, if longer), or when the latest rejection was a state too far from the
attitude stamps; WARN when inputs were rejected; OK otherwise. :class:`Health` keeps what those
and the status's values are made of: when the latest state was accepted, the latest rejection,
the latest sample and the recent compute times.
"""

from __future__ import annotations

import math

import numpy as np

#: Levels of a diagnostic_msgs/DiagnosticStatus.
OK, WARN, ERROR = 0, 1, 2
#: Compute times kept for the p50/p99/max of the diagnostics (the latest this many wrenches).
COMPUTE_WINDOW = 2000


def health_level(
    state_age: float | None,
    last_rejection_reason: str | None,
    rejected: int,
    state_timeout: float,
    diagnostics_period: float,
) -> tuple[int, str]:
    """Level (OK, WARN, ERROR) and message of the diagnostic status.

    Parameters
    ----------
    state_age : float or None
        Seconds since the latest accepted orbital state (None: none yet).
    last_rejection_reason : str or None
        Reason of the latest rejected input (one of ``REJECTION_REASONS``), if any.
    rejected : int
        Inputs rejected so far, all reasons.
    state_timeout, diagnostics_period : float
        The settings of those names [s]: a state older than the larger of the two is stale.
    """
    if state_age is None:
        return ERROR, "no orbital state"
    if state_age > max(state_timeout, diagnostics_period):
        return ERROR, f"state is stale ({state_age:.1f} s old)"
    if last_rejection_reason == "stale_state":
        return ERROR, "state is stale relative to the attitude stamps"
    if rejected:
        return WARN, f"{rejected} inputs rejected so far"
    return OK, "ok"


class Health:
    """What the diagnostic status of one estimator is made of, updated message by message.

    Parameters
    ----------
    ticks_per_second : float
        Units of the times given to :meth:`state_accepted` and :meth:`level` per second (1 for
        seconds of a monotonic clock, 1e9 for integer nanoseconds of bag time, which are then
        subtracted exactly).
    window : int
        Compute times kept (the latest ones).

    Attributes
    ----------
    last_sample : object or None
        The latest sample computed (a WrenchSample, or anything with its ``conditions`` and
        ``drag_coefficient``), for the status's values.
    last_rejection_reason : str or None
        Reason of the latest rejected input.
    computed : int
        Samples computed so far.
    """

    def __init__(self, ticks_per_second: float = 1.0, window: int = COMPUTE_WINDOW):
        self.ticks_per_second = ticks_per_second
        self.last_sample = None
        self.last_rejection_reason: str | None = None
        self.computed = 0
        self._last_state_time = None
        self._compute_ms = np.zeros(window)  # a ring, written in place

    def state_accepted(self, now) -> None:
        """An orbital state was accepted at time ``now`` (in ticks)."""
        self._last_state_time = now

    def rejected(self, reason: str) -> None:
        """An input was rejected for ``reason``."""
        self.last_rejection_reason = reason

    def sample_computed(self, compute_seconds: float, sample) -> None:
        """A sample was computed in ``compute_seconds`` [s]."""
        self._compute_ms[self.computed % self._compute_ms.size] = 1e3 * compute_seconds
        self.computed += 1
        self.last_sample = sample

    def compute_ms(self) -> np.ndarray:
        """The latest compute times [ms] (at most ``window``; in no particular order)."""
        return self._compute_ms[: min(self.computed, self._compute_ms.size)]

    def state_age(self, now) -> float | None:
        """Seconds from the latest accepted state to ``now`` (in ticks), None without one."""
        if self._last_state_time is None:
            return None
        return (now - self._last_state_time) / self.ticks_per_second

    def level(self, now, settings, rejected: int) -> tuple[int, str]:
        """:func:`health_level` at time ``now`` (in ticks) under ``settings`` (WrenchSettings)."""
        return health_level(
            self.state_age(now),
            self.last_rejection_reason,
            rejected,
            settings.state_timeout,
            settings.diagnostics_period,
        )


class StampGaps:
    """Messages missing from a regular stream, estimated from its stamps.

    A GNC loop stamps its attitudes at a fixed interval. A step between consecutive stamps of
    more than 1.5 intervals is counted as round(step / interval) - 1 missing messages (lost by
    the middleware, or never sent: a paused simulator counts too); any other step is the new
    interval. Two such steps in a row of one size (within 10 %) are a slower stream: the second
    becomes the interval (the first stays counted). Stamps that do not advance are left out.

    Attributes
    ----------
    missing : int
        Messages estimated missing so far.
    interval : float or None
        The latest regular interval [s].
    """

    def __init__(self):
        self.missing = 0
        self.interval: float | None = None
        self._latest: float | None = None
        self._gap: float | None = None  # the step counted as a gap just before

    def stamp(self, stamp: float) -> None:
        """A message stamped ``stamp`` [s] arrived."""
        if not math.isfinite(stamp):
            return
        latest = self._latest
        if latest is None or not stamp > latest:
            if latest is None:
                self._latest = stamp
            return
        step = stamp - latest
        interval = self.interval
        if interval is not None and step > 1.5 * interval:
            if self._gap is not None and abs(step - self._gap) <= 0.1 * step:
                self.interval, self._gap = step, None  # the stream slowed down
            else:
                self.missing += round(step / interval) - 1
                self._gap = step
        else:
            self.interval, self._gap = step, None
        self._latest = stamp


class SequenceGaps:
    """Messages lost on one topic, counted from the publisher's sequence numbers.

    A publisher numbers its messages 1, 2, 3 ...; every number skipped between two messages the
    node takes was lost on the way: in the middleware, or overwritten in the subscription's own
    queue (KEEP_LAST ``qos_depth``) while the node was busy. The first message taken from a
    publisher starts its count (the numbers before it may have been sent before the publisher
    found the node). While the topic has more than one publisher their numbers interleave and
    no message says whose it is: no gap is counted then, nor the first one after it, and a
    number that does not advance starts a new count (another publisher, or the same one
    restarted). Losses the middleware reports (:meth:`reported`) count where they exceed the
    gaps counted.

    Attributes
    ----------
    counted : int
        Messages missing from the sequence numbers so far.
    middleware : int
        Messages the middleware reported lost so far.
    """

    def __init__(self):
        self.counted = 0
        self.middleware = 0
        self._latest: int | None = None
        self._shared = False  # whether the topic had several publishers at the latest check

    @property
    def lost(self) -> int:
        """Messages lost: the larger of the two counts (both see a lost message of a single
        publisher; only the middleware sees one while several publish)."""
        return max(self.counted, self.middleware)

    def number(self, sequence: int, single_publisher) -> None:
        """A message numbered ``sequence`` by its publisher was taken; ``single_publisher()``
        says whether the topic has one publisher (asked only when the number skips some)."""
        latest, self._latest = self._latest, sequence
        if latest is None or sequence <= latest + 1:
            return
        single = bool(single_publisher())
        if single and not self._shared:
            self.counted += sequence - latest - 1
        self._shared = not single

    def restart(self) -> None:
        """A publisher came or went: the next message starts a new count."""
        self._latest = None

    def reported(self, count_change: int) -> None:
        """The middleware reported ``count_change`` more messages lost."""
        self.middleware += count_change
