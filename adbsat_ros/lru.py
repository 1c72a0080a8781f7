"""The bounded store of most recently used entries, with hit and miss counts, of every cache."""

from __future__ import annotations

from collections import OrderedDict
from typing import Callable


class LruStore:
    """At most ``max_entries`` values (never None) by key, least recently used dropped first."""

    def __init__(self, max_entries: int | None):
        if max_entries is not None and int(max_entries) < 1:
            raise ValueError(f"max_entries must be >= 1 or None, got {max_entries!r}")
        self.max_entries = None if max_entries is None else int(max_entries)
        self._entries: OrderedDict = OrderedDict()
        self.hits = self.misses = self.evictions = 0

    def get(self, key, make: Callable[[], object], count: bool = True):
        """The value of ``key``, stored or ``make()`` (then stored); ``count`` False: uncounted."""
        value = self._entries.get(key)
        if value is not None:
            self._entries.move_to_end(key)
            self.hits += count
            return value
        self.misses += count
        value = self._entries[key] = make()
        if self.max_entries is not None and len(self._entries) > self.max_entries:
            self._entries.popitem(last=False)
            self.evictions += 1
        return value

    def __len__(self) -> int:
        return len(self._entries)

    def __contains__(self, key) -> bool:
        return key in self._entries

    def clear(self) -> None:
        """Drop every entry (the counters run on)."""
        self._entries.clear()

    def info(self) -> dict:
        """Counters and size: hits, misses, evictions, size, max_entries."""
        return {
            "hits": self.hits,
            "misses": self.misses,
            "evictions": self.evictions,
            "size": len(self._entries),
            "max_entries": self.max_entries,
        }
