"""Bag analysis of an articulated body: the joint_states in the bag set the joint positions as
in the node; the wrenches, the joint torques in the output bag and the CSV's joint columns equal
the estimator's fed the same messages in bag order, for one worker or two; bad joint states are
counted; a bag without the joint topic is refused naming the option."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest
from rosbags.rosbag2 import Reader

from adbsat_ros.bags import io as bag_io
from adbsat_ros.bags import scenario
from adbsat_ros.bags.analysis import analyze_bag
from adbsat_ros.bags.io import BagError
from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.samples import Rejection
from adbsat_ros.estimator.settings import WrenchSettings

HINGES = ("wing_left_hinge", "wing_right_hinge")
SETTINGS = {"mesh": "example-articulated", "joint_state_timeout": 2.0}
NS = 1_000_000_000


def joint_events(messages):
    """Joint states at 1 Hz, 0.3 s after each second: the arrays turn 2 deg a second; one
    message beyond the hinge's limits."""
    out = []
    end = messages.attitudes.stamps_ns[-1]
    t0 = int(messages.attitudes.stamps_ns[0])
    for k in range(int((end - t0) // NS) + 1):
        t_ns = t0 + k * NS + 300_000_000
        angle = math.radians(10.0 + 2.0 * k)
        positions = (9.0, 0.0) if k == 5 else (angle, -angle)
        out.append((t_ns, positions))
    return out


def write_bag(messages, path):
    events = [(int(t), 0, i) for i, t in enumerate(messages.states.stamps_ns)]
    events += [(int(t), 1, i) for i, t in enumerate(messages.attitudes.stamps_ns)]
    joints = joint_events(messages)
    events += [(t, 2, i) for i, (t, _) in enumerate(joints)]
    events.sort()
    records = []
    for t_ns, kind, i in events:
        if kind == 0:
            s = messages.states
            records.append(
                (
                    "/state",
                    t_ns,
                    bag_io.odometry_message(
                        t_ns, "eci", "eci", s.position_eci[i], s.velocity_eci[i]
                    ),
                )
            )
        elif kind == 1:
            q = messages.attitudes.quaternion_xyzw[i]
            records.append(("/attitude", t_ns, bag_io.quaternion_stamped_message(t_ns, "eci", q)))
        else:
            msg = bag_io.joint_state_message(t_ns, "", HINGES, joints[i][1])
            records.append(("/joint_states", t_ns, msg))
    bag_io.write_bag(path, records)
    return events, joints


def direct_samples(messages, events, joints, settings):
    """The estimator fed in bag order: every sample (None for a refused attitude)."""
    est = AeroWrenchEstimator(settings)
    samples = []
    for t_ns, kind, i in events:
        try:
            if kind == 0:
                s = messages.states
                est.on_state(s.stamps[i], s.position_eci[i], s.velocity_eci[i])
            elif kind == 1:
                a = messages.attitudes
                samples.append(est.on_attitude(a.stamps[i], a.quaternion_xyzw[i]))
            else:
                est.on_joint_state(t_ns / NS, HINGES, joints[i][1])
        except Rejection:
            if kind == 1:
                samples.append(None)
    return samples, est.rejections


@pytest.mark.parametrize(
    "workers, exact", [(1, False), (2, False), (2, True)], ids=["1", "2", "2-exact"]
)
def test_joint_torques_and_wrenches_are_the_estimators(tmp_path, workers, exact):
    """Also with the shading of each attitude's own positions (``joint_shading_exact``)."""
    messages = scenario.generate(
        scenario.Scenario(duration_s=8, rate_hz=5, state_rate_hz=1, attitude="tumble")
    )
    events, joints = write_bag(messages, tmp_path / "in")
    settings = WrenchSettings.from_parameters({**SETTINGS, "joint_shading_exact": exact})
    report = analyze_bag(
        tmp_path / "in",
        models=[("wings", settings)],
        out_bag=tmp_path / "out",
        out_csv=tmp_path / "out.csv",
        workers=workers,
        chunk_messages=10,
    )
    expected, rejections = direct_samples(messages, events, joints, settings)
    computed = [s for s in expected if s is not None]
    assert len(computed) >= 30 and rejections["bad_joint_state"] == 1
    summary = report.models[0]
    assert summary.rejections == {k: v for k, v in rejections.items() if v}
    topics = {}
    with Reader(tmp_path / "out") as reader:
        for conn, _, raw in reader.messages():
            topics.setdefault(conn.topic, []).append(bag_io.deserialize(raw, conn.msgtype))
    torques = topics["/adbsat/wings/joint_torques"]
    wrenches = topics["/adbsat/wings/wrench"]
    assert len(torques) == len(wrenches) == len(computed)
    for msg, wrench, sample in zip(torques, wrenches, computed):
        assert list(msg.name) == list(HINGES)
        assert msg.position.tolist() == sample.joints.positions.tolist()
        assert msg.effort.tolist() == sample.joints.efforts.tolist()
        f = wrench.wrench.force
        assert [f.x, f.y, f.z] == sample.force.tolist()
    with open(tmp_path / "out.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    ok = [r for r in rows if r["wings.status"] == "ok"]
    assert len(ok) == len(computed)
    for row, sample in zip(ok, computed):
        for k, name in enumerate(HINGES):
            assert float(row[f"wings.joint.{name}.position_rad"]) == sample.joints.positions[k]
            assert float(row[f"wings.joint.{name}.effort_Nm"]) == sample.joints.efforts[k]
    assert np.ptp([s.joints.positions[0] for s in computed]) > math.radians(5.0)


def test_a_bag_without_the_joint_topic_is_refused_naming_the_option(tmp_path):
    messages = scenario.generate(scenario.Scenario(duration_s=2, rate_hz=2, state_rate_hz=1))
    bag_io.write_scenario_bag(messages, tmp_path / "in")
    with pytest.raises(BagError, match=r"no topic /joint_states \(given by --joint-states-topic\)"):
        analyze_bag(
            tmp_path / "in",
            models=[("wings", WrenchSettings.from_parameters(SETTINGS))],
            out_csv=tmp_path / "out.csv",
        )
