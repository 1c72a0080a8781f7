"""The console scripts ``adbsat_node`` and ``adbsat_orbit_publisher``.

Each handles SIGINT and SIGTERM before importing rclpy, so a signal during start-up ends it too.
"""

from __future__ import annotations

import sys

from adbsat_ros.processes import (
    Interrupted,
    exit_now,
    handle_signals,
    raising_signals,
    signal_name,
)


def adbsat_node(args=None) -> int:
    """Console script ``adbsat_node`` (:func:`adbsat_ros.ros.node.main`)."""
    with handle_signals():
        try:
            with raising_signals():
                from adbsat_ros.ros.node import main
        except Interrupted:
            return _stopped("adbsat_node")
        return main(args)


def adbsat_orbit_publisher(argv=None) -> int:
    """Console script ``adbsat_orbit_publisher`` (:func:`adbsat_ros.ros.orbit_publisher.main`)."""
    with handle_signals():
        try:
            with raising_signals():
                from adbsat_ros.ros.orbit_publisher import main
        except Interrupted:
            return _stopped("adbsat_orbit_publisher")
        return main(argv)


def _stopped(name: str) -> int:
    print(f"{name}: stopped by {signal_name()}", file=sys.stderr)
    exit_now(0)  # (an import stopped half-way: the interpreter's clean-up could crash on it)
    return 0
