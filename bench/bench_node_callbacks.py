"""The node's own CPU per message, without the middleware: its callbacks called directly.

Usage:
    python bench/bench_node_callbacks.py [--max-edge 0.064] [--number 2000] [--repeat 7]
        [--baseline DIR_OR_REV] [--param NAME=VALUE ...]

Builds adbsat_node (rclpy, one process, nobody subscribed) on the example satellite refined to
~9,600 faces with its default parameters (sentman, raycast shading cached) and epoch stamps, and
times what its subscriptions do with one message, as the executor would call them:

* an attitude at 1 kHz stamps, fixed attitude (a cache hit), a state every 100 messages: the
  whole wrench (flight conditions prepared by the message before, panel method, CDR packing,
  publish, preparing the next stamp);
* an attitude with a NaN quaternion: rejected, counted and (throttled) logged;
* an Odometry state: what the subscription receives (CDR bytes, or for a typed subscription the
  message rclpy deserialises first, which is counted here too).

``--baseline DIR_OR_REV`` builds the node of another tree too: a checkout directory (e.g. the flat
layout at ../baseline, whose node is ``adbsat_ros.node``) or a git revision, its ``adbsat_ros``
copied and imported as ``adbsat_ros_baseline`` (which works for a tree whose modules import each
other relatively, as the flat layout's do), and times both in alternating rounds, so that both
see the same machine load. Prints the median over rounds of the mean CPU time of the process per
message (``time.process_time``: time the machine's other load takes from it is not counted) in
microseconds, the fastest round's in brackets, and with a baseline the median over rounds of the
ratio of the two nodes' times in that round (the paired comparison: each pair of rounds saw the
same spell of the machine).
"""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import inspect
import math
import os
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's adbsat_ros first

import rclpy  # noqa: E402
import yaml  # noqa: E402
from bench_flight_conditions import import_baseline  # noqa: E402
from geometry_msgs.msg import QuaternionStamped  # noqa: E402
from nav_msgs.msg import Odometry  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402
from rclpy.serialization import deserialize_message, serialize_message  # noqa: E402

R_ORBIT = 6378137.0 + 300e3
V_ORBIT = math.sqrt(3.986004418e14 / R_ORBIT)
STATE_EVERY = 100  # attitudes per state: 10 Hz states with 1 kHz attitudes


def attitude_bytes(k: int, quaternion_xyzw=(0.0, 0.0, 0.0, 1.0)) -> bytes:
    msg = QuaternionStamped()
    msg.header.frame_id = "eci"
    msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(k * 1_000_000, 1_000_000_000)
    msg.quaternion.x, msg.quaternion.y, msg.quaternion.z, msg.quaternion.w = quaternion_xyzw
    return bytes(serialize_message(msg))


def state_bytes(k: int) -> bytes:
    msg = Odometry()
    msg.header.frame_id = msg.child_frame_id = "eci"
    msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(k * 1_000_000, 1_000_000_000)
    msg.pose.pose.position.x = R_ORBIT
    msg.twist.twist.linear.y = V_ORBIT
    return bytes(serialize_message(msg))


def node_module(package: str):
    """The node module of an imported package: ``ros.node`` (subpackage layout) or ``node``."""
    try:
        return importlib.import_module(f"{package}.ros.node")
    except ModuleNotFoundError:
        return importlib.import_module(f"{package}.node")


def import_tree(spec: str) -> str:
    """Import the ``adbsat_ros`` of a checkout directory or git revision as
    ``adbsat_ros_baseline``; return that name."""
    if not (Path(spec) / "adbsat_ros").is_dir():
        return import_baseline(spec, tempfile.mkdtemp())
    package_dir = Path(tempfile.mkdtemp()) / "adbsat_ros"
    shutil.copytree(
        Path(spec) / "adbsat_ros", package_dir, ignore=shutil.ignore_patterns("__pycache__")
    )
    name = "adbsat_ros_baseline"
    module_spec = importlib.util.spec_from_file_location(
        name, package_dir / "__init__.py", submodule_search_locations=[str(package_dir)]
    )
    module = importlib.util.module_from_spec(module_spec)
    sys.modules[name] = module
    module_spec.loader.exec_module(module)
    return name


def _taking(callback):
    """``callback`` as a function of the message alone (one that rclpy passes the message info
    too is given an empty info)."""
    if len(inspect.signature(callback).parameters) == 2:
        return lambda message: callback(message, {})
    return callback


