"""Processes of the long jobs: worker counts and start method, workers dying with their parent,
the heap frozen for the garbage collector, and SIGINT/SIGTERM handling (docs/architecture.md,
"Signals and worker processes")."""

from __future__ import annotations

import contextlib
import ctypes
import gc
import os
import signal
import sys
import threading

#: Exit status of a command that SIGINT or SIGTERM stopped before it finished (its outputs so far
#: kept as its documentation says); the node and the tools that run until stopped exit with 0.
INTERRUPTED_STATUS = 1

#: The signals a command handles (a stop asked for).
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)

#: Seconds after which a stop that came during an import is tried again.
IMPORT_RETRY_S = 0.005


def umask() -> int:
    """The process's umask (read by setting it and setting it back)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def usable_cpus() -> int:
    """The CPUs this process may run on (its affinity mask where the platform has one)."""
    try:
        return len(os.sched_getaffinity(0)) or 1
    except AttributeError:  # (no affinity masks on this platform)
        return os.cpu_count() or 1


def worker_count(requested: int | None) -> tuple:
    """``(workers, note)``: ``requested`` (default every usable CPU), at most :func:`usable_cpus`.
    ValueError: a count not a whole number >= 1."""
    cpus = usable_cpus()
    if requested is None:
        return cpus, None
    if isinstance(requested, bool) or int(requested) != requested or requested < 1:
        raise ValueError(f"workers must be a whole number >= 1, got {requested!r}")
    if requested > cpus:
        return cpus, f"{requested} workers asked for, {cpus} used: the usable CPUs here"
    return int(requested), None


def pool_context():
    """A worker pool's multiprocessing context: fork where there is one, else the default."""
    import multiprocessing  # (not at start-up)

    if "fork" in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("fork")
    return multiprocessing.get_context()


@contextlib.contextmanager
def frozen_heap():
    """Keep the objects that exist now out of the garbage collector's passes while inside."""
    if gc.get_freeze_count():
        yield
        return
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()


class Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM raised in the main thread by :func:`handle_signals`."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


class _Signals:
    """The handler of :func:`handle_signals`: sets :attr:`event`, raises where allowed."""

    def __init__(self):
        self.pid = os.getpid()
        self.event = threading.Event()
        self.signum = None
        self.armed = False
        self.in_order = 0

    def __call__(self, signum, frame):
        if os.getpid() != self.pid:  # a process forked from the command: a worker
            as_worker(signum)
            return
        first = self.signum is None
        if first:
            self.signum = signum
        self.event.set()
        if first and self.armed and not self.in_order:
            self._raise(frame)

    def _raise(self, frame) -> None:
        """Raise :class:`Interrupted`, or retry by SIGALRM while ``frame``'s stack imports."""
        if _importing(frame):  # an extension importing from C may print or abort on a raise
            signal.signal(signal.SIGALRM, self._again)
            signal.siginterrupt(signal.SIGALRM, False)  # (no system call fails on it)
            signal.setitimer(signal.ITIMER_REAL, IMPORT_RETRY_S)
            return
        raise Interrupted(self.signum)

    def _again(self, signum, frame) -> None:
        if self.armed and not self.in_order:
            self._raise(frame)


def _importing(frame) -> bool:
    """Whether ``frame`` or one that called it is the import machinery's."""
    while frame is not None:
        if frame.f_code.co_filename.startswith("<frozen importlib"):
            return True
        frame = frame.f_back
    return False


def as_worker(signum: int) -> None:
    """A worker ignores SIGINT (sent to the process group; the parent decides), dies of SIGTERM."""
    if signum == signal.SIGTERM:
        signal.signal(signum, signal.SIG_DFL)
        os.kill(os.getpid(), signum)


_SIGNALS: list = []


def _signals() -> _Signals | None:
    """The handler of :func:`handle_signals` in this process, or None."""
    return _SIGNALS[-1] if _SIGNALS and _SIGNALS[-1].pid == os.getpid() else None


