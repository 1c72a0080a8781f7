"""Running a sweep on Dask: the chunks as tasks, each written to the store as it finishes.

Without a scheduler address the sweep starts a ``distributed.LocalCluster`` of worker processes
on this machine (one thread each: the panel method holds the GIL); with one, it connects to that
running scheduler (``dask scheduler`` and ``dask worker`` processes, or a cluster that
dask-jobqueue or dask-kubernetes started). Each task carries the spec (a few kilobytes); every
worker builds the set-up it names (mesh, shader) once (:mod:`adbsat_ros.sweep.evaluate`), so
a mesh file must be readable at the same path on the workers. A worker that dies takes its
running chunks with it; the scheduler gives them to another worker. Nothing in a chunk depends
on where or when it ran, so the store is the same whatever the workers and the order.
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

from adbsat_ros.sweep.evaluate import SweepSetup, compute_chunk
from adbsat_ros.sweep.spec import SweepSpec
from adbsat_ros.sweep.store import SweepStore

#: Times a chunk is submitted again after its worker died with it (dask itself recomputes what
#: it can; this covers a task it gives up on or forgets).
MAX_RETRIES = 3


@dataclass
class SweepReport:
    """What a run did: chunks in all, found written, computed now; points; wall time [s];
    whether it stopped early (a signal), and the workers it had."""

    chunks: int = 0
    already_done: int = 0
    computed: int = 0
    points: int = 0
    seconds: float = 0.0
    stopped: bool = False
    workers: int = 0
    notes: list = field(default_factory=list)


def run_sweep(
    spec: SweepSpec,
    out,
    scheduler: str | None = None,
    workers: int | None = None,
    overwrite: bool = False,
    progress: bool = False,
    stop=None,
) -> SweepReport:
    """Compute the chunks of ``spec`` not in the store at ``out`` yet, on Dask.

    Parameters
    ----------
    spec : SweepSpec
    out : path
        The Zarr store (made, or taken up where it stopped).
    scheduler : str, optional
        Address of a running Dask scheduler (``tcp://host:8786``); None: a LocalCluster here.
    workers : int, optional
        Worker processes of the LocalCluster (default: every usable CPU).
    overwrite : bool
        Replace a store of another spec at ``out``.
    progress : bool
        A progress bar (tqdm, on stderr).
    stop : threading.Event, optional
        Set to stop after the chunks finishing now (they are written; rerun to go on).

    Raises
    ------
    StoreError
        ``out`` holds something else.
    MeshError, ValueError
        The spec's body or materials cannot be set up.
    """
    import distributed  # noqa: F401  (its loggers exist from here on)

    started = time.perf_counter()
    # its INFO lines (the in-process scheduler's) would bury the progress bar
    loggers = [
        logging.getLogger(name)
        for name in list(logging.root.manager.loggerDict)
        if name.split(".")[0] == "distributed"
    ]
    levels = [logger.level for logger in loggers]
    for logger in loggers:
        logger.setLevel(logging.ERROR)
    try:
        return _run(spec, out, scheduler, workers, overwrite, progress, stop, started)
    finally:
        for logger, level in zip(loggers, levels):
            logger.setLevel(level)


def _run(spec, out, scheduler, workers, overwrite, progress, stop, started) -> SweepReport:
    import dask
    from distributed import Client, LocalCluster, as_completed
    from distributed.client import FutureCancelledError as CancelledError
    from distributed.comm.core import CommClosedError
    from distributed.scheduler import KilledWorker
    from tqdm import tqdm

    from adbsat_ros.processes import worker_count

    setup = SweepSetup(spec)  # (checked here first: a bad mesh fails before any worker starts)
    store = SweepStore.open(out, spec, setup, overwrite)
    todo = store.missing()
    report = SweepReport(chunks=len(store.slices), already_done=len(store.slices) - len(todo))
    if not todo:
        report.seconds = time.perf_counter() - started
        return report
    cluster = None
    if scheduler is None:
        count, note = worker_count(workers)
        if note:
            report.notes.append(f"--workers: {note}")
        with dask.config.set({"distributed.nanny.pre-spawn-environ": _worker_environment()}):
            cluster = LocalCluster(
                n_workers=count,
                threads_per_worker=1,
                processes=True,
                dashboard_address=":0",  # (a free port: two sweeps on one machine never clash)
                silence_logs=logging.ERROR,
            )
    client = Client(cluster if cluster is not None else scheduler)
    try:
        report.workers = len(client.scheduler_info()["workers"])

        # the spec (a few kB) goes with each task, and the set-up it names is built once per
        # worker: scattered data would have no lineage, and its loss with a worker would
        # cancel the tasks that need it
        def submit(index):
            return client.submit(compute_chunk, spec, store.slices[index], pure=False)

        futures = {submit(i): i for i in todo}
        retries = dict.fromkeys(todo, 0)
        pending = as_completed(futures)
        bar = tqdm(total=len(store.slices), initial=report.already_done, disable=not progress)
        with bar:
            for future in pending:
                index = futures.pop(future)
                try:
                    results = future.result()
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
                store.write(index, results)
                report.computed += 1
                bar.update(1)
                if stop is not None and stop.is_set():
                    report.stopped = True
                    break
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    report.points = sum(_points(store.slices[i]) for i in set(todo) - set(store.missing()))
    report.seconds = time.perf_counter() - started
    return report


def _worker_environment() -> dict:
    """Dask's environment for worker processes without ``MALLOC_TRIM_THRESHOLD_``: a fixed
    trim threshold (Dask sets 64 KiB) makes glibc give memory back at every turn of the panel
    method's small arrays; measured in one run, 2,701 attitudes of the example satellite took
    18.2 s in one process with it and 12.1 s without (the work itself takes a few hundred MB)."""
    import dask

    environment = dict(dask.config.get("distributed.nanny.pre-spawn-environ", {}))
    environment.pop("MALLOC_TRIM_THRESHOLD_", None)
    return environment


def _points(slices) -> int:
    count = 1
    for a, b in slices:
        count *= b - a
    return count
