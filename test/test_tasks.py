"""The chunk engine (adbsat_ros.tasks): a run stopped mid-way ends its local workers, a killed
worker's chunks are computed again; by default a job starts in this process and starts workers
only for a rest that pays."""

from __future__ import annotations

import multiprocessing
import os
import signal
import threading
import time

import pytest

from adbsat_ros.processes import usable_cpus


class SlowJob:
    """Chunk 0 returns at once; the others run until their worker is ended."""

    key = "stopped-run"

    def setup(self):
        return self

    def evaluate(self, chunk):
        if chunk:
            time.sleep(3600.0)  # (ended by the stop, never reached in full)
        return chunk


def test_a_stopped_run_ends_its_workers():
    """A run on two local workers stopped after its first result: the chunks running are
    dropped at once, their workers ended."""
    from adbsat_ros.tasks import run_chunks

    stop = threading.Event()
    done, workers = [], []

    def take(index, result):
        done.append(result)
        workers.extend(multiprocessing.active_children())
        stop.set()

    report = run_chunks(SlowJob(), {0: 0, 1: 1, 2: 2}, take, workers=2, stop=stop)
    assert report.stopped and done == [0] and len(workers) == 2
    assert not [p for p in workers if p.is_alive()]


class DyingJob:
    """Chunks of numbers squared; chunk 1 kills its worker process the first ``deaths`` times."""

    key = "dying"

    def __init__(self, folder, deaths: int):
        self.folder, self.deaths = folder, deaths

    def setup(self):
        return self

    def evaluate(self, chunk):
        marks = sorted(self.folder.iterdir())
        if chunk == 1 and len(marks) < self.deaths:
            (self.folder / str(len(marks))).touch()
            os.kill(os.getpid(), signal.SIGKILL)
        return chunk * chunk


@pytest.mark.skipif(usable_cpus() < 2, reason="needs two usable CPUs")
def test_a_killed_workers_chunks_are_computed_again_and_a_chunk_that_always_kills_fails(tmp_path):
    from adbsat_ros.tasks import MAX_RETRIES, run_chunks

    done = {}
    report = run_chunks(
        DyingJob(tmp_path, 2), {i: i for i in range(6)}, done.__setitem__, workers=2
    )
    assert done == {i: i * i for i in range(6)} and report.computed == 6
    again = tmp_path / "again"
    again.mkdir()
    with pytest.raises(RuntimeError, match=f"^chunk 1 failed {MAX_RETRIES + 2} times, the last in"):
        run_chunks(DyingJob(again, 100), {0: 0, 1: 1}, done.__setitem__, workers=2)
    assert len(list(again.iterdir())) == MAX_RETRIES + 2


@pytest.mark.skipif(usable_cpus() < 2, reason="needs two usable CPUs")
def test_the_chunk_named_is_the_one_that_kills_not_one_pending_beside_it(tmp_path):
    """Every chunk pending when a pool breaks is charged; one charged too often is tried alone."""
    from adbsat_ros.tasks import MAX_RETRIES, run_chunks

    done = {}
    with pytest.raises(RuntimeError, match=f"^chunk 1 failed {MAX_RETRIES + 2} times, the last in"):
        run_chunks(DyingJob(tmp_path, 100), {i: i for i in range(8)}, done.__setitem__, workers=2)
    assert len(list(tmp_path.iterdir())) == MAX_RETRIES + 2
    assert 1 not in done and done == {i: i * i for i in done}


class SquareJob:
    """Chunks of numbers squared, after ``pause`` [s] each."""

    key = "squares"

    def __init__(self, pause: float = 0.0):
        self.pause = pause

    def setup(self):
        return self

    def evaluate(self, chunk):
        time.sleep(self.pause)
        return chunk * chunk


def counted_pools(monkeypatch, allowed: bool) -> list:
    """The worker counts of the pools started from now on (refused unless ``allowed``)."""
    from adbsat_ros import tasks

    started = []
    real = tasks._run_in_pool

    def run_in_pool(job, chunks, on_result, count, *rest):
        started.append(count)
        assert allowed, "a pool of workers was started"
        return real(job, chunks, on_result, count, *rest)

    monkeypatch.setattr(tasks, "_run_in_pool", run_in_pool)
    return started


def test_workers_are_worth_starting_only_for_a_rest_longer_than_their_start():
    from adbsat_ros.tasks import worth_workers

    assert worth_workers(10.0, 2.0, 2) and not worth_workers(4.0, 2.0, 2)
    assert not worth_workers(100.0, 2.0, 1)  # (one worker is this process)
    assert worth_workers(4.0, 2.5, 4) and not worth_workers(4.0, 2.5, 2)


def test_a_small_job_runs_in_this_process_by_default(monkeypatch):
    """The default worker count starts no cluster for chunks of microseconds; the same results."""
    from adbsat_ros.tasks import run_chunks

    started = counted_pools(monkeypatch, allowed=False)
    done = {}
    report = run_chunks(SquareJob(), {i: i for i in range(20)}, done.__setitem__)
    assert done == {i: i * i for i in range(20)} and started == []
    assert report.workers == 1 and report.here == report.computed == 20


@pytest.mark.skipif(usable_cpus() < 2, reason="needs two usable CPUs")
def test_workers_take_the_rest_once_they_pay_and_an_explicit_count_uses_them(monkeypatch):
    """By default, chunks are timed here and the rest goes to a pool of workers once it pays (its
    start taken as free here); an explicit ``workers=2`` starts one at once."""
    from adbsat_ros import tasks

    monkeypatch.setattr(tasks, "POOL_START_S", 0.0)
    started = counted_pools(monkeypatch, allowed=True)
    done = {}
    report = tasks.run_chunks(SquareJob(0.2), {i: i for i in range(8)}, done.__setitem__)
    assert done == {i: i * i for i in range(8)} and started == [2]
    assert report.workers == 2 and report.here == 2 and report.computed == 8
    done.clear()
    report = tasks.run_chunks(SquareJob(), {i: i for i in range(3)}, done.__setitem__, workers=2)
    assert done == {i: i * i for i in range(3)} and started == [2, 2]
    assert report.workers == 2 and report.here == 0


class CubeSetup:
    """A set-up built before the run: chunks cubed, where the job's own set-up squares them."""

    def evaluate(self, chunk):
        return chunk**3


@pytest.mark.parametrize("workers", [1, 2, None])
def test_a_set_up_built_already_is_taken_here_and_by_forked_workers(workers):
    from adbsat_ros.tasks import run_chunks

    job = SquareJob()
    job.key = f"prebuilt {workers}"
    results = {}
    report = run_chunks(
        job,
        {i: i for i in range(6)},
        results.__setitem__,
        workers=workers,
        setup=CubeSetup(),
    )
    assert report.computed == 6
    assert results == {i: i**3 for i in range(6)}
