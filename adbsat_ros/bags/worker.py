"""The bag analysis's workers: chunks of trigger messages replayed through the node's handling.

A worker replays a chunk from reset estimators (one per model), decoding, handling and encoding
each message as the node does, and returns per message and model a :class:`MessageRecord`.
"""

from __future__ import annotations

import collections
import concurrent.futures
import itertools
import os
import time
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from typing import NamedTuple

from adbsat_ros.bags import io as bag_io
from adbsat_ros.bags.reading import JOINTS, STATE
from adbsat_ros.bags.table import model_cells, model_extra_columns, utc_text
from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.handling import MessageHandler, Outcome
from adbsat_ros.messages.decoding import (
    UndecodableMessage,
    decode_attitude,
    decode_joint_state,
    decode_odometry,
)
from adbsat_ros.messages.encoding import encode_wrench
from adbsat_ros.messages.stamps import stamp_seconds
from adbsat_ros.processes import die_with_parent, frozen_heap, pool_context
from adbsat_ros.tasks import POOL_START_S, dead_worker, run_while_alone, shut_pool

#: How often [s] the caller waiting for a chunk looks at its stop event.
STOP_POLL_S = 0.1


class SampleNumbers(NamedTuple):
    """A WrenchSample's diagnostic numbers, flat to pickle; :attr:`conditions` is the record."""

    mass_density: float
    temperature: float
    altitude: float
    speed: float
    speed_ratio: float
    alpha: float
    drag_coefficient: float
    solar_diagnostics: dict | None = None
    space_weather: object = None

    @property
    def conditions(self) -> "SampleNumbers":
        """The record itself, as ``WrenchSample.conditions`` reads."""
        return self

    @classmethod
    def of_sample(cls, sample) -> "SampleNumbers":
        """The numbers of a WrenchSample."""
        c = sample.conditions
        return cls(
            float(c.mass_density),
            float(c.temperature),
            float(c.altitude),
            float(c.speed),
            float(c.speed_ratio),
            float(c.alpha),
            float(sample.drag_coefficient),
            sample.solar_diagnostics,
            c.space_weather,
        )


class MessageRecord(NamedTuple):
    """What one message came to for one model, as the merge needs it: only numbers and bytes.

    ``status``: None (no wrench asked), ``ok`` or the reason; ``cache_keys``: the shading-cache
    cells read, ``uncounted_keys`` those read without counting (the Sun's); ``*_cdr``: messages to
    write.
    """

    state_accepted: bool = False
    status: str | None = None
    reason: str | None = None
    reason_text: str | None = None
    latest_rejection: bool = False
    numbers: SampleNumbers | None = None
    compute_seconds: float | None = None
    wrench_cdr: bytes | None = None
    coefficients_cdr: bytes | None = None
    cache_keys: tuple = ()
    solar_cdr: bytes | None = None
    total_cdr: bytes | None = None
    joint_torques_cdr: bytes | None = None
    uncounted_keys: tuple = ()


class Row(NamedTuple):
    """The CSV row of a message: stamp (sec, nanosec), UTC text, models' cells, plot numbers."""

    stamp_sec: int
    stamp_nanosec: int
    utc: str
    cells: str
    plot: list


class ChunkResult(NamedTuple):
    """A chunk's records and rows per message; ``error``: why message ``len(records)`` is
    unreadable."""

    records: list
    rows: list
    error: str | None = None


class WorkerModel:
    """One model's estimator in a worker, and the node's per-message handling around it."""

    def __init__(self, settings, mesh):
        self.estimator = AeroWrenchEstimator(settings, mesh)
        self.handler = MessageHandler(self.estimator)
        self._queries = self._query_count()

    def start_chunk(self) -> None:
        """Reset for a chunk (it starts at a state a fresh estimator accepts alike)."""
        self.estimator.reset()
        self._queries = self._query_count()

    def _query_count(self) -> int:
        cache = self.estimator.model.cache
        return 0 if cache is None else cache.hits + cache.misses

    def record(self, outcome: Outcome) -> MessageRecord:
        """The record of ``outcome``, the message just handled."""
        # its shading-cache cell: the merge counts hits and misses as one sequential cache would
        count = self._query_count()
        keys = uncounted = ()
        cache = self.estimator.model.cache
        if count != self._queries:
            self._queries = count
            keys = cache.last_keys
        if cache is not None and cache.last_uncounted:  # (taken: the next message's are new)
            uncounted, cache.last_uncounted = cache.last_uncounted, ()
        reason = reason_text = None
        if outcome.rejection is not None:
            reason, reason_text = outcome.rejection.reason, outcome.rejection.message
        elif outcome.error is not None:
            error = outcome.error
            reason, reason_text = "compute_error", f"{type(error).__name__}: {error}"
        sample = outcome.sample
        if sample is None:
            return MessageRecord(
                outcome.state_accepted,
                outcome.status,
                reason,
                reason_text,
                outcome.rejection is not None,
                cache_keys=keys,
                uncounted_keys=uncounted,
            )
        messages = encode_wrench(outcome.stamp, sample, self.estimator.settings)
        return MessageRecord(
            outcome.state_accepted,
            "ok",
            numbers=SampleNumbers.of_sample(sample),
            compute_seconds=sample.compute_seconds,
            wrench_cdr=messages.wrench,
            coefficients_cdr=messages.coefficients,
            cache_keys=keys,
            solar_cdr=messages.solar,
            total_cdr=messages.total,
            joint_torques_cdr=messages.joint_torques,
            uncounted_keys=uncounted,
        )