class NodeUnderTest:
    """One package's node, and what its subscriptions are handed for a CDR message."""

    def __init__(self, package: str, mesh_path: str, parameters=()):
        node_module_ = node_module(package)
        self.node = node_module_.AdbsatNode(
            parameter_overrides=[
                Parameter("mesh", value=mesh_path),
                Parameter("time_mode", value="epoch"),
                *parameters,
            ]
        )
        self.subscriptions = {sub.topic_name.lstrip("/"): sub for sub in self.node.subscriptions}
        self.callbacks = {topic: _taking(sub.callback) for topic, sub in self.subscriptions.items()}
        self.k = 0  # attitude stamps [ms]

    def handed(self, topic: str, raw: bytes):
        """What the executor passes to ``topic``'s callback for these bytes."""
        sub = self.subscriptions[topic]
        return raw if sub.raw else deserialize_message(raw, sub.msg_type)

    def accepted(self, attitudes, states, number: int) -> None:
        """The next ``number`` of the 1 kHz ``attitudes``, with ``states`` every STATE_EVERY."""
        on_attitude, on_state = self.callbacks["attitude"], self.callbacks["state"]
        for _ in range(number):
            k = self.k
            if k % STATE_EVERY == 0:
                on_state(self.handed("state", states[k // STATE_EVERY]))
            on_attitude(attitudes[k])
            self.k += 1

    def rejected(self, raw: bytes, number: int) -> None:
        on_attitude = self.callbacks["attitude"]
        for _ in range(number):
            on_attitude(raw)

    def state(self, raw: bytes, number: int) -> None:
        on_state = self.callbacks["state"]
        for _ in range(number):
            on_state(self.handed("state", raw))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--max-edge", type=float, default=0.064)
    parser.add_argument("--number", type=int, default=2000, help="messages per timing round")
    parser.add_argument("--repeat", type=int, default=7, help="rounds")
    parser.add_argument(
        "--baseline",
        metavar="DIR_OR_REV",
        help="also time the node of another tree (a checkout directory or a git revision)",
    )
    parser.add_argument(
        "--param",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="a parameter of the working tree's node (a YAML value), e.g. "
        "shading_interpolation=false to compare with a tree that had no interpolation",
    )
    args = parser.parse_args()
    parameters = []
    for item in args.param:
        name, _, value = item.partition("=")
        parameters.append(Parameter(name, value=yaml.safe_load(value)))

    from meshes import write_obj

    from adbsat_ros.geometry.example_satellite import example_satellite

    mesh = example_satellite(max_edge=args.max_edge)
    mesh_path = Path(tempfile.mkdtemp()) / "satellite.obj"
    write_obj(mesh, mesh_path)
    packages = {"working tree": "adbsat_ros"}
    if args.baseline:
        packages[f"baseline {args.baseline}"] = import_tree(args.baseline)
    rclpy.init()
    nodes = {
        label: NodeUnderTest(package, str(mesh_path), parameters if package == "adbsat_ros" else ())
        for label, package in packages.items()
    }
    total = args.number * (args.repeat + 1)
    attitudes = [attitude_bytes(k) for k in range(total)]
    states = [state_bytes(k) for k in range(0, total, STATE_EVERY)]
    nan_attitude = attitude_bytes(0, (math.nan, 0.0, 0.0, 1.0))
    one_state = state_bytes(0)
    cases = {
        "attitude -> wrench (cache hit, state every 100)": lambda n: n.accepted(
            attitudes, states, args.number
        ),
        "attitude rejected (NaN quaternion)": lambda n: n.rejected(nan_attitude, args.number),
        "state (Odometry)": lambda n: n.state(one_state, args.number),
    }
    print(
        f"mesh: example satellite, {mesh.n_panels} faces; {args.repeat} rounds of "
        f"{args.number} messages"
    )
    print(f"{'case':<50}" + "".join(f"{label + ' (fastest)':>28}" for label in nodes))
    for name, case in cases.items():
        for node in nodes.values():  # warm-up round (first ray cast, caches), not timed
            node.k = 0
            case(node)
            node.node.estimator.reset()
        times = {label: [] for label in nodes}
        for _ in range(args.repeat):
            for label, node in nodes.items():
                t0 = time.process_time()
                case(node)
                times[label].append((time.process_time() - t0) / args.number)
        medians = [statistics.median(t) * 1e6 for t in times.values()]
        fastest = [min(t) * 1e6 for t in times.values()]
        line = f"{name:<50}" + "".join(f"{m:17.1f} ({f:5.1f}) us" for m, f in zip(medians, fastest))
        if len(medians) == 2:  # each round against the other node's round right after it
            paired = statistics.median(b / a for a, b in zip(*times.values()))
            line += f"   baseline / working tree {paired:.2f}x"
        print(line)
    published = {label: node.node.estimator.published for label, node in nodes.items()}
    print("wrenches published:", published)
    for node in nodes.values():
        node.node.destroy_node()
    rclpy.try_shutdown()


if __name__ == "__main__":
    sys.exit(main())
