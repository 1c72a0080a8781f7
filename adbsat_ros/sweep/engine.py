"""Running a sweep: its missing chunks on local workers or a Dask scheduler, each written as it
finishes; a mesh file must be readable at the same path on every worker. docs/sweeps.md."""

from __future__ import annotations

import math
import os
import time
import uuid
from dataclasses import dataclass

from adbsat_ros.bounds import check_memory
from adbsat_ros.processes import interruptible
from adbsat_ros.sweep.spec import SweepSpec
from adbsat_ros.sweep.store import SweepChunks, SweepStore, chunk_shape
from adbsat_ros.tasks import ChunkJob, TaskReport, run_chunks

#: Memory of the process that runs a sweep for each of its chunks [bytes]: the chunk's index
#: ranges, its task in the Dask client and scheduler (each carries the spec) and its future.
BYTES_PER_CHUNK = 16_384
#: Memory of a worker for each point of a chunk [bytes]: the point's results (24 or 30 numbers)
#: and the temporaries of its evaluation.
BYTES_PER_POINT = 4_096


@dataclass
class SweepReport(TaskReport):
    """What a run did (a TaskReport's counts), and its chunks in all, found; points; wall time
    [s]."""

    chunks: int = 0
    already_done: int = 0
    points: int = 0
    seconds: float = 0.0


def run_sweep(
    spec: SweepSpec,
    out,
    scheduler: str | None = None,
    workers: int | None = None,
    overwrite: bool = False,
    progress: bool = False,
    stop=None,
) -> SweepReport:
    """Compute the chunks of ``spec`` not in the Zarr store at ``out`` yet. scheduler: a running
    Dask scheduler's address (``tcp://host:8786``), None: this machine; workers: local processes
    (default every usable CPU; 1: this process); overwrite: replace another spec's store at
    ``out``; stop: a threading.Event, stopping after the chunk finishing now (rerun to go on).
    StoreError: ``out`` holds something else. ValueError: the body cannot be set up (or MeshError).
    """
    from tqdm import tqdm

    check_memory(*memory_estimate(spec))  # (before any work)
    started = time.perf_counter()
    # (local workers write their chunks' results themselves; a scheduler's return them)
    where = None if scheduler is not None else os.fspath(out)
    with interruptible():  # (nothing written yet: a signal ends it at once)
        chunks = SweepChunks(spec, where)  # (checked first: a bad mesh fails before any worker)
    store = SweepStore.open(out, spec, chunks.setup, overwrite)
    todo = store.missing()
    report = SweepReport(chunks=len(store.slices), already_done=len(store.slices) - len(todo))
    bar = tqdm(total=len(store.slices), initial=report.already_done, disable=not progress)

    def write(index, results):
        if results is not None:  # (else written where it ran)
            store.write_results(store.slices[index], results)
        store.mark_done(index)
        bar.update(1)

    with bar:
        run_chunks(
            ChunkJob(f"sweep {uuid.uuid4().hex}", SweepChunks, (spec, where)),
            {i: store.slices[i] for i in todo},
            write,
            scheduler=scheduler,
            workers=workers,
            stop=stop,
            report=report,
            setup=chunks,
        )
    done_chunks = set(todo) - set(store.missing())
    report.points = sum(math.prod(b - a for a, b in store.slices[i]) for i in done_chunks)
    report.seconds = time.perf_counter() - started
    return report


def memory_estimate(spec: SweepSpec) -> tuple:
    """``(what, bytes)``: the memory a run of ``spec`` needs."""
    sizes = chunk_shape(spec.shape, spec.chunk_points)
    chunks = math.prod(-(-n // s) for n, s in zip(spec.shape, sizes))
    estimate = chunks * BYTES_PER_CHUNK + math.prod(sizes) * BYTES_PER_POINT
    points = math.prod(spec.shape)
    return (
        f"the sweep of {points} points in {chunks} chunks of {spec.chunk_points} points",
        estimate,
    )
