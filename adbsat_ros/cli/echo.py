"""``adbsat-ros echo TOPIC``: print a topic's messages (the node's wrench, coefficients,
acceleration, /diagnostics ...), for machines without the ``ros2`` command (needs rclpy)."""

from __future__ import annotations

import sys

from adbsat_ros.cli.bag_live import RosNotAvailable, ros_module
from adbsat_ros.cli.options import number, positive_float


def configure(p) -> None:
    """Give the ``echo`` subcommand's parser ``p`` its description and options."""
    p.description = (
        "Print the messages of a ROS 2 topic as `field: value` lines, each followed by ---, as "
        "`ros2 topic echo` does; the type is the one the graph gives the topic. Needs rclpy."
    )
    p.add_argument("topic", metavar="TOPIC", help="topic name, e.g. wrench or /diagnostics")
    p.add_argument(
        "--count",
        type=number("--count", integer=True, low=1),
        default=1,
        help="messages to print (default 1)",
    )
    p.add_argument(
        "--timeout",
        type=positive_float("--timeout"),
        default=5.0,
        help="seconds to wait for the topic and for each message (default 5)",
    )
    p.set_defaults(func=run)


def run(args) -> int:
    """Run ``adbsat-ros echo``; returns the exit status (1 if fewer messages came)."""
    try:
        tools = ros_module("graph_tools")
    except RosNotAvailable as exc:
        print(f"adbsat-ros echo: error: {exc}", file=sys.stderr)
        return 1
    try:
        printed = tools.echo(args.topic, args.count, args.timeout, print)
    except tools.ToolError as exc:
        print(f"adbsat-ros echo: error: {exc}", file=sys.stderr)
        return 1
    if printed < args.count:
        print(
            f"adbsat-ros echo: error: {printed} of {args.count} messages came within "
            f"{args.timeout:g} s of each other",
            file=sys.stderr,
        )
        return 1
    return 0
