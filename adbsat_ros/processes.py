"""Processes of the long jobs (database builds, bag analysis, the node): how workers start and
how many, the heap kept out of the garbage collector's passes while they run, and stopping on
SIGINT/SIGTERM in order."""

from __future__ import annotations

import contextlib
import gc
import multiprocessing
import os
import signal
import threading


def usable_cpus() -> int:
    """The CPUs this process may run on (its affinity mask where the platform has one)."""
    try:
        return len(os.sched_getaffinity(0)) or 1
    except AttributeError:  # (no affinity masks on this platform)
        return os.cpu_count() or 1


def worker_count(requested: int | None) -> tuple:
    """``(workers, note)``: ``requested`` processes (default: every usable CPU), at most
    :func:`usable_cpus` (more only add memory and switching: 1,000 workers took 11 GB); ``note``
    says so when it capped the request, else it is None.

    Raises
    ------
    ValueError
        For a count that is not a whole number >= 1.
    """
    cpus = usable_cpus()
    if requested is None:
        return cpus, None
    if isinstance(requested, bool) or int(requested) != requested or requested < 1:
        raise ValueError(f"workers must be a whole number >= 1, got {requested!r}")
    if requested > cpus:
        return cpus, f"{requested} workers asked for, {cpus} used: the usable CPUs here"
    return int(requested), None


def pool_context():
    """The multiprocessing context of a worker pool: fork where the platform has it (workers
    start in milliseconds and inherit the imports, meshes and caches), else the default."""
    if "fork" in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("fork")
    return multiprocessing.get_context()


@contextlib.contextmanager
def frozen_heap():
    """Keep the objects that exist now out of the garbage collector's passes while inside.

    A parallel job makes many small tracked objects (bag analysis about 20 per message, and
    keeps a chunk's worth); every full collection then walks the whole heap, some 130,000
    objects of numpy, trimesh, rosbags and the meshes. Unpickling a bag analysis's 6,602-message
    chunk took 41 ms with the heap walked and 11.5 ms frozen (:func:`gc.freeze`), in one run.
    Frozen before the workers fork, the heap also stays shared with them, as the :mod:`gc`
    documentation advises. Nothing is frozen if the caller froze objects already.
    """
    if gc.get_freeze_count():
        yield
        return
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()


@contextlib.contextmanager
def stop_on_signals():
    """An event set by SIGINT or SIGTERM while inside (the previous handlers come back after).

    A long job checks the event and stops in order: the ROS node ends its spin loop before it
    takes rclpy down (rclpy's own handlers shut the context down under a running callback,
    which then fails to publish with a traceback); bag analysis keeps what it wrote as PARTIAL.
    """
    stop = threading.Event()
    handlers = {}
    for signum in (signal.SIGINT, signal.SIGTERM):
        handlers[signum] = signal.signal(signum, lambda *_: stop.set())
    try:
        yield stop
    finally:
        for signum, handler in handlers.items():
            signal.signal(signum, handler)
