"""Where an articulated node's time goes, message by message: arrays tracking against joints
fixed.

Usage:
    python bench/articulated_message_costs.py [--messages 20000] [--warm-up 4000]

Runs the node's per-message path without ROS (as ``bench/bench_articulated.py`` does: the
estimator and the CDR bytes of the outputs) on the example satellite's URDF refined to 10,464
faces, the wings either tracking the Sun at 0.1 deg/s or fixed at 0.3 rad, joint states at
10 Hz, attitudes at 1 kHz. Each message is timed (CPU time of the thread, the state and joint
state due with it included) and classed by what it triggered: ``config`` (a new grid
configuration was posed and shaded), ``cell`` (a new direction cell was shaded), ``js`` (it
brought a joint state), ``plain`` (none of these). Printed per class: the count, the mean and
median per message, and its share of the mean per attitude.
"""

from __future__ import annotations

import argparse
import statistics
import time

from bench_articulated import (
    STATE_EVERY,
    attitude,
    fixed_joints,
    handler,
    state,
    tracking_joints,
)

from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.example_urdf import example_satellite_urdf
from adbsat_ros.messages.encoding import encode_wrench

CLASSES = ("plain", "js", "cell", "config")


def run(body, joints, messages: int, warm_up: int) -> dict:
    """{class: [CPU time of each message, us]} over ``messages`` after ``warm_up``."""
    h = handler(WrenchSettings.from_parameters({}), body)
    clock = time.thread_time_ns
    out = {name: [] for name in CLASSES}
    for k in range(warm_up + messages):
        t0 = clock()
        if k % STATE_EVERY == 0:
            h.on_state(state(k))
        joint_state = joints(k)
        if joint_state is not None:
            h.on_joint_state(joint_state)
        cache = h.estimator.model.cache
        configurations, cells = cache.configuration_misses, cache.misses
        outcome = h.on_attitude(attitude(k))
        if outcome.sample is not None:
            encode_wrench(outcome.stamp, outcome.sample, h.estimator.settings)
        elapsed = (clock() - t0) / 1e3
        if k < warm_up:
            continue
        if cache.configuration_misses > configurations:
            kind = "config"
        elif cache.misses > cells:
            kind = "cell"
        else:
            kind = "js" if joint_state is not None else "plain"
        out[kind].append(elapsed)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--messages", type=int, default=20000)
    parser.add_argument("--warm-up", type=int, default=4000)
    args = parser.parse_args()
    body = ArticulatedBody.from_urdf(example_satellite_urdf(), max_edge_fraction=0.0625)
    hinges = tuple(body.joints)
    tracking, fixed = tracking_joints(hinges), fixed_joints(hinges)
    print(f"{body.mesh().n_panels} faces; {args.messages} messages after {args.warm_up}")
    for name, joints in (("tracking", tracking), ("fixed", fixed)):
        times = run(body, joints, args.messages, args.warm_up)
        total = sum(sum(t) for t in times.values())
        print(f"{name}: mean {total / args.messages:.1f} us per attitude")
        for kind in CLASSES:
            t = times[kind]
            if not t:
                print(f"  {kind:7s} n=0")
                continue
            print(
                f"  {kind:7s} n={len(t):6d}  mean {statistics.fmean(t):9.1f} us  "
                f"median {statistics.median(t):9.1f} us  "
                f"per attitude {sum(t) / args.messages:6.2f} us"
            )


if __name__ == "__main__":
    main()
