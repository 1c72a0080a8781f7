"""ROS 2 node: attitude and orbital state in, aerodynamic WrenchStamped out (docs/node.md).

A shell around the per-message path shared with bag analysis (CDR bytes in and out).
"""

from __future__ import annotations

import gc
import os
import sys

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions

from adbsat_ros.estimator.settings import settings_from_file
from adbsat_ros.geometry.mesh import MeshError
from adbsat_ros.processes import run_until_stopped, signal_name, stop_on_signals
from adbsat_ros.ros.executors import make_executor, spin_until_shutdown
from adbsat_ros.ros.managed_node import AdbsatLifecycleNode
from adbsat_ros.ros.node_core import WrenchNodeCore
from adbsat_ros.ros.node_help import NODE_NAME, help_text


class AdbsatNode(WrenchNodeCore, Node):
    """The aerodynamic wrench node; MeshError/ValueError at construction on a bad set-up."""

    def __init__(self, **node_kwargs):
        super().__init__(NODE_NAME, **node_kwargs)
        self.declare_wrench_parameters()
        self.set_up(self.create_publisher)


def params_files(argv) -> list:
    """The files given with ``--params-file`` among the ROS arguments of ``argv``."""
    files, ros, tokens = [], False, iter(argv)
    for token in tokens:
        if token == "--ros-args":
            ros = True
        elif token == "--":
            ros = False
        elif ros and token == "--params-file":
            files.append(next(tokens, ""))
    return files


def main(args=None) -> int:
    """Console script ``adbsat_node --ros-args --params-file config/adbsat.yaml``; the exit status.

    ``--help`` prints :func:`help_text`; ``--managed`` runs the lifecycle node; 1 if no set-up.
    """
    return run_until_stopped(NODE_NAME, _main, args)


def _main(args=None) -> int:
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    argv = sys.argv if args is None else args
    own = argv[1 : argv.index("--ros-args")] if "--ros-args" in argv else argv[1:]
    if "--help" in own or "-h" in own:
        print(help_text())
        return 0
    unknown = [a for a in own if a != "--managed"]
    if unknown:
        print(
            f"{NODE_NAME}: error: unknown option {unknown[0]!r} (--help, --managed)",
            file=sys.stderr,
        )
        return 1
    for path in params_files(argv):  # checked here: rclpy ignores unknown names, and a missing
        try:  # file fails its init with a traceback
            settings_from_file(path, NODE_NAME)
        except ValueError as exc:
            print(f"{NODE_NAME}: error: {exc}", file=sys.stderr)
            return 1
    try:
        rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
        return _run(managed="--managed" in own)
    finally:
        rclpy.try_shutdown()


def _run(managed: bool = False) -> int:
    """Make the node, spin it until a signal, a shutdown or (managed) the lifecycle ``shutdown``
    transition, take it down; the exit status."""
    node = None
    try:
        try:
            node = AdbsatLifecycleNode() if managed else AdbsatNode()
        except (MeshError, ValueError, OSError) as exc:
            if signal_name() is None:  # (else a library's failure under the signal: a stop)
                print(f"{NODE_NAME}: error: {exc}", file=sys.stderr)
            return 1
        except Exception as exc:  # e.g. a parameter of the wrong type in the params file
            if signal_name() is None:
                print(f"{NODE_NAME}: error: {type(exc).__name__}: {exc}", file=sys.stderr)
            return 1
        executor = make_executor(node.get_parameter("executor").value)
        executor.add_node(node)
        # everything made so far (mesh, shading structures, imported modules) lives as long as the
        # process: move it out of the collector's generations, so that no collection the message
        # traffic triggers walks it (a full one over it would hold up the messages)
        gc.collect()
        gc.freeze()
        try:
            with stop_on_signals() as stop:  # (set already by a signal a library swallowed)
                finalized = (lambda: node.finalized) if managed else None
                spin_until_shutdown(executor, stop=stop, done=finalized)
        except ExternalShutdownException:
            pass
        finally:
            executor.shutdown()
        return 0
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    sys.exit(main())
