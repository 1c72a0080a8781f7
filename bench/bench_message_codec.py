"""Cost of one attitude in and one wrench out, as message objects or as CDR bytes.

Usage:
    python bench/bench_message_codec.py [--repeat 20000]

For one geometry_msgs/QuaternionStamped read (stamp and quaternion) and one
geometry_msgs/WrenchStamped written (stamp, frame, force, torque), three ways:

* rclpy: deserialize_message / serialize_message, i.e. the typesupport conversions between CDR
  and Python message objects that a typed subscription and publisher make for every message;
* rosbags: its pure-Python CDR codec with its own message classes;
* stamped_cdr: the struct reader and writer the node uses (adbsat_ros.messages.cdr), the one
  hand-made codec of the package.

Prints the median time per message pair in microseconds, each codec timed in alternating blocks
so that the machine's slow spells fall on all three.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np
from geometry_msgs.msg import QuaternionStamped, WrenchStamped
from rclpy.serialization import deserialize_message, serialize_message

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's adbsat_ros first

from adbsat_ros.bags import io as bag_io  # noqa: E402
from adbsat_ros.messages.cdr import quaternion_stamped_fields, wrench_stamped_cdr  # noqa: E402

FORCE, TORQUE = [1.0e-3, -2.0e-5, 3.0e-6], [4.0e-7, 5.0e-6, -6.0e-7]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=20000)
    args = parser.parse_args()

    msg = QuaternionStamped()
    msg.header.frame_id = "eci"
    msg.header.stamp.sec, msg.header.stamp.nanosec = 1_767_225_600, 10_000_000
    msg.quaternion.z, msg.quaternion.w = math.sin(0.1), math.cos(0.1)
    raw = bytes(serialize_message(msg))
    out = WrenchStamped()

    def with_rclpy():
        m = deserialize_message(raw, QuaternionStamped)
        q = m.quaternion
        _ = (m.header.stamp.sec, m.header.stamp.nanosec, q.x, q.y, q.z, q.w)
        out.header.stamp = m.header.stamp
        out.header.frame_id = "body"
        f, t = out.wrench.force, out.wrench.torque
        f.x, f.y, f.z = FORCE
        t.x, t.y, t.z = TORQUE
        return serialize_message(out)

    def with_rosbags():
        m = bag_io.deserialize(raw, bag_io.QUATERNION_STAMPED)
        q = m.quaternion
        _ = (q.x, q.y, q.z, q.w)
        ns = m.header.stamp.sec * 1_000_000_000 + m.header.stamp.nanosec
        return bag_io.serialize(bag_io.wrench_stamped_message(ns, "body", FORCE, TORQUE))

    def with_struct():
        stamp, _ = quaternion_stamped_fields(raw)
        return wrench_stamped_cdr(stamp.sec, stamp.nanosec, "body", FORCE, TORQUE)

    # the three give the same wrench
    for fn in (with_rclpy, with_rosbags):
        back = deserialize_message(bytes(fn()), WrenchStamped)
        assert back.header.stamp == msg.header.stamp and back.wrench.force.x == FORCE[0]
    assert bytes(with_rosbags()) == with_struct()

    pairs = {
        "rclpy message objects": with_rclpy,
        "rosbags codec": with_rosbags,
        "stamped_cdr (struct)": with_struct,
    }

    for title, cases in (("one QuaternionStamped read + one WrenchStamped written", pairs),):
        block = 500
        times = {name: [] for name in cases}
        for _ in range(max(args.repeat // block, 1)):
            for name, fn in cases.items():
                t0 = time.perf_counter()
                for _ in range(block):
                    fn()
                times[name].append((time.perf_counter() - t0) / block)
        print(f"{title}; {args.repeat} per codec")
        print(f"{'codec':<24} {'median us':>10}")
        for name, t in times.items():
            print(f"{name:<24} {1e6 * float(np.median(t)):10.2f}")


if __name__ == "__main__":
    main()
