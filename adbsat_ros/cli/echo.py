"""``adbsat-ros echo TOPIC``: print a topic's messages, as ``ros2 topic echo`` (needs rclpy)."""

from __future__ import annotations

import functools
import sys

from adbsat_ros.cli.options import (
    CommandFailed,
    add_timeout,
    errors_as,
    option,
    positive_int,
    ros_module,
)
from adbsat_ros.processes import signal_name, stop_on_signals


def configure(p) -> None:
    """Configure ``adbsat-ros echo``."""
    p.description = (
        "Print the messages of a ROS 2 topic as `field: value` lines, each followed by ---, as "
        "`ros2 topic echo` does, until Ctrl-C (or --count messages); then the count and mean "
        "rate on stderr, as `ros2 topic hz`. The type is the one the graph gives the topic. "
        "Needs rclpy."
    )
    p.add_argument("topic", metavar="TOPIC", help="topic name, e.g. wrench or /diagnostics")
    option(p, "--count", "stop after this many messages (default: until Ctrl-C)", positive_int)
    add_timeout(p, "the topic, and with --count for each message")
    p.set_defaults(func=run)


def rate_summary(times) -> str:
    """``N messages, mean rate R Hz over T s`` of the arrival times [s] of the messages."""
    n = len(times)
    span = times[-1] - times[0] if n > 1 else 0.0
    if span <= 0.0:
        return f"{n} message{'' if n == 1 else 's'}"
    return f"{n} messages, mean rate {(n - 1) / span:.4g} Hz over {span:.3f} s"


def run(args) -> int:
    """Run ``adbsat-ros echo``; the exit status (1 if fewer than --count messages came)."""
    tools = ros_module("graph_tools")
    write = functools.partial(print, flush=True)  # (each message as it comes, also into a pipe)
    with stop_on_signals() as stop, errors_as(CommandFailed, tools.ToolError):
        times = tools.echo(args.topic, args.count, args.timeout, write, stop)
    stopped = f"stopped by {signal_name()}; " if stop.is_set() else ""
    print(f"adbsat-ros echo: {stopped}{rate_summary(times)}", file=sys.stderr)
    if args.count is not None and len(times) < args.count and not stop.is_set():
        raise CommandFailed(
            f"{len(times)} of {args.count} messages came within {args.timeout:g} s of each other"
        )
    return 0
