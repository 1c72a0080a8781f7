"""How bag analysis cuts its trigger messages into chunks (adbsat_ros.bags.planning)."""

import numpy as np
import pytest

from adbsat_ros.bags.planning import MAX_CHUNK_MESSAGES, plan_chunks
from adbsat_ros.bags.reading import ATTITUDE, STATE


def flight(seconds: float):
    """Kinds and stamps of a flight at 100 Hz with a state every tenth message."""
    n = int(seconds * 100) + 1
    kinds = np.full(n, ATTITUDE)
    kinds[::10] = STATE
    return kinds, np.arange(n) * 0.01


@pytest.mark.parametrize("seconds", [60.0, 300.0, 1000.0])
@pytest.mark.parametrize("workers", [1, 2, 3])
def test_default_chunks_cover_the_flight_and_balance_the_workers(seconds, workers):
    kinds, stamps = flight(seconds)
    chunks = plan_chunks(kinds, stamps, ["attitude"], workers, None, lambda k: True)
    assert chunks[0][0] == 0 and chunks[-1][1] == len(kinds)
    assert all(a < b for a, b in chunks)
    assert all(b == c for (_, b), (c, _) in zip(chunks[:-1], chunks[1:]))
    sizes = [b - a for a, b in chunks]
    assert max(sizes) <= MAX_CHUNK_MESSAGES + 10  # (cut at the state next to the target)
    if workers > 1:
        # as many chunks per worker: none runs a last chunk alone while the others wait
        assert len(chunks) % workers == 0
        assert max(sizes) - min(sizes) <= 0.25 * max(sizes)


def test_given_chunk_size_is_kept():
    kinds, stamps = flight(300.0)
    chunks = plan_chunks(kinds, stamps, ["attitude"], 2, 2000, lambda k: True)
    # 30,001 messages: 2,000 each, the last message joined to the last chunk (a chunk of one
    # message would cost more than it saves)
    assert [b - a for a, b in chunks] == [2000] * 14 + [2001]
    # a chunk starts where its state is accepted, at the first such state from its target on
    refused = {2000, 2010}
    chunks = plan_chunks(kinds, stamps, ["attitude"], 2, 2000, lambda k: k not in refused)
    assert chunks[0] == (0, 2020) and chunks[1] == (2020, 4000)
