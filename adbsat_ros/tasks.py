"""Chunked jobs, the one engine of sweeps and databases: in this process (one worker), a pool of
worker processes forked from it, or a running Dask scheduler. With the default worker count a
job starts in this process and starts workers only for a rest that would take longer on one
than they cost to start (:func:`run_chunks`).

A worker forked after this process made the job's set-up takes it; any other builds it on its
first chunk and keeps it (:data:`SETUPS`; scattered data would be lost with a worker). A chunk's
result may not depend on where or when it ran.
"""

from __future__ import annotations

import contextlib
import ctypes
import functools
import logging
import os
import threading
import time
from dataclasses import dataclass, field
from typing import Callable

from adbsat_ros.lru import LruStore
from adbsat_ros.processes import die_with_parent, frozen_heap, pool_context, worker_count

#: Times a chunk is submitted again after its worker died with it.
MAX_RETRIES = 3

#: How often [s] a run on workers with no result to take looks at its stop event.
STOP_POLL_S = 0.1

#: What a local worker costs before its first chunk [s]: forking it (it takes this process's
#: set-up of the job; docs/cli.md, "Workers").
POOL_START_S = 0.1

#: The job of this process's worker pool by its key, while it runs: forked workers have it
#: from the fork, so their tasks carry the key alone (:class:`ForkedJob`).
_FORKED: dict = {}

#: Set-ups of the latest jobs on this process, by the job's key: a worker builds a job's
#: set-up on its first chunk and keeps it for the rest.
SETUPS = LruStore(2)


@dataclass(frozen=True)
class ChunkJob:
    """A picklable job: a ``key`` (equal keys: equal set-ups) and what its chunks need, built
    where they run by ``make(*args)``: an object with ``evaluate(chunk)``."""

    key: str
    make: Callable
    args: tuple = ()

    def setup(self):
        """What the chunks need, built here."""
        return self.make(*self.args)


@dataclass
class TaskReport:
    """What a run did: chunks computed (``here``: in this process), whether a signal stopped it,
    its workers (1: this process alone), warnings."""

    computed: int = 0
    stopped: bool = False
    workers: int = 0
    notes: list = field(default_factory=list)
    here: int = 0


def run_chunk(job: ChunkJob, chunk):
    """The task: ``chunk``'s result, with this process's set-up of ``job``."""
    keep_freed_memory()
    return SETUPS.get(job.key, job.setup).evaluate(chunk)


@dataclass(frozen=True)
class ForkedJob:
    """A job a forked worker has from the fork: its key alone travels with a task."""

    key: str

    def setup(self):
        """The set-up of the job of this key (:data:`_FORKED`)."""
        return _FORKED[self.key].setup()


#: glibc's ``mallopt`` parameters (malloc.h) and the values a worker sets.
M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3
TRIM_THRESHOLD, MMAP_THRESHOLD = 512 << 20, 32 << 20


@functools.cache
def keep_freed_memory() -> None:
    """Make glibc keep the memory this process frees for its next allocations (once)."""
    with contextlib.suppress(OSError, AttributeError):  # (not glibc: its own allocator's ways)
        libc = ctypes.CDLL(None)
        libc.mallopt(M_TRIM_THRESHOLD, TRIM_THRESHOLD)
        libc.mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD)


