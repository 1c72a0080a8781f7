"""CPU time per message of an articulated body's wrench against the rigid body of the same
panels, in one run.

Usage:
    python bench/bench_articulated.py [--rounds 5] [--messages 4000] [--first-messages 20]
        [--fin-messages 200]
        [--max-edge-fraction 0.0625] [--fin-edge-fraction 0.075] [--wrench-only]

Each message goes through the node's per-message path without ROS
(:class:`~adbsat_ros.estimator.handling.MessageHandler`: the estimator and the CDR bytes of the
outputs; with ``--wrench-only`` of the wrench alone, as the node with nobody subscribed to the
coefficients and the joint torques), timed in CPU time of this thread. The stream is the node
benchmark's: attitudes at 1 kHz turning slowly (0.5 deg/s about a tilted axis), a state every
100 ms (a circular orbit at 300 km), with the default parameters (sentman, ray-cast shading
cached at 0.25 deg, interpolated; the joint configuration grid at 0.25 deg). Cases:

* ``rigid``: the example satellite with wings, read from its URDF with both wings at 0.3 rad
  and merged into one mesh (``--max-edge-fraction`` 0.0625 refines it to 10,464 faces), as a
  plain mesh;
* ``fixed``: the same URDF as an articulated body, its joint states (both wings at 0.3 rad,
  unchanged) at 10 Hz;
* ``tracking``: its arrays turning at 0.1 deg/s (sun tracking), joint states at 10 Hz;
* ``fins``: the finned example (``--fin-edge-fraction`` 0.075 refines it to 12,832 faces, the
  refinement nearest the wings' 10,464 above it), its four fins stepping to a new deflection
  (a 0.4 deg step of a +-10 deg sweep, 157 messages a period) with every message: ``fins``
  from a fresh node, every message a new grid configuration (the first sweep, rounds of
  ``--first-messages``); ``fins-steady`` after three whole sweeps (the steady state: every
  configuration of the sweep kept, ``joint_shading_cache_size`` 256, each needing new
  direction cells only as the attitude turns, one cell crossing in 500 messages), rounds of
  ``--fin-messages``; ``fins-2deg`` the same with the configuration grid at 2 deg
  (``joint_shading_resolution_deg``), nearest point; ``fins-2deg-blend`` the same with
  ``joint_shading_interpolation``; ``fins-exact`` with ``joint_shading_exact`` (every message
  shades the body posed at its positions for its flow direction; rounds of
  ``--fin-messages``).

Then, with ``--new-configurations`` N (default 12): what one new grid configuration costs the
node's shading (a read of the model's shading cache at a configuration not seen before: posing
the body, its candidate filter and hulls, and shading the direction cells around the flow at
the stream's attitude), CPU time, median of N, every moving joint 0.3 deg further each time.

In each round rigid, fixed and tracking take the next ``--messages`` of their streams message by
message, in turn (a slower spell of the shared host falls on each alike), then the fin cases
theirs. Printed per case: the median over rounds of the mean CPU time per message [us] (joint
states included), the mean over every message measured (what a run costs: the fins' and the
tracking arrays' costs come in bursts as cells and configurations are shaded), its ratio to
``rigid``'s, and the shading counters (cells and configurations shaded, hits).
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.handling import MessageHandler
from adbsat_ros.estimator.settings import WrenchSettings, setup_from_settings
from adbsat_ros.estimator.state import checked_rotation
from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.example_urdf import example_finned_urdf, example_satellite_urdf
from adbsat_ros.messages.cdr import AttitudeFields, Stamp
from adbsat_ros.messages.decoding import JointStateFields, OdometryFields
from adbsat_ros.messages.encoding import encode_wrench
from adbsat_ros.physics.model import build_model

R_ORBIT = 6378137.0 + 300e3
V_ORBIT = math.sqrt(3.986004418e14 / R_ORBIT)
T0_NS = 1_767_225_600_000_000_000  # 2026-01-01T00:00:00Z, UNIX time [ns]
PERIOD_NS = 1_000_000  # 1 kHz attitudes
STATE_EVERY = 100  # 10 Hz states
JOINTS_EVERY = 100  # 10 Hz joint states (tracking, fixed)
TURN_RATE = math.radians(0.5)  # attitude [rad/s]
TRACK_RATE = math.radians(0.1)  # arrays [rad/s]
FIXED_ANGLE = 0.3  # the wings' hinges [rad] (rigid, fixed; where tracking starts)
SWEEP = 158  # messages of one period of the fins' sweep, and one more


def stamp(k: int) -> Stamp:
    return Stamp(*divmod(T0_NS + k * PERIOD_NS, 1_000_000_000))


def attitude(k: int) -> AttitudeFields:
    angle = 0.2 + TURN_RATE * k * PERIOD_NS * 1e-9
    axis = (0.3, 0.8, 0.52)
    norm = math.sqrt(sum(a * a for a in axis))
    s = math.sin(angle / 2) / norm
    return AttitudeFields(stamp(k), [axis[0] * s, axis[1] * s, axis[2] * s, math.cos(angle / 2)])


def state(k: int) -> OdometryFields:
    t = k * PERIOD_NS * 1e-9
    w = V_ORBIT / R_ORBIT
    position = (R_ORBIT * math.cos(w * t), R_ORBIT * math.sin(w * t), 0.0)
    velocity = (-V_ORBIT * math.sin(w * t), V_ORBIT * math.cos(w * t), 0.0)
    return OdometryFields(stamp(k), "eci", "eci", position, (0.0, 0.0, 0.0, 1.0), velocity)


def fixed_joints(hinges):
    """``joints(k)``: the wings' hinges at FIXED_ANGLE, a joint state every JOINTS_EVERY
    messages (None between)."""

    def joints(k):
        if k % JOINTS_EVERY:
            return None
        return JointStateFields(stamp(k), hinges, (FIXED_ANGLE, FIXED_ANGLE))

    return joints


def tracking_joints(hinges):
    """``joints(k)``: the wings' hinges turning at TRACK_RATE from FIXED_ANGLE (sun tracking),
    a joint state every JOINTS_EVERY messages (None between)."""

    def joints(k):
        if k % JOINTS_EVERY:
            return None
        angle = FIXED_ANGLE + TRACK_RATE * k * PERIOD_NS * 1e-9
        return JointStateFields(stamp(k), hinges, (angle, angle))

    return joints


class Case:
    """A handler and its message stream: ``joints(k)`` gives the joint state due at message k
    (or None)."""

    #: What is serialised besides the wrench (``encode_wrench``'s flags).
    outputs = {"coefficients": True, "joint_torques": True}

    def __init__(self, name, handler, joints=None):
        self.name, self.handler, self.joints = name, handler, joints
        self.k = 0
        self.means = []

    def take(self, clock=time.thread_time_ns) -> int:
        """Hand the handler the next message (its state and joint state first, if due); its
        CPU time [ns]."""
        handler, k = self.handler, self.k
        t0 = clock()
        if k % STATE_EVERY == 0:
            handler.on_state(state(k))
        if self.joints is not None:
            joint_state = self.joints(k)
            if joint_state is not None:
                handler.on_joint_state(joint_state)
        outcome = handler.on_attitude(attitude(k))
        if outcome.sample is None:
            raise RuntimeError(f"{self.name}: message {k} refused: {outcome.rejection}")
        settings = handler.estimator.settings
        encode_wrench(outcome.stamp, outcome.sample, settings, **self.outputs)
        elapsed = clock() - t0
        self.k += 1
        return elapsed

    def run(self, n: int) -> None:
        """The next ``n`` messages, their mean CPU time [us] kept as a round's."""
        self.means.append(sum(self.take() for _ in range(n)) / n / 1e3)

    def counters(self) -> str:
        cache = self.handler.estimator.model.cache
        text = f"cells shaded {cache.misses}, hits {cache.hits}"
        if cache.body is not None:
            text += (
                f"; configurations shaded {cache.configuration_misses}, "
                f"hits {cache.configuration_hits}"
            )
        return text


