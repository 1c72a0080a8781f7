"""LruStore: the bounded most-recently-used store the caches keep their entries in."""

import pytest

from adbsat_ros.lru import LruStore


def _made(log, value):
    def make():
        log.append(value)
        return value

    return make


def test_the_least_recently_used_entry_goes_first_and_is_counted():
    store, made = LruStore(2), []
    assert store.get("a", _made(made, 1)) == 1
    assert store.get("b", _made(made, 2)) == 2
    assert store.get("a", _made(made, 10)) == 1  # stored: not made again, and now the newest
    assert store.get("c", _made(made, 3)) == 3  # drops "b", the least recently used
    assert made == [1, 2, 3]
    assert "a" in store and "c" in store and "b" not in store and len(store) == 2
    assert store.info() == {"hits": 1, "misses": 3, "evictions": 1, "size": 2, "max_entries": 2}


def test_a_lookup_not_counted_still_stores_and_orders():
    store = LruStore(2)
    store.get("a", lambda: 1)
    store.get("b", lambda: 2, count=False)
    store.get("a", lambda: 10, count=False)  # "a" the newest
    store.get("c", lambda: 3, count=False)  # drops "b"
    assert (store.hits, store.misses, store.evictions) == (0, 1, 1)
    assert "b" not in store and "a" in store


def test_without_a_bound_nothing_is_dropped_and_clear_keeps_the_counters():
    store = LruStore(None)
    for k in range(100):
        store.get(k, lambda k=k: k + 1)
    assert len(store) == 100 and store.evictions == 0 and store.max_entries is None
    store.clear()
    assert len(store) == 0 and store.misses == 100


@pytest.mark.parametrize("bound", [0, -3])
def test_a_bound_below_one_is_refused_by_name(bound):
    with pytest.raises(ValueError, match="max_entries must be >= 1"):
        LruStore(bound)