def run_chunks(
    job: ChunkJob,
    chunks: dict,
    on_result: Callable,
    *,
    scheduler: str | None = None,
    workers: int | None = None,
    stop=None,
    report: TaskReport | None = None,
    setup=None,
) -> TaskReport:
    """Compute every chunk of ``job`` and call ``on_result(index, result)`` here as each finishes.

    chunks: index -> chunk (picklable).
    scheduler: a running Dask scheduler's address (``tcp://host:8786``); None: this machine.
    workers: processes without ``scheduler`` (1: this process). None: every usable CPU, started
      only once the chunks left, timed here one by one, are worth them (:func:`worth_workers`).
    stop: an event; set, the run stops after the chunk finishing now (rerun to go on).
    report: the TaskReport to fill and return (default a new one).
    setup: ``job.setup()`` built here already: this process and forked workers take it (a job
      run here first builds it once, for both).
    RuntimeError: a chunk whose workers died :data:`MAX_RETRIES` + 1 times (on a local pool, then
      once more in a worker of its own).
    """
    report = TaskReport() if report is None else report
    if not chunks:
        return report
    if scheduler is None:
        count, note = worker_count(workers)
        if note:
            report.notes.append(f"--workers: {note}")
        count = min(count, len(chunks))
        if count == 1 or workers is None:
            setup = job.setup() if setup is None else setup
            chunks = _run_here(setup, chunks, on_result, count, stop, report)
            if not chunks or report.stopped:
                return report
        return _run_in_pool(job, chunks, on_result, count, stop, report, setup)
    with _quiet_distributed():
        return _run_on_dask(job, chunks, on_result, scheduler, stop, report)


def worth_workers(left_s: float, start_s: float, count: int) -> bool:
    """Whether ``count`` workers that take ``start_s`` [s] to start (and set the job up) finish
    a rest of ``left_s`` [s] on one process sooner than this process: ``left_s / count +
    start_s < left_s``."""
    return count > 1 and left_s / count + start_s < left_s


def run_while_alone(evaluate, chunks, count: int, left: int, start_s: float):
    """Yield ``evaluate(chunk)`` of each chunk, in this process, until :func:`worth_workers` says
    that ``count`` workers finish the ``left`` chunks sooner; timed by the fastest chunk so far,
    from the second on: a worker takes ``start_s`` [s] to start, and what the first chunk took
    more."""
    first = fastest = None
    for done, chunk in enumerate(chunks, 1):
        started = time.perf_counter()
        result = evaluate(chunk)
        took = time.perf_counter() - started
        first = took if first is None else first
        fastest = took if fastest is None else min(fastest, took)
        left -= 1
        yield result
        workers = min(count, left) if done > 1 else 1  # (the first chunk: one-time costs)
        if worth_workers(fastest * left, start_s + first - fastest, workers):
            return


def _run_here(setup, chunks: dict, on_result, count: int, stop, report) -> dict:
    """Compute chunks with ``setup`` here while :func:`run_while_alone` does; the chunks left."""
    report.workers = 1
    left = dict(chunks)
    results = run_while_alone(setup.evaluate, chunks.values(), count, len(chunks), POOL_START_S)
    for index, result in zip(chunks, results):
        del left[index]
        on_result(index, result)
        report.computed += 1
        report.here += 1
        if stop is not None and stop.is_set():
            report.stopped = True
            break
    return left


def _run_in_pool(job, chunks: dict, on_result, count, stop, report, setup) -> TaskReport:
    """The chunks on a pool of ``count`` worker processes forked from this one (taking ``setup``
    if not None); the chunks of a pool that a worker's death broke go to a new pool."""
    from concurrent.futures import FIRST_COMPLETED, wait
    from concurrent.futures.process import BrokenProcessPool

    report.workers = count
    # (before the workers fork: they keep it)
    _FORKED[job.key] = job if setup is None else ChunkJob(job.key, lambda: setup)
    left, retries, task = dict(chunks), dict.fromkeys(chunks, 0), ForkedJob(job.key)
    try:
        while left and not report.stopped:
            with frozen_heap():
                pool, futures = _pool(count), {}
                for index, chunk in left.items():
                    try:
                        futures[pool.submit(run_chunk, task, chunk)] = index
                    except BrokenProcessPool:  # (a worker died already: the rest to a new pool)
                        break
            try:
                while futures and not report.stopped:
                    done, _ = wait(futures, STOP_POLL_S, FIRST_COMPLETED)
                    for future in done:
                        index = futures.pop(future)
                        try:
                            result = future.result()
                        except BrokenProcessPool:  # (a worker died: again in a new pool)
                            retries[index] += 1
                            if retries[index] <= MAX_RETRIES:
                                continue
                            result = _alone(task, index, left[index])  # (or the one beside it?)
                        del left[index]
                        on_result(index, result)
                        report.computed += 1
                        if stop is not None and stop.is_set():
                            break
                    report.stopped = stop is not None and stop.is_set()
            finally:
                shut_pool(pool, kill=bool(futures))  # (the chunks running are dropped)
    finally:
        _FORKED.pop(job.key, None)
    return report


