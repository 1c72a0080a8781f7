"""The rclpy executor the node spins on, and spinning it until the process is told to stop."""

from __future__ import annotations

import io

import rclpy
from rclpy.executors import SingleThreadedExecutor

try:  # rclpy 7.1.5 and later (Jazzy wheels); older Jazzy builds lack it
    from rclpy.experimental import EventsExecutor
except ImportError:
    EventsExecutor = None


def make_executor(kind: str = "events", context=None):
    """An rclpy executor: ``"events"`` (EventsExecutor) or ``"single_threaded"`` (else ValueError).

    Spin it with :func:`spin_until_shutdown`: the EventsExecutor's own ``spin()`` in the Jazzy
    wheels busy-waits and ignores SIGINT/SIGTERM.
    """
    if kind not in ("events", "single_threaded"):
        raise ValueError(f"executor must be events or single_threaded, got {kind!r}")
    if kind == "events" and EventsExecutor is not None:
        try:
            return EventsExecutor(context=context)
        except (io.UnsupportedOperation, AttributeError, ValueError):
            pass  # (it enables faulthandler on sys.stderr: no real file in a notebook, capsys)
    return SingleThreadedExecutor(context=context)


def spin_until_shutdown(executor, context=None, stop=None, done=None) -> None:
    """Spin ``executor`` until its context shuts down, ``stop`` is set or ``done()`` is true."""
    while rclpy.ok(context=context) and not (stop is not None and stop.is_set()):
        if done is not None and done():
            return
        executor.spin_once(timeout_sec=0.2)
