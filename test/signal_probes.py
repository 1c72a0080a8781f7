"""Commands started as their console scripts start them, and signalled at a chosen point of their
run: what the signal tests share. Every wait is for an event (a handler installed, files mapped,
children forked), with a time-out that only catches a hang."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: Seconds after which a wait is a hang.
HANG_S = 60.0


def console_script(name: str) -> list:
    """The command that runs console script ``name`` as setup.py declares it (what the installed
    script does: import the function, call it, exit with its status)."""
    text = (ROOT / "setup.py").read_text(encoding="utf-8")
    module, function = re.search(rf'"{re.escape(name)} = ([\w.]+):(\w+)"', text).groups()
    code = f"import sys; from {module} import {function}; sys.exit({function}())"
    return [sys.executable, "-c", code]


def _status(pid: int, field: str) -> str | None:
    try:
        with open(f"/proc/{pid}/status", encoding="ascii") as stream:
            for line in stream:
                if line.startswith(field + ":"):
                    return line.split()[1]
    except OSError:
        return None
    return None


def handles_sigterm(pid: int) -> bool:
    """Whether the process catches SIGTERM: the command's own handler is installed (Python
    catches SIGINT by itself, SIGTERM never)."""
    mask = _status(pid, "SigCgt")
    return mask is not None and bool(int(mask, 16) & (1 << (signal.SIGTERM - 1)))


def ignores(pid: int, signum: int) -> bool:
    """Whether the process ignores signal ``signum`` (SIG_IGN)."""
    mask = _status(pid, "SigIgn")
    return mask is not None and bool(int(mask, 16) & (1 << (signum - 1)))


def mapped_files(pid: int) -> int:
    """The files the process has mapped (shared libraries, extension modules): more as its
    imports go on."""
    try:
        with open(f"/proc/{pid}/maps", encoding="ascii", errors="replace") as stream:
            return len({line.split()[-1] for line in stream if "/" in line})
    except OSError:
        return 0


def cpu_seconds(pid: int) -> float:
    """CPU time the process has used [s] (user + system)."""
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii") as stream:
            fields = stream.read().rsplit(")", 1)[1].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def descendants(pid: int) -> set:
    """The pids of every process below ``pid`` (children, their children...)."""
    parents = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/stat", encoding="ascii") as stream:
                    parents[int(entry)] = int(stream.read().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                pass
    found, todo = set(), [pid]
    while todo:
        parent = todo.pop()
        for child, its_parent in parents.items():
            if its_parent == parent and child not in found:
                found.add(child)
                todo.append(child)
    return found


def alive(pid: int) -> bool:
    """Whether ``pid`` is a process that has not ended (a zombie has ended)."""
    state = _status(pid, "State")
    return state is not None and state != "Z"


class Run:
    """A command started with its output in files (a pipe could fill and stall it)."""

    def __init__(self, cmd, **popen):
        self.out = tempfile.TemporaryFile("w+")
        self.err = tempfile.TemporaryFile("w+")
        self.proc = subprocess.Popen(cmd, stdout=self.out, stderr=self.err, text=True, **popen)

    def wait_for(self, predicate, what: str, required: bool = True) -> bool:
        """Wait until ``predicate()``; False if the process ended first. After :data:`HANG_S`
        a ``required`` event fails the test; any other is given up (True)."""
        deadline = time.monotonic() + HANG_S
        while not predicate():
            if self.proc.poll() is not None:
                return False
            if time.monotonic() > deadline:
                assert not required, f"no {what} within {HANG_S} s: {self.stderr()}"
                return True
            time.sleep(0.001)
        return True

    def finish(self) -> tuple:
        """``(exit status, stdout, stderr)`` once it ends (killed if it hangs)."""
        try:
            self.proc.wait(timeout=HANG_S)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
            raise AssertionError(f"still running {HANG_S} s after the signal: {self.stderr()}")
        return self.proc.returncode, self.stdout(), self.stderr()

    def stdout(self) -> str:
        self.out.seek(0)
        return self.out.read()

    def stderr(self) -> str:
        self.err.seek(0)
        return self.err.read()

    def kill(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()


def signal_in_start_up(cmd, more_files: int, signum=signal.SIGINT, **popen):
    """Start ``cmd``, and send ``signum`` once it handles signals and has mapped ``more_files``
    more files (0: at once; later and later in its start-up with more). ``(exit status,
    stdout, stderr)``, or None if it ended before the signal. (A command that maps fewer files
    in all is signalled while it works, once :data:`HANG_S` have passed.)"""
    run = Run(cmd, **popen)
    try:
        pid = run.proc.pid
        if not run.wait_for(lambda: handles_sigterm(pid), "signal handler"):
            return None
        base = mapped_files(pid)
        if not run.wait_for(lambda: mapped_files(pid) >= base + more_files, "", required=False):
            return None
        run.proc.send_signal(signum)
        return run.finish()
    finally:
        run.kill()


def wait_gone(pids) -> set:
    """Wait until none of ``pids`` is alive; those still alive after :data:`HANG_S`."""
    deadline = time.monotonic() + HANG_S
    left = set(pids)
    while left and time.monotonic() < deadline:
        left = {p for p in left if alive(p)}
        time.sleep(0.01)
    return left