def signal_name() -> str | None:
    """The name of the first signal :func:`handle_signals` caught (``SIGINT``), or None."""
    signals = _signals()
    if signals is None or signals.signum is None:
        return None
    return signal.Signals(signals.signum).name


@contextlib.contextmanager
def handle_signals():
    """SIGINT and SIGTERM handled for a whole command, whose ``main`` enters this first thing.
    Signals raise only inside :func:`raising_signals`; the previous handlers come back after."""
    if _signals() is not None or threading.current_thread() is not threading.main_thread():
        yield
        return
    signals = _Signals()
    _SIGNALS.append(signals)
    previous = {}
    try:
        for signum in STOP_SIGNALS:
            previous[signum] = signal.signal(signum, signals)
        previous[signal.SIGALRM] = signal.getsignal(signal.SIGALRM) or signal.SIG_DFL  # (_raise)
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        _SIGNALS.remove(signals)


def exit_now(status: int) -> None:
    """End the program with ``status`` at once, output flushed (an import may be half-done)."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    os._exit(status)


@contextlib.contextmanager
def raising_signals():
    """Under :func:`handle_signals`: a signal raises :class:`Interrupted` while inside."""
    signals = _signals()
    if signals is None:
        yield
        return
    if signals.event.is_set():
        raise Interrupted(signals.signum or signal.SIGINT)
    saved = signals.armed, signals.in_order
    signals.armed, signals.in_order = True, 0
    try:
        yield
    finally:
        signals.armed, signals.in_order = saved


@contextlib.contextmanager
def interruptible():
    """Inside :func:`stop_on_signals`, a stretch with nothing to keep: a signal ends it."""
    signals = _signals()
    if signals is None:
        yield
        return
    with raising_signals():
        yield
    if signals.event.is_set():  # (a library caught the Interrupted raised inside)
        raise Interrupted(signals.signum or signal.SIGINT)


@contextlib.contextmanager
def stop_on_signals():
    """An event set by SIGINT/SIGTERM while inside (they raise nothing); a long job checks it at its
    boundaries and stops in order (docs/architecture.md, "Signals and worker processes")."""
    signals = _signals()
    if signals is not None:
        signals.in_order += 1
        try:
            yield signals.event
        finally:
            signals.in_order -= 1
        return
    stop = threading.Event()
    handlers = {signum: signal.signal(signum, lambda *_: stop.set()) for signum in STOP_SIGNALS}
    try:
        yield stop
    finally:
        for signum, handler in handlers.items():
            signal.signal(signum, handler)


def run_until_stopped(program: str, body, argv=None) -> int:
    """Run ``body(argv)`` under :func:`handle_signals`; its exit status (0 after a signal)."""
    with handle_signals():
        interrupted = False
        try:
            with raising_signals():
                status = body(argv)
        except Interrupted:
            status, interrupted = 0, True
        if signal_name() is None:
            return status
        print(f"{program}: stopped by {signal_name()}", file=sys.stderr)
        if (interrupted or status) and argv is None:
            exit_now(0)
        return 0


#: ``prctl`` option of Linux: the signal a process gets when its parent dies.
PR_SET_PDEATHSIG = 1


def die_with_parent(parent: int, stops_to_parent: bool = False) -> None:
    """In a worker's initializer: die with ``parent`` even if it is SIGKILLed; SIGINT ignored."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    # stops_to_parent: the parent ends the job in order; a pool worker killed while it writes a
    # result to its pipe leaves half a message the pool waits for forever (a Dask nanny restarts)
    signal.signal(signal.SIGTERM, signal.SIG_IGN if stops_to_parent else signal.SIG_DFL)
    if sys.platform.startswith("linux"):
        with contextlib.suppress(OSError, AttributeError):  # (no prctl in this C library)
            ctypes.CDLL(None).prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL))
    if os.getppid() != parent:  # (it died before the parent-death signal was set)
        os._exit(1)
