"""The node's CPU per message for an articulated body against the rigid body of the same panels,
in one run: ``adbsat_node`` itself (rclpy), its subscriptions' callbacks handed CDR bytes.

Usage:
    python bench/bench_articulated_node.py [--messages 27000] [--warm-up 3000] [--block 1000]
        [--max-edge-fraction 0.0625]

The streams are those of ``bench_articulated.py`` (attitudes at 1 kHz turning at 0.5 deg/s,
states at 10 Hz, joint states at 10 Hz), as CDR bytes. Nodes (default parameters, epoch time):

* ``rigid``: ``mesh`` = the example satellite with wings, both at 0.3 rad, merged into one mesh
  (an OBJ written here; ``--max-edge-fraction`` 0.0625 refines it to 10,464 faces; every OBJ
  here is written with 17 significant digits, so the nodes read the panels exactly: rounded
  to nine, the turned wings' panels no longer share their facets, and the rigid node would
  evaluate 170 facets instead of 12);
* ``fixed``: ``robot_description`` = the same body as a URDF whose links are those meshes (OBJ
  files written here), joint states unchanged (both wings at 0.3 rad);
* ``tracking``: the same URDF, the wings turning at 0.1 deg/s (sun tracking).

Each node publishes its wrench (and the articulated ones the joint torques) with nobody
subscribed, as a node with no matching reader does. The nodes take the stream in turn, message
by message: a slower spell of the shared host falls on every node alike. Each node's callbacks
for a message are timed in CPU time of this thread. Printed per node, after ``--warm-up``
messages (the first cells and configurations): the mean CPU time per attitude over every
message [us] (joint states and states included: what a run of the node costs; the tracking
node's new grid configurations come in bursts, one in 2,500 attitudes, so its cost is this
mean, not a median), its ratio to ``rigid``, and the median and range of that ratio over
blocks of ``--block`` messages.
"""

from __future__ import annotations

import argparse
import inspect
import os
import re
import statistics
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import rclpy  # noqa: E402
from bench_articulated import (  # noqa: E402
    FIXED_ANGLE,
    JOINTS_EVERY,
    PERIOD_NS,
    STATE_EVERY,
    TRACK_RATE,
    attitude,
    state,
)
from geometry_msgs.msg import QuaternionStamped  # noqa: E402
from meshes import write_obj  # noqa: E402
from nav_msgs.msg import Odometry  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402
from rclpy.serialization import serialize_message  # noqa: E402
from sensor_msgs.msg import JointState  # noqa: E402

from adbsat_ros.geometry.articulated import ArticulatedBody  # noqa: E402
from adbsat_ros.geometry.example_urdf import example_satellite_urdf  # noqa: E402
from adbsat_ros.ros.node import AdbsatNode  # noqa: E402


def attitude_cdr(k: int) -> bytes:
    fields = attitude(k)
    msg = QuaternionStamped()
    msg.header.frame_id = "eci"
    msg.header.stamp.sec, msg.header.stamp.nanosec = fields.stamp
    msg.quaternion.x, msg.quaternion.y, msg.quaternion.z, msg.quaternion.w = fields.quaternion_xyzw
    return bytes(serialize_message(msg))


def state_cdr(k: int) -> bytes:
    fields = state(k)
    msg = Odometry()
    msg.header.frame_id = msg.child_frame_id = "eci"
    msg.header.stamp.sec, msg.header.stamp.nanosec = fields.stamp
    p, v = msg.pose.pose.position, msg.twist.twist.linear
    p.x, p.y, p.z = fields.position
    v.x, v.y, v.z = fields.linear_velocity
    return bytes(serialize_message(msg))


def joint_state_cdr(k: int, names, angle: float) -> bytes:
    msg = JointState()
    msg.header.stamp.sec, msg.header.stamp.nanosec = attitude(k).stamp
    msg.name = list(names)
    msg.position = [angle] * len(names)
    return bytes(serialize_message(msg))


def link_mesh_urdf(body: ArticulatedBody, text: str, directory: Path) -> str:
    """``text`` (the URDF ``body`` was read from) with each link's visual replaced by the
    link's panels as an OBJ file in ``directory`` (so its refinement is kept)."""
    for link, _ in sorted(body.link_spans.items()):
        name = body.links[link]
        mesh = body.link_mesh(link)
        path = directory / f"{name}.obj"
        write_obj(mesh, path, digits=17)
        material = mesh.material_names[mesh.material_index[0]]
        visual = (
            f'<visual><geometry><mesh filename="{path}"/></geometry>'
            f'<material name="{material}"/></visual>'
        )
        text = re.sub(
            rf'(<link name="{name}">).*?(</link>)', rf"\g<1>{visual}\g<2>", text, flags=re.S
        )
    return text


