"""Process pools of the parallel jobs (database builds, bag analysis): how workers start, and the
heap kept out of the garbage collector's passes while they run."""

from __future__ import annotations

import contextlib
import gc
import multiprocessing


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
