"""Where a bag's trigger messages can be cut into chunks that replay from a reset estimator
with the sequential results (:func:`safe_split_points`).
"""

from __future__ import annotations

import numpy as np

from adbsat_ros.bags.reading import ATTITUDE, JOINTS, STATE

#: Smallest default chunk: below this a process pool costs more than it saves.
MIN_CHUNK_MESSAGES = 250
#: Chunks per worker by default (load balance, and the merge writes while workers compute).
CHUNKS_PER_WORKER = 8
#: Largest default chunk with several workers: a stop waits for the chunks being computed.
MAX_CHUNK_MESSAGES = 2000


def safe_split_points(kinds, stamps, attitude_sources) -> np.ndarray:
    """Trigger-message indices k >= 1 where a freshly reset estimator gives the sequential results.

    They differ only in the latest state and last stamps: agree from k on if k is a state stamped
    later than every earlier state, no attitude stamp from k on is earlier than one before k, and no
    joint state comes before k. ``stamps``: header stamps [s] in bag order.
    """
    kinds = np.asarray(kinds)
    stamps = np.asarray(stamps, dtype=float)
    n = len(kinds)
    if n < 2:
        return np.zeros(0, dtype=np.int64)
    finite = np.isfinite(stamps)

    def before_max(mask):  # max over j < k of stamps[j] where mask, -inf if none
        x = np.where(mask & finite, stamps, -np.inf)
        out = np.empty(n)
        out[0] = -np.inf
        np.maximum.accumulate(x[:-1], out=out[1:])
        return out

    def from_min(mask):  # min over j >= k of stamps[j] where mask, +inf if none
        x = np.where(mask & finite, stamps, np.inf)
        return np.minimum.accumulate(x[::-1])[::-1]

    is_state = kinds == STATE
    ok = is_state & finite & (stamps > before_max(is_state))
    for source in set(attitude_sources):
        trigger = is_state if source == "odometry" else kinds == ATTITUDE
        ok &= from_min(trigger) >= before_max(trigger)
    joints = np.flatnonzero(kinds == JOINTS)
    if joints.size:
        ok[joints[0] + 1 :] = False
    ok[0] = False
    return np.flatnonzero(ok)


def plan_chunks(
    kinds, stamps, attitude_sources, workers: int, chunk_messages: int | None, accepted
) -> list:
    """Cut the trigger messages into chunks [start, stop) at safe split points; they cover all.

    ``accepted(k)``: whether every model's reset estimator accepts state message k.
    """
    n = len(kinds)
    if chunk_messages is None:
        per_worker = -(-n // (CHUNKS_PER_WORKER * workers))
        step = min(MAX_CHUNK_MESSAGES, max(MIN_CHUNK_MESSAGES, per_worker))
        count = -(-n // step)
        if workers > 1 and count > workers:
            # as many chunks for each worker: with one more, its last would run alone
            count = -(-count // workers) * workers
            step = n / count
    else:
        step = int(chunk_messages)
    splits = []
    if step < n:
        candidates = safe_split_points(kinds[: len(stamps)], stamps, attitude_sources)
        # cut at the first safe point from each multiple of ``step`` on (multiples of the
        # start, so that cuts late by a few messages do not add up to a chunk fewer)
        target = step
        for k in candidates.tolist():
            if k < target or n - k < max(1, step // 4):
                continue
            if accepted(k):
                splits.append(k)
                target = (k // step + 1) * step
    bounds = [0, *splits, n]
    return [(a, b) for a, b in zip(bounds[:-1], bounds[1:]) if b > a]
