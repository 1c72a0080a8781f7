"""The node's CPU per message for an articulated body against the rigid body of the same panels,
in one run: ``adbsat_node`` itself (rclpy), its subscriptions' callbacks handed CDR bytes.

Usage:
    python bench/bench_articulated_node.py [--rounds 5] [--messages 3000]
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
subscribed, as a node with no matching reader does. Rounds are interleaved; printed per node:
the median over rounds of the process CPU time per attitude (joint states and states
included) [us], and its ratio to ``rigid``.
"""

from __future__ import annotations

import argparse
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
from nav_msgs.msg import Odometry  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402
from rclpy.serialization import serialize_message  # noqa: E402
from sensor_msgs.msg import JointState  # noqa: E402

from adbsat_ros.geometry.articulated import ArticulatedBody  # noqa: E402
from adbsat_ros.geometry.example_satellite import write_obj  # noqa: E402
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


class NodeCase:
    """A node and its message stream; ``angle(k)`` the wings' angle due at message k."""

    def __init__(self, name: str, node: AdbsatNode, hinges, angle=None):
        self.name, self.node, self.hinges, self.angle = name, node, hinges, angle
        subs = {sub.topic_name.split("/")[-1]: sub.callback for sub in node.subscriptions}
        self.on_attitude, self.on_state = subs["attitude"], subs["state"]
        self.on_joint_state = subs.get("joint_states")
        self.k = 0
        self.means = []

    def run(self, n: int) -> None:
        messages = []  # (the bytes are made before the clock starts)
        for k in range(self.k, self.k + n):
            joint = None
            if self.angle is not None and k % JOINTS_EVERY == 0:
                joint = joint_state_cdr(k, self.hinges, self.angle(k))
            messages.append(
                (state_cdr(k) if k % STATE_EVERY == 0 else None, joint, attitude_cdr(k))
            )
        published = self.node.estimator.published
        t0 = time.process_time()
        for state_raw, joint_raw, attitude_raw in messages:
            if state_raw is not None:
                self.on_state(state_raw)
            if joint_raw is not None:
                self.on_joint_state(joint_raw)
            self.on_attitude(attitude_raw)
        self.means.append((time.process_time() - t0) / n * 1e6)
        if self.node.estimator.published - published != n:
            raise RuntimeError(f"{self.name}: not every attitude gave a wrench")
        self.k += n


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--messages", type=int, default=3000)
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
        for case in cases:  # warm-up: the first cells and configurations
            case.run(args.messages // 4)
            case.means.clear()
        for _ in range(args.rounds):
            for case in cases:
                case.run(args.messages)
        rigid = statistics.median(cases[0].means)
        print(f"{wings.mesh().n_panels} faces; {args.rounds} rounds of {args.messages} messages")
        for case in cases:
            mean = statistics.median(case.means)
            print(f"{case.name:9s} {mean:8.1f} us/message  ratio to rigid {mean / rigid:6.3f}")
    finally:
        for case in locals().get("cases", []):
            case.node.destroy_node()
        rclpy.try_shutdown()


if __name__ == "__main__":
    sys.exit(main())
