"""``adbsat-ros echo TOPIC``: print a topic's messages, as ``ros2 topic echo`` (needs rclpy)."""

from __future__ import annotations

from adbsat_ros.cli.options import (
    CommandFailed,
    add_timeout,
    errors_as,
    option,
    positive_int,
    ros_module,
)


def configure(p) -> None:
    """Configure ``adbsat-ros echo``."""
    p.description = (
        "Print the messages of a ROS 2 topic as `field: value` lines, each followed by ---, as "
        "`ros2 topic echo` does; the type is the one the graph gives the topic. Needs rclpy."
    )
    p.add_argument("topic", metavar="TOPIC", help="topic name, e.g. wrench or /diagnostics")
    option(p, "--count", "messages to print (default 1)", positive_int, default=1)
    add_timeout(p, "the topic and for each message")
    p.set_defaults(func=run)


def run(args) -> int:
    """Run ``adbsat-ros echo``; the exit status (1 if fewer messages came)."""
    tools = ros_module("graph_tools")
    with errors_as(CommandFailed, tools.ToolError):
        printed = tools.echo(args.topic, args.count, args.timeout, print)
    if printed < args.count:
        raise CommandFailed(
            f"{printed} of {args.count} messages came within {args.timeout:g} s of each other"
        )
    return 0
