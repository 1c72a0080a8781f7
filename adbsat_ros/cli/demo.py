"""``adbsat-ros demo``: run the ROS 2 node live on the bundled satellite and show what it computes.

The node and rclpy are imported when the demo runs (start-up time, and a clear message when ROS
is not installed).
"""

from __future__ import annotations

import sys

from adbsat_ros.cli.options import positive_float
from adbsat_ros.processes import INTERRUPTED_STATUS


def configure(p) -> None:
    """Give the ``demo`` subcommand's parser ``p`` its description and options."""
    p.description = (
        "Start adbsat_node (bundled satellite, default parameters) in this process, publish a "
        "300 km circular orbit with a tumbling (or nadir-pointing) attitude to it live, print a "
        "line of its results every 0.5 s, and write a CSV and PNG plots. Needs rclpy. ROS "
        "discovery is limited to this machine unless ROS_AUTOMATIC_DISCOVERY_RANGE is set; the "
        "topics live under /adbsat_demo."
    )
    p.add_argument(
        "--duration",
        type=positive_float("--duration"),
        default=8.0,
        metavar="S",
        help="wall seconds of live publishing (default 8)",
    )
    p.add_argument(
        "--speedup",
        type=positive_float("--speedup"),
        default=10.0,
        metavar="K",
        help="simulated seconds per wall second (default 10; attitudes always at 20 Hz wall)",
    )
    p.add_argument(
        "--attitude",
        choices=("tumble", "nadir"),
        default=None,
        help="tumbling at 1 deg/s (default) or nadir-pointing (the default with --articulated)",
    )
    p.add_argument(
        "--articulated",
        action="store_true",
        help="the bundled finned body (example-finned) instead, steering its four fins +-10 deg "
        "through joint_states: the table and the CSV add the fins' positions and hinge "
        "torques, and demo_hinge_torques.png plots them",
    )
    p.add_argument(
        "--out-dir",
        default="adbsat_demo",
        metavar="DIR",
        help="directory for demo_wrench.csv and the plots (default ./adbsat_demo)",
    )
    p.set_defaults(func=run)


def run(args) -> int:
    """Run the demo; 0 if the node answered every attitude, 1 otherwise (also when a signal
    stopped it)."""
    try:
        from adbsat_ros.ros.demo import run_demo

        result = run_demo(
            args.duration,
            args.speedup,
            args.out_dir,
            args.attitude,
            articulated=args.articulated,
        )
    except ImportError as exc:
        print(
            "adbsat-ros demo: error: needs the ROS 2 Python packages, which cannot be imported: "
            f"{exc}; install them with: pip install 'adbsat_ros[ros]'",
            file=sys.stderr,
        )
        return 1
    if result.interrupted:  # (by SIGINT or SIGTERM: what was received is written)
        return INTERRUPTED_STATUS
    if result.wrenches_received == 0 or result.mismatched or not result.files:
        print(
            "adbsat-ros demo: error: the node did not answer as expected (see above)",
            file=sys.stderr,
        )
        return 1
    return 0
