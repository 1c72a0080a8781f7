"""``adbsat-ros bag play`` and ``bag record``: live rosbag tools (rclpy imported when they run)."""

from __future__ import annotations

import sys

from adbsat_ros.bags.io import BagError
from adbsat_ros.cli.options import (
    CommandFailed,
    add_qos_depth,
    add_storage,
    errors_as,
    flag,
    non_negative_int,
    option,
    positive_float,
    ros_module,
)
from adbsat_ros.processes import stop_on_signals


def configure_play(play) -> None:
    """Configure ``bag play``."""
    play.description = (
        "Publish the messages of a rosbag2 bag (.mcap or .db3) on their topics, unchanged "
        "(header stamps as recorded), spaced as recorded and scaled by --rate. Needs rclpy. "
        "Discovery stays on this machine unless ROS_AUTOMATIC_DISCOVERY_RANGE is set."
    )
    play.add_argument("bag", help="rosbag2 bag directory (or its .mcap/.db3 file)")
    help = "playback speed factor (default 1: as recorded; 2: twice as fast)"
    option(play, "--rate", help, positive_float, default=1.0)
    help = "start again from the beginning until Ctrl-C (stamps go back in time at each restart)"
    flag(play, "--loop", help)
    option(play, "--topics", "play only these topics (default: all)", nargs="+", metavar="TOPIC")
    help = "wait until every played topic has N subscribers before starting"
    option(play, "--wait-for-subscribers", help, non_negative_int, default=0, metavar="N")
    help = "give up waiting for subscribers after S seconds (default 30)"
    option(play, "--wait-timeout", help, positive_float, default=30.0, metavar="S")
    add_qos_depth(play, "(reliable) publishers")
    play.set_defaults(func=run_play, command="bag play")


def configure_record(record) -> None:
    """Configure ``bag record``."""
    record.description = (
        "Subscribe to the given topics and write their messages (serialized, as received) into "
        "a new rosbag2 bag, stamped with the receive time. A topic's type is taken from the "
        "graph once a publisher appears, or given as TOPIC:TYPE. Stops after --duration or on "
        "Ctrl-C; the bag is complete either way (also on SIGTERM). Needs rclpy."
    )
    record.add_argument("out", metavar="OUT", help="bag directory to create (must not exist)")
    help = "topics to record, each /name or /name:package/msg/Type"
    option(record, "--topics", help, nargs="+", required=True, metavar="TOPIC")
    add_storage(record, "storage format")
    help = "stop after S seconds (default: at Ctrl-C)"
    option(record, "--duration", help, positive_float, default=None, metavar="S")
    add_qos_depth(record, "subscriptions")
    record.set_defaults(func=run_record, command="bag record")


def _log(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def _counts(counter) -> str:
    return ", ".join(f"{topic} {n}" for topic, n in sorted(counter.items())) or "none"


def _run_live(module: str, function: str, *args, **options):
    """Run ``adbsat_ros.ros.<module>.<function>(*args, **options)``; a BagError is CommandFailed."""
    run = getattr(ros_module(module), function)
    with errors_as(CommandFailed, BagError), stop_on_signals() as stop:
        return run(*args, **options, stop=stop, log=_log)


def run_play(args) -> int:
    """Run ``bag play``; the exit status."""
    summary = _run_live(
        "bag_play",
        "play",
        args.bag,
        rate=args.rate,
        loop=args.loop,
        topics=args.topics,
        wait_for_subscribers=args.wait_for_subscribers,
        wait_timeout=args.wait_timeout,
        qos_depth=max(1, args.qos_depth),
    )
    how = "stopped" if summary.interrupted else "done"
    print(
        f"{how}: published {summary.total} messages ({_counts(summary.published)}) "
        f"in {summary.wall_seconds:.1f} s, {summary.passes} pass(es) through the bag"
    )
    return 0


def run_record(args) -> int:
    """Run ``bag record``; the exit status."""
    summary = _run_live(
        "bag_record",
        "record",
        args.out,
        args.topics,
        storage=args.storage,
        duration=args.duration,
        qos_depth=max(1, args.qos_depth),
    )
    print(
        f"wrote {summary.path} ({summary.storage}): {summary.total} messages "
        f"({_counts(summary.recorded)}) in {summary.wall_seconds:.1f} s"
    )
    if summary.missing:
        print(
            f"warning: no publisher ever appeared on {', '.join(summary.missing)}; nothing "
            "recorded from it",
            file=sys.stderr,
        )
    return 0
