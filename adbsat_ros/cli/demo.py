"""``adbsat-ros demo``: run the ROS 2 node live on the bundled satellite, show its output."""

from __future__ import annotations

from adbsat_ros.cli.options import CommandFailed, flag, option, positive_float, ros_module
from adbsat_ros.processes import INTERRUPTED_STATUS


def configure(p) -> None:
    """Configure ``adbsat-ros demo``."""
    p.description = (
        "Start adbsat_node (bundled satellite, default parameters) in this process, publish a "
        "300 km circular orbit with a tumbling (or nadir-pointing) attitude to it live, print a "
        "line of its results every 0.5 s, and write a CSV and PNG plots. Needs rclpy. ROS "
        "discovery is limited to this machine unless ROS_AUTOMATIC_DISCOVERY_RANGE is set; the "
        "topics live under /adbsat_demo."
    )
    help = "wall seconds of live publishing (default 8)"
    option(p, "--duration", help, positive_float, default=8.0, metavar="S")
    help = "simulated seconds per wall second (default 10; attitudes always at 20 Hz wall)"
    option(p, "--speedup", help, positive_float, default=10.0, metavar="K")
    help = "tumbling at 1 deg/s (default) or nadir-pointing (the default with --articulated)"
    option(p, "--attitude", help, choices=("tumble", "nadir"), default=None)
    help = (
        "the bundled finned body (example-finned) instead, steering its four fins +-10 deg "
        "through joint_states: the table and the CSV add the fins' positions and hinge "
        "torques, and demo_hinge_torques.png plots them"
    )
    flag(p, "--articulated", help)
    help = (
        "the node's space_weather: fixed (default) or historical (the indices of the demo's "
        "date from CelesTrak's record, shown in /diagnostics)"
    )
    option(p, "--space-weather", help, choices=("fixed", "historical"), default="fixed")
    help = "directory for demo_wrench.csv and the plots (default ./adbsat_demo)"
    option(p, "--out-dir", help, default="adbsat_demo", metavar="DIR")
    p.set_defaults(func=run)


def run(args) -> int:
    """Run the demo; 0 if the node answered every attitude (a signal: INTERRUPTED_STATUS)."""
    demo = ros_module("demo")
    result = demo.run_demo(
        args.duration,
        args.speedup,
        args.out_dir,
        args.attitude,
        articulated=args.articulated,
        space_weather=args.space_weather,
    )
    if result.interrupted:  # (by SIGINT or SIGTERM: what was received is written)
        return INTERRUPTED_STATUS
    if result.wrenches_received == 0 or result.mismatched or not result.files:
        raise CommandFailed("the node did not answer as expected (see above)")
    return 0
