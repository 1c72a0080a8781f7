"""``adbsat-ros param list|get|set NODE [NAME [VALUE]]``: as ``ros2 param`` (needs rclpy)."""

from __future__ import annotations

from adbsat_ros.cli.options import (
    CommandFailed,
    CommandLineError,
    add_timeout,
    errors_as,
    ros_module,
)


def configure(p) -> None:
    """Configure ``adbsat-ros param``."""
    p.description = (
        "List, get or set the parameters of a running ROS 2 node (e.g. adbsat_node) over its "
        "parameter services, as `ros2 param` does; a rejected value prints the node's reason. "
        "Needs rclpy; discovery stays on this machine unless ROS_AUTOMATIC_DISCOVERY_RANGE says "
        "otherwise."
    )
    p.add_argument("action", choices=("list", "get", "set"), help="what to do")
    p.add_argument("node", metavar="NODE", help="the node's name, e.g. adbsat_node (or /ns/name)")
    p.add_argument("name", metavar="NAME", nargs="?", help="parameter name (get, set)")
    p.add_argument(
        "value",
        metavar="VALUE",
        nargs="?",
        help="value for set, read as the parameter's declared type (the node is asked): 150, "
        "2e2, true, [0.1, 0, 0]; a string parameter takes the text as it is",
    )
    add_timeout(p, "the node")
    p.set_defaults(func=run)


def run(args) -> int:
    """Run ``adbsat-ros param``; the exit status (1: the node refuses or is absent)."""
    if args.action in ("get", "set") and args.name is None:
        raise CommandLineError(f"param {args.action}: NAME is needed")
    if args.action == "set" and args.value is None:
        raise CommandLineError("param set: VALUE is needed")
    if args.action == "list" and args.name is not None:
        raise CommandLineError("param list: takes no NAME")
    tools = ros_module("graph_tools")
    with errors_as(CommandFailed, tools.ToolError), errors_as(CommandLineError, tools.BadInput):
        if args.action == "list":
            for name, value in tools.list_parameters(args.node, args.timeout).items():
                print(f"{name}: {value!r}")
        elif args.action == "get":
            print(repr(tools.get_parameter(args.node, args.name, args.timeout)))
        else:
            value = tools.set_parameter(args.node, args.name, args.value, args.timeout)
            print(f"set {args.name} = {value!r}")
    return 0
