"""The console scripts ``adbsat_node`` and ``adbsat_orbit_publisher``.

Each handles SIGINT and SIGTERM before importing rclpy, so a signal during start-up ends it too.
"""

from __future__ import annotations

import importlib
import sys

from adbsat_ros.processes import Interrupted, exit_now, handle_signals, raising_signals, signal_name


def adbsat_node(args=None) -> int:
    """Console script ``adbsat_node`` (:func:`adbsat_ros.ros.node.main`)."""
    return _script("adbsat_node", "node", args)


def adbsat_orbit_publisher(argv=None) -> int:
    """Console script ``adbsat_orbit_publisher`` (:func:`adbsat_ros.ros.orbit_publisher.main`)."""
    return _script("adbsat_orbit_publisher", "orbit_publisher", argv)


def _script(name: str, module: str, argv) -> int:
    """``adbsat_ros.ros.<module>.main(argv)``, imported under the signal handlers."""
    with handle_signals():
        try:
            with raising_signals():
                main = importlib.import_module(f"adbsat_ros.ros.{module}").main
        except Interrupted:
            print(f"{name}: stopped by {signal_name()}", file=sys.stderr)
            # (an import stopped half-way: the interpreter's clean-up could crash on it)
            exit_now(0)
            return 0
        return main(argv)