def _pool(count: int):
    """A pool of ``count`` worker processes forked from this one, each ending with it."""
    from concurrent.futures import ProcessPoolExecutor

    return ProcessPoolExecutor(
        count, pool_context(), initializer=die_with_parent, initargs=(os.getpid(), True)
    )


def shut_pool(pool, kill: bool = False) -> None:
    """Shut ``pool`` down, first killing its workers if ``kill`` (their chunks dropped) or if one
    has died: a broken pool waits for the others, which ignore SIGTERM, for ever."""
    if kill or dead_worker(pool) is not None:
        for process in list((pool._processes or {}).values()):
            process.kill()
    pool.shutdown(cancel_futures=True)


def dead_worker(pool) -> int | None:
    """The exit code of a worker of ``pool`` that ended (they end only with the pool), or None."""
    codes = [p.exitcode for p in list((pool._processes or {}).values())]
    return next((code for code in codes if code is not None), None)


def _alone(task, index, chunk):
    """``chunk``'s result from a worker of its own: pending each time a pool broke, it may only
    have stood beside the chunk that kills its worker. RuntimeError if it kills this one too."""
    from concurrent.futures.process import BrokenProcessPool

    with frozen_heap():
        pool = _pool(1)
        future = pool.submit(run_chunk, task, chunk)
    try:
        return future.result()
    except BrokenProcessPool as exc:
        raise RuntimeError(
            f"chunk {index} failed {MAX_RETRIES + 2} times, the last in a worker of its own: "
            f"{exc!r}"
        ) from None
    finally:
        shut_pool(pool, kill=not future.done())


def _run_on_dask(job, chunks, on_result, scheduler, stop, report) -> TaskReport:
    from distributed import Client, as_completed
    from distributed.client import FutureCancelledError as CancelledError
    from distributed.comm.core import CommClosedError
    from distributed.scheduler import KilledWorker

    try:
        client = Client(scheduler)
    except (OSError, TimeoutError) as exc:
        raise OSError(f"scheduler {scheduler}: no Dask scheduler answers there ({exc})") from None
    with client:
        report.workers = len(client.scheduler_info()["workers"])

        def submit(index):
            return client.submit(run_chunk, job, chunks[index], pure=False)

        futures = {submit(i): i for i in chunks}
        retries = dict.fromkeys(chunks, 0)
        pending = as_completed(futures)
        waiting = stop if stop is not None else threading.Event()
        while futures:
            if waiting.is_set():  # (the chunks running are dropped: rerun to go on)
                report.stopped = True
                break
            if not pending.has_ready():
                waiting.wait(STOP_POLL_S)
                continue
            future = next(pending)
            index = futures.pop(future)
            try:
                result = future.result()
            except (CancelledError, KilledWorker, CommClosedError) as exc:
                # (its worker died, or its result with it): compute it again elsewhere
                retries[index] += 1
                if retries[index] > MAX_RETRIES:
                    raise RuntimeError(
                        f"chunk {index} failed {MAX_RETRIES + 1} times; the last: {exc!r}"
                    ) from None
                again = submit(index)
                futures[again] = index
                pending.add(again)
                continue
            on_result(index, result)
            report.computed += 1
            if stop is not None and stop.is_set():
                report.stopped = True
                break
    return report


@contextlib.contextmanager
def _quiet_distributed():
    """Dask's loggers at CRITICAL while inside (its INFO lines would bury a progress bar)."""
    import distributed  # noqa: F401  (its loggers exist from here on)

    names = [n for n in list(logging.root.manager.loggerDict) if n.split(".")[0] == "distributed"]
    saved = [(logger, logger.level) for logger in map(logging.getLogger, names)]
    for logger, _ in saved:
        logger.setLevel(logging.CRITICAL)
    try:
        yield
    finally:
        for logger, level in saved:
            logger.setLevel(level)
