"""``adbsat-ros bag play`` and ``adbsat-ros bag record``: live rosbag tools (need rclpy).

Configured into the ``bag`` command group by :mod:`adbsat_ros.cli.bag`; rclpy and the ROS tools
are imported only when one of these runs, so the rest of the command line works without ROS
installed (and starts without paying for it). Discovery stays on this machine unless
ROS_AUTOMATIC_DISCOVERY_RANGE says otherwise.
"""

from __future__ import annotations

import importlib
import os
import sys

from adbsat_ros.bags.io import BagError
from adbsat_ros.cli.options import non_negative_int, positive_float
from adbsat_ros.processes import stop_on_signals


class RosNotAvailable(RuntimeError):
    """rclpy or the message packages cannot be imported."""


def configure_play(play) -> None:
    """Give the ``bag play`` parser its description and options."""
    play.description = (
        "Publish the messages of a rosbag2 bag (.mcap or .db3) on their topics, unchanged "
        "(header stamps as recorded), spaced as recorded and scaled by --rate. Needs rclpy. "
        "Discovery stays on this machine unless ROS_AUTOMATIC_DISCOVERY_RANGE is set."
    )
    play.add_argument("bag", help="rosbag2 bag directory (or its .mcap/.db3 file)")
    play.add_argument(
        "--rate",
        type=positive_float("--rate"),
        default=1.0,
        help="playback speed factor (default 1: as recorded; 2: twice as fast)",
    )
    play.add_argument(
        "--loop",
        action="store_true",
        help="start again from the beginning until Ctrl-C (stamps go back in time at each restart)",
    )
    play.add_argument(
        "--topics", nargs="+", metavar="TOPIC", help="play only these topics (default: all)"
    )
    play.add_argument(
        "--wait-for-subscribers",
        type=non_negative_int("--wait-for-subscribers"),
        default=0,
        metavar="N",
        help="wait until every played topic has N subscribers before starting",
    )
    play.add_argument(
        "--wait-timeout",
        type=positive_float("--wait-timeout"),
        default=30.0,
        metavar="S",
        help="give up waiting for subscribers after S seconds (default 30)",
    )
    play.add_argument(
        "--qos-depth",
        type=int,
        default=1000,
        metavar="N",
        help="history depth of the (reliable) publishers (default 1000)",
    )
    play.set_defaults(func=run_play, command="bag play")


def configure_record(record) -> None:
    """Give the ``bag record`` parser its description and options."""
    record.description = (
        "Subscribe to the given topics and write their messages (serialized, as received) into "
        "a new rosbag2 bag, stamped with the receive time. A topic's type is taken from the "
        "graph once a publisher appears, or given as TOPIC:TYPE. Stops after --duration or on "
        "Ctrl-C; the bag is complete either way (also on SIGTERM). Needs rclpy."
    )
    record.add_argument("out", metavar="OUT", help="bag directory to create (must not exist)")
    record.add_argument(
        "--topics",
        nargs="+",
        required=True,
        metavar="TOPIC",
        help="topics to record, each /name or /name:package/msg/Type",
    )
    record.add_argument(
        "--storage",
        choices=("mcap", "sqlite3"),
        default="mcap",
        help="storage format (default mcap)",
    )
    record.add_argument(
        "--duration",
        type=positive_float("--duration"),
        default=None,
        metavar="S",
        help="stop after S seconds (default: at Ctrl-C)",
    )
    record.add_argument(
        "--qos-depth",
        type=int,
        default=1000,
        metavar="N",
        help="history depth of the subscriptions (default 1000)",
    )
    record.set_defaults(func=run_record, command="bag record")


def ros_module(name: str):
    """``adbsat_ros.ros.<name>``, or RosNotAvailable naming what is missing."""
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    try:
        return importlib.import_module(f"adbsat_ros.ros.{name}")
    except ImportError as exc:
        raise RosNotAvailable(
            "needs the ROS 2 Python packages (rclpy and messages), which cannot be imported: "
            f"{exc}; install them with: pip install 'adbsat_ros[ros]'"
        ) from None


def _log(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def _counts(counter) -> str:
    return ", ".join(f"{topic} {n}" for topic, n in sorted(counter.items())) or "none"


def run_play(args) -> int:
    """Run ``bag play``; returns the exit status."""
    try:
        bag_play = ros_module("bag_play")
        with stop_on_signals() as stop:
            summary = bag_play.play(
                args.bag,
                rate=args.rate,
                loop=args.loop,
                topics=args.topics,
                wait_for_subscribers=args.wait_for_subscribers,
                wait_timeout=args.wait_timeout,
                qos_depth=max(1, args.qos_depth),
                stop=stop,
                log=_log,
            )
    except (RosNotAvailable, BagError) as exc:
        print(f"adbsat-ros bag play: error: {exc}", file=sys.stderr)
        return 1
    how = "stopped" if summary.interrupted else "done"
    print(
        f"{how}: published {summary.total} messages ({_counts(summary.published)}) "
        f"in {summary.wall_seconds:.1f} s, {summary.passes} pass(es) through the bag"
    )
    return 0


def run_record(args) -> int:
    """Run ``bag record``; returns the exit status."""
    try:
        bag_record = ros_module("bag_record")
        with stop_on_signals() as stop:
            summary = bag_record.record(
                args.out,
                args.topics,
                storage=args.storage,
                duration=args.duration,
                qos_depth=max(1, args.qos_depth),
                stop=stop,
                log=_log,
            )
    except (RosNotAvailable, BagError) as exc:
        print(f"adbsat-ros bag record: error: {exc}", file=sys.stderr)
        return 1
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
