"""Waiting for events in tests that run commands as processes: no test depends on how fast the
machine is, so a test waits for what it needs to see (a file, a worker process) and only a hang
ends the wait."""

from __future__ import annotations

import os
import time

#: Seconds to wait for an event before calling it a hang (the wait ends when the event comes).
HANG_TIMEOUT = 120.0


def wait_for(predicate, process=None, timeout: float = HANG_TIMEOUT, poll: float = 0.05) -> bool:
    """Poll ``predicate()`` until it is true (True), ``process`` (a Popen) has ended or
    ``timeout`` seconds have passed (False)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        if process is not None and process.poll() is not None:
            return predicate()
        time.sleep(poll)
    return False


def child_pids(pid: int) -> list:
    """The process ids whose parent is ``pid`` (from /proc)."""
    children = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat", encoding="ascii", errors="replace") as stream:
                fields = stream.read().rsplit(")", 1)[1].split()
        except OSError:  # (gone meanwhile)
            continue
        if int(fields[1]) == pid:
            children.append(int(entry))
    return children
