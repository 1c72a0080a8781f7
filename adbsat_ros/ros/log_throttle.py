"""At most one log line per kind of event and period, decided before the logger is called."""

from __future__ import annotations

import time

#: Seconds between two log lines about the same kind of event (e.g. one rejection reason).
LOG_THROTTLE_S = 5.0


class LogThrottle:
    """At most one log line per key every ``period`` s; ``clock()`` gives the time [s].

    rclpy's ``throttle_duration_sec`` inspects its caller on every call, suppressed ones too.
    """

    def __init__(self, logger, period: float = LOG_THROTTLE_S, clock=time.monotonic):
        self._logger = logger
        self._period = period
        self._clock = clock
        self._last: dict = {}

    def __call__(self, level: str, key: str, text: str) -> bool:
        """Log ``text`` at ``level`` unless ``key`` was within ``period`` s; whether logged."""
        now = self._clock()
        last = self._last.get(key)
        if last is not None and now - last < self._period:
            return False
        self._last[key] = now
        getattr(self._logger, level)(text)
        return True
