"""The health of the wrench computation: its diagnostic level and message, and message losses.
Shared by the node and bag analysis; rules: docs/node.md (``/diagnostics``, "Lost messages")."""

from __future__ import annotations

import math

import numpy as np

#: Levels of a diagnostic_msgs/DiagnosticStatus.
OK, WARN, ERROR = 0, 1, 2
#: Compute times kept for the p50/p99/max of the diagnostics (the latest this many wrenches).
COMPUTE_WINDOW = 2000


#: Rejections that follow from a missing state (not why it is missing).
FOR_WANT_OF_STATE = ("no_state", "stale_state")


def health_level(
    state_age: float | None,
    last_rejection_reason: str | None,
    rejected: int,
    state_timeout: float,
    diagnostics_period: float,
    cause: str | None = None,
) -> tuple[int, str]:
    """Level (OK, WARN, ERROR) and message of the diagnostic status; ages and periods [s].
    ``cause``: the latest rejection since the latest state other than FOR_WANT_OF_STATE, which
    leads the message when there is no usable state (``bad_state_frame: no orbital state``)."""
    prefix = f"{cause}: " if cause else ""
    if state_age is None:
        return ERROR, prefix + "no orbital state"
    if state_age > max(state_timeout, diagnostics_period):
        return ERROR, prefix + f"state is stale ({state_age:.1f} s old)"
    if last_rejection_reason == "stale_state":
        return ERROR, "state is stale relative to the attitude stamps"
    if rejected:
        latest = f" (latest: {last_rejection_reason})" if last_rejection_reason else ""
        return WARN, f"{rejected} inputs rejected so far{latest}"
    return OK, "ok"


class Health:
    """What the diagnostic status of one estimator is made of, updated message by message.
    ticks_per_second: time units per second of ``now`` arguments (1e9 for bag nanoseconds).
    window: compute times kept (the latest ones)."""

    def __init__(self, ticks_per_second: float = 1.0, window: int = COMPUTE_WINDOW):
        self.ticks_per_second = ticks_per_second
        self.last_sample = None
        self.last_rejection_reason: str | None = None
        self.cause: str | None = None  # (health_level's)
        self.computed = 0
        self._last_state_time = None
        self._compute_ms = np.zeros(window)  # a ring, written in place

    def state_accepted(self, now) -> None:
        """An orbital state was accepted at time ``now`` (in ticks)."""
        self._last_state_time = now
        self.cause = None

    def rejected(self, reason: str) -> None:
        """An input was rejected for ``reason``."""
        self.last_rejection_reason = reason
        if reason not in FOR_WANT_OF_STATE:
            self.cause = reason

    def sample_computed(self, compute_seconds: float, sample) -> None:
        """A sample was computed in ``compute_seconds`` [s]."""
        self._compute_ms[self.computed % self._compute_ms.size] = 1e3 * compute_seconds
        self.computed += 1
        self.last_sample = sample

    def compute_ms(self) -> np.ndarray:
        """The latest compute times [ms], at most ``window``, in no particular order."""
        return self._compute_ms[: min(self.computed, self._compute_ms.size)]

    def state_age(self, now) -> float | None:
        """Seconds from the latest accepted state to ``now`` (in ticks), None without one."""
        if self._last_state_time is None:
            return None
        return (now - self._last_state_time) / self.ticks_per_second

    def level(self, now, settings, rejected: int) -> tuple[int, str]:
        """:func:`health_level` at time ``now`` (in ticks) under ``settings``."""
        return health_level(
            self.state_age(now),
            self.last_rejection_reason,
            rejected,
            settings.state_timeout,
            settings.diagnostics_period,
            self.cause,
        )


class StampGaps:
    """Messages missing from a regular stream, estimated from its stamps [s]. A step over 1.5
    intervals counts round(step / interval) - 1 ``missing``; any other step is the new
    ``interval``; two equal gaps in a row (within 10 %) are a slower stream."""

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
    """Messages lost on one topic: ``counted`` from the publishers' sequence numbers (no gap while
    several publishers interleave them), ``middleware`` as the middleware reported."""

    def __init__(self):
        self.counted = 0
        self.middleware = 0
        self._latest: int | None = None
        self._shared = False  # whether the topic had several publishers at the latest check

    @property
    def lost(self) -> int:
        """Messages lost: the larger of the two counts."""
        return max(self.counted, self.middleware)

    def number(self, sequence: int, single_publisher) -> None:
        """A message numbered ``sequence`` was taken; ``single_publisher()`` is asked on a skip."""
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