def handler(settings, body) -> MessageHandler:
    return MessageHandler(AeroWrenchEstimator(settings, body))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--messages", type=int, default=4000)
    parser.add_argument("--first-messages", type=int, default=20)
    parser.add_argument("--fin-messages", type=int, default=200)
    parser.add_argument("--max-edge-fraction", type=float, default=0.0625)
    parser.add_argument("--fin-edge-fraction", type=float, default=0.075)
    parser.add_argument("--new-configurations", type=int, default=12)
    parser.add_argument(
        "--wrench-only",
        action="store_true",
        help="serialise the wrench alone, as the node does with nobody subscribed to the "
        "coefficients and the joint torques",
    )
    args = parser.parse_args()

    wings = ArticulatedBody.from_urdf(
        example_satellite_urdf(), max_edge_fraction=args.max_edge_fraction, source="wings"
    )
    finned = ArticulatedBody.from_urdf(
        example_finned_urdf(), max_edge_fraction=args.fin_edge_fraction, source="finned"
    )
    settings = WrenchSettings.from_parameters({})
    hinges = tuple(wings.joints)
    fins = tuple(finned.joints)

    fixed, tracking = fixed_joints(hinges), tracking_joints(hinges)

    def stepping(k):
        d = math.radians(10.0) * math.sin(k * math.radians(0.4) / math.radians(10.0))
        return JointStateFields(stamp(k), fins, (d, -d, 0.5 * d, -0.5 * d))

    cases = [
        Case("rigid", handler(settings, wings.mesh(dict.fromkeys(hinges, FIXED_ANGLE)))),
        Case("fixed", handler(settings, wings), fixed),
        Case("tracking", handler(settings, wings), tracking),
    ]

    def fin_settings(**values):
        return WrenchSettings.from_parameters({"joint_shading_cache_size": 256, **values})

    fin_cases = [
        Case("fins", handler(settings, finned), stepping),
        Case("fins-steady", handler(fin_settings(), finned), stepping),
        Case(
            "fins-2deg",
            handler(fin_settings(joint_shading_resolution_deg=2.0), finned),
            stepping,
        ),
        Case(
            "fins-2deg-blend",
            handler(
                fin_settings(joint_shading_resolution_deg=2.0, joint_shading_interpolation=True),
                finned,
            ),
            stepping,
        ),
        Case(
            "fins-exact",
            handler(WrenchSettings.from_parameters({"joint_shading_exact": True}), finned),
            stepping,
        ),
    ]
    if args.wrench_only:
        Case.outputs = {"coefficients": False, "joint_torques": False}
    for case in cases:  # warm-up: the first cells and configurations
        case.run(args.messages // 4)
        case.means.clear()
    for case in fin_cases:
        # (the grid's steady states after three whole sweeps; the exact mode keeps nothing)
        case.run(5 if case.name in ("fins", "fins-exact") else 3 * SWEEP)
        case.means.clear()
    for _ in range(args.rounds):
        totals = [0] * len(cases)  # (the wings' cases take their streams message by message)
        for _ in range(args.messages):
            for i, case in enumerate(cases):
                totals[i] += case.take()
        for case, total in zip(cases, totals):
            case.means.append(total / args.messages / 1e3)
        for case in fin_cases:
            case.run(args.first_messages if case.name == "fins" else args.fin_messages)
    rigid = statistics.fmean(cases[0].means)
    print(
        f"faces: wings {wings.mesh().n_panels}, finned {finned.mesh().n_panels}; "
        f"{args.rounds} rounds of {args.messages} messages ({args.first_messages} for the "
        f"first sweep of the fins, {args.fin_messages} for the others)"
    )
    for case in cases + fin_cases:
        median, mean = statistics.median(case.means), statistics.fmean(case.means)
        print(
            f"{case.name:15s} {median:10.1f} us/message  mean {mean:10.1f} us  "
            f"ratio of means to rigid {mean / rigid:7.3f}  ({case.counters()})"
        )
    for body in (wings, finned):
        times = new_configuration_times(body, args.new_configurations)
        print(
            f"new configuration, {body.source}: {statistics.median(times):.1f} ms "
            f"(median of {len(times)}; {min(times):.1f}-{max(times):.1f})"
        )


def new_configuration_times(body, n: int) -> list:
    """CPU times [ms] of the node's shading at ``n`` configurations never seen before."""
    cache = build_model(setup_from_settings(WrenchSettings.from_parameters({})), body).cache
    m = checked_rotation(attitude(1000).quaternion_xyzw, "attitude", 1e-6)
    # the gas moves along -y (the orbit's velocity is +y there): in the body, R^T (0, -1, 0)
    flow_body = [-m[1], -m[4], -m[7]]

    def positions(k):
        return {name: math.radians(0.3 * k) for name in body.joints}

    cache.read(flow_body, cache.vertices(positions(0)))
    out = []
    for k in range(1, n + 1):
        t0 = time.process_time()
        cache.read(flow_body, cache.vertices(positions(k)))
        out.append((time.process_time() - t0) * 1e3)
    return out


if __name__ == "__main__":
    main()