class Worker:
    """The models of one process, from ``specs`` (WrenchSettings, PanelMesh), one per model."""

    def __init__(self, specs, stopped=None):
        self.models = [WorkerModel(settings, mesh) for settings, mesh in specs]
        self.extras = tuple(model_extra_columns(m.estimator) for m in self.models)
        self.stopped = stopped

    def run(self, chunk) -> ChunkResult:
        """Replay ``chunk`` (kinds, CDR bytes); once ``stopped()``, end after this message."""
        kinds, raws = chunk
        models = self.models
        for m in models:
            m.start_chunk()
        utc_of = models[0].estimator.utc
        records, rows = [], []
        for kind, raw in zip(kinds, raws):
            try:
                if kind == JOINTS:
                    joint_state = decode_joint_state(raw, bag_io.deserialize_joint_state)
                    stamp = joint_state.stamp
                    outcomes = [
                        m.handler.on_joint_state(joint_state)
                        if m.estimator.body is not None
                        else Outcome(stamp=stamp)  # (a rigid model has no joints to set)
                        for m in models
                    ]
                elif kind == STATE:
                    odometry = decode_odometry(raw, bag_io.deserialize_odometry)
                    stamp = odometry.stamp
                    outcomes = [m.handler.on_state(odometry) for m in models]
                else:
                    attitude = decode_attitude(raw, bag_io.deserialize_attitude)
                    stamp = attitude.stamp
                    outcomes = [m.handler.on_attitude(attitude) for m in models]
            except UndecodableMessage as exc:
                return ChunkResult(records, rows, exc.reason)
            row = None
            if any(o.triggered for o in outcomes):
                cells, plot = model_cells(outcomes, self.extras)
                utc = utc_text(utc_of, stamp_seconds(stamp), outcomes[0].sample)
                row = Row(stamp.sec, stamp.nanosec, utc, cells, plot)
            records.append(tuple(m.record(o) for m, o in zip(models, outcomes)))
            rows.append(row)
            if self.stopped is not None and self.stopped():
                break
        return ChunkResult(records, rows)


_WORKER: Worker | None = None


def _init_worker(specs, parent: int, stop) -> None:
    """Pool initializer: the estimators, once per process; stops are left to the parent."""
    global _WORKER
    die_with_parent(parent, stops_to_parent=True)
    _WORKER = Worker(specs, lambda: stop.value)


def _run_chunk(chunk) -> ChunkResult:
    return _WORKER.run(chunk)


def chunk_results(specs, chunks, workers: int, stop=None, planned: int | None = None, report=None):
    """The ChunkResult of each chunk, in order: here (``workers`` 1), or by a pool kept ahead.

    planned: the number of chunks, given when ``workers`` is the default: they start here, and
    the pool only once the chunks left, timed here, are worth it
    (:func:`adbsat_ros.tasks.run_while_alone`); ``report.workers`` is then set to the count used.
    """
    with frozen_heap():
        yield from _chunk_results(specs, iter(chunks), workers, stop, planned, report)


def _chunk_results(specs, chunks, workers: int, stop, planned, report):
    if workers <= 1 or planned is not None:
        started = time.perf_counter()
        worker = Worker(specs, None if stop is None else stop.is_set)
        start_s = POOL_START_S + time.perf_counter() - started  # (each worker sets it up too)
        left = planned or 0
        for result in run_while_alone(worker.run, chunks, workers, left, start_s):
            left -= 1
            yield result
            if stop is not None and stop.is_set():
                return
        if left <= 0:  # (every chunk done here)
            return
        del worker
        workers = min(workers, left)
        if report is not None:
            report.workers = workers
    context = pool_context()
    halt = context.RawValue("b", 0)  # (shared with the workers, read at every message)
    with ProcessPoolExecutor(
        max_workers=workers,
        mp_context=context,
        initializer=_init_worker,
        initargs=(specs, os.getpid(), halt),
    ) as pool:
        todo, pending = chunks, collections.deque()
        try:
            pending.extend(pool.submit(_run_chunk, c) for c in itertools.islice(todo, 2 * workers))
            while pending:
                result = _result(pending.popleft(), stop, halt, pool)
                chunk = next(todo, None)
                if chunk is not None and not halt.value:
                    pending.append(pool.submit(_run_chunk, chunk))
                yield result
        except BrokenProcessPool:
            raise _died(pool) from None
        finally:
            halt.value = 1
            for future in pending:
                future.cancel()
            shut_pool(pool)


def _result(future, stop, halt, pool) -> ChunkResult:
    """``future``'s ChunkResult; ``halt`` is set as soon as ``stop`` is. BagError if a worker died
    (its pool may not notice: a worker handing a large result over would wait for ever)."""
    while True:
        try:
            return future.result(timeout=STOP_POLL_S)
        except concurrent.futures.TimeoutError:
            if stop is not None and stop.is_set():
                halt.value = 1
            if dead_worker(pool) is not None:
                raise _died(pool) from None


def _died(pool) -> bag_io.BagError:
    """The error of a pool one of whose workers died."""
    code = dead_worker(pool)
    killed = ", killed: out of memory?" if code == -9 else ""
    return bag_io.BagError(
        f"a worker process died (exit code {code}{killed}); nothing was written: run again, "
        "with fewer --workers if memory is short"
    )
