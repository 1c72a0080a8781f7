"""The chunk engine (adbsat_ros.tasks): a run stopped mid-way ends its local workers for good."""

from __future__ import annotations

import threading
import time


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
