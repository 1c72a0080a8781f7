"""The chunk engine (adbsat_ros.tasks): a run stopped mid-way ends its local workers for good;
by default a job starts in this process and starts workers only for a rest that pays."""

from __future__ import annotations

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


def test_a_stopped_run_starts_no_worker_again(monkeypatch):
    """A run on two local workers stopped after its first result: its workers are ended, and
    the nannies start none in their place (one started then would outlive the cluster)."""
    from distributed import Client, Nanny

    from adbsat_ros.tasks import run_chunks

    started = []
    instantiate = Nanny.instantiate

    async def counting(self):
        started.append(self.name)
        return await instantiate(self)

    monkeypatch.setattr(Nanny, "instantiate", counting)
    close = Client.close

    def late_close(self, *args, **kwargs):
        # as on a loaded machine: the nannies see their workers die before the cluster closes
        time.sleep(2.0)
        return close(self, *args, **kwargs)

    monkeypatch.setattr(Client, "close", late_close)
    stop = threading.Event()
    done = []

    def take(index, result):
        done.append(result)
        stop.set()

    report = run_chunks(SlowJob(), {0: 0, 1: 1, 2: 2}, take, workers=2, stop=stop)
    assert report.stopped and done == [0]
    assert sorted(started) == [0, 1], started


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


def counted_clusters(monkeypatch, allowed: bool) -> list:
    """The worker counts of the LocalClusters started from now on (refused unless ``allowed``)."""
    from adbsat_ros import tasks

    started = []
    real = tasks.local_cluster

    def local_cluster(count):
        started.append(count)
        assert allowed, "a LocalCluster was started"
        return real(count)

    monkeypatch.setattr(tasks, "local_cluster", local_cluster)
    return started


def test_workers_are_worth_starting_only_for_a_rest_longer_than_their_start():
    from adbsat_ros.tasks import worth_workers

    assert worth_workers(10.0, 2.0, 2) and not worth_workers(4.0, 2.0, 2)
    assert not worth_workers(100.0, 2.0, 1)  # (one worker is this process)
    assert worth_workers(4.0, 2.5, 4) and not worth_workers(4.0, 2.5, 2)


def test_a_small_job_runs_in_this_process_by_default(monkeypatch):
    """The default worker count starts no cluster for chunks of microseconds; the same results."""
    from adbsat_ros.tasks import run_chunks

    started = counted_clusters(monkeypatch, allowed=False)
    done = {}
    report = run_chunks(SquareJob(), {i: i for i in range(20)}, done.__setitem__)
    assert done == {i: i * i for i in range(20)} and started == []
    assert report.workers == 1 and report.here == report.computed == 20


@pytest.mark.skipif(usable_cpus() < 2, reason="needs two usable CPUs")
def test_workers_take_the_rest_once_they_pay_and_an_explicit_count_uses_them(monkeypatch):
    """By default, chunks are timed here and the rest goes to a LocalCluster once it pays (its
    start taken as free here); an explicit ``workers=2`` starts one at once."""
    from adbsat_ros import tasks

    monkeypatch.setattr(tasks, "CLUSTER_START_S", 0.0)
    started = counted_clusters(monkeypatch, allowed=True)
    done = {}
    report = tasks.run_chunks(SquareJob(0.2), {i: i for i in range(8)}, done.__setitem__)
    assert done == {i: i * i for i in range(8)} and started == [2]
    assert report.workers == 2 and report.here == 2 and report.computed == 8
    done.clear()
    report = tasks.run_chunks(SquareJob(), {i: i for i in range(3)}, done.__setitem__, workers=2)
    assert done == {i: i * i for i in range(3)} and started == [2, 2]
    assert report.workers == 2 and report.here == 0