def _taking(callback):
    """``callback`` as a function of the message alone (one that rclpy passes the message info
    too is given an empty info)."""
    if len(inspect.signature(callback).parameters) == 2:
        return lambda message: callback(message, {})
    return callback


class NodeCase:
    """A node and its message stream; ``angle(k)`` the wings' angle due at message k."""

    def __init__(self, name: str, node: AdbsatNode, hinges, angle=None):
        self.name, self.node, self.hinges, self.angle = name, node, hinges, angle
        subs = {sub.topic_name.split("/")[-1]: _taking(sub.callback) for sub in node.subscriptions}
        self.on_attitude, self.on_state = subs["attitude"], subs["state"]
        self.on_joint_state = subs.get("joint_states")
        self.times = []  # CPU time of each message [ns]

    def messages(self, start: int, stop: int) -> list:
        """(state, joint state, attitude) CDR bytes of messages [start, stop) (None where a
        message is not due)."""
        out = []
        for k in range(start, stop):
            joint = None
            if self.angle is not None and k % JOINTS_EVERY == 0:
                joint = joint_state_cdr(k, self.hinges, self.angle(k))
            out.append((state_cdr(k) if k % STATE_EVERY == 0 else None, joint, attitude_cdr(k)))
        return out

    def take(self, message, clock=time.thread_time_ns) -> None:
        """Hand the node one message (its state and joint state first, if due); time it."""
        state_raw, joint_raw, attitude_raw = message
        published = self.node.estimator.published
        t0 = clock()
        if state_raw is not None:
            self.on_state(state_raw)
        if joint_raw is not None:
            self.on_joint_state(joint_raw)
        self.on_attitude(attitude_raw)
        self.times.append(clock() - t0)
        if self.node.estimator.published != published + 1:
            raise RuntimeError(f"{self.name}: an attitude gave no wrench")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--messages", type=int, default=27000)
    parser.add_argument("--warm-up", type=int, default=3000)
    parser.add_argument("--block", type=int, default=1000)
    parser.add_argument("--max-edge-fraction", type=float, default=0.0625)
    args = parser.parse_args()

    text = example_satellite_urdf()
    wings = ArticulatedBody.from_urdf(text, max_edge_fraction=args.max_edge_fraction)
    hinges = tuple(wings.joints)
    directory = Path(tempfile.mkdtemp())
    urdf = link_mesh_urdf(wings, text, directory)
    rigid_path = directory / "rigid.obj"
    write_obj(wings.mesh(dict.fromkeys(hinges, FIXED_ANGLE)), rigid_path, digits=17)
    common = [Parameter("time_mode", value="epoch")]

    def node(name: str, *parameters) -> AdbsatNode:
        return AdbsatNode(namespace=name, parameter_overrides=[*common, *parameters])

    rclpy.init()
    try:
        cases = [
            NodeCase(
                "rigid",
                node("rigid", Parameter("mesh", value=str(rigid_path))),
                hinges,
            ),
            NodeCase(
                "fixed",
                node("fixed", Parameter("robot_description", value=urdf)),
                hinges,
                lambda k: FIXED_ANGLE,
            ),
            NodeCase(
                "tracking",
                node("tracking", Parameter("robot_description", value=urdf)),
                hinges,
                lambda k: FIXED_ANGLE + TRACK_RATE * k * PERIOD_NS * 1e-9,
            ),
        ]
        total = args.warm_up + args.messages
        for start in range(0, total, args.block):  # (the bytes are made between blocks)
            stop = min(start + args.block, total)
            streams = [case.messages(start, stop) for case in cases]
            for k in range(stop - start):
                for case, stream in zip(cases, streams):
                    case.take(stream[k])
        print(
            f"{wings.mesh().n_panels} faces; {args.messages} messages after {args.warm_up}, "
            f"blocks of {args.block}"
        )
        rigid = cases[0].times[args.warm_up :]
        for case in cases:
            times = case.times[args.warm_up :]
            blocks = [
                sum(times[i : i + args.block]) / sum(rigid[i : i + args.block])
                for i in range(0, len(times), args.block)
            ]
            print(
                f"{case.name:9s} {statistics.fmean(times) / 1e3:8.1f} us/message  ratio to rigid "
                f"{sum(times) / sum(rigid):6.3f}  (blocks: median {statistics.median(blocks):.3f}, "
                f"{min(blocks):.3f}-{max(blocks):.3f})"
            )
    finally:
        for case in locals().get("cases", []):
            case.node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    sys.exit(main())
