"""Bag analysis with solar radiation pressure: the solar and total wrenches in the output bag and
the CSV equal the estimator's, message by message; a model without it is unchanged."""

from __future__ import annotations

import csv

import numpy as np
from rosbags.rosbag2 import Reader

from adbsat_ros.bags import io as bag_io
from adbsat_ros.bags import scenario
from adbsat_ros.bags.analysis import analyze_bag
from adbsat_ros.bags.table import MODEL_COLUMNS, SOLAR_COLUMNS
from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.settings import WrenchSettings

PLAIN = {"shading": "none", "mesh": "example"}
SOLAR = dict(PLAIN, solar_pressure=True, specular_reflectivity=0.2, diffuse_reflectivity=0.3)


def direct_samples(messages, settings):
    """The estimator fed straight from the generator's arrays: every sample, in order."""
    est = AeroWrenchEstimator(settings)
    events = [(t, 0, i) for i, t in enumerate(messages.states.stamps_ns)]
    events += [(t, 1, i) for i, t in enumerate(messages.attitudes.stamps_ns)]
    samples = []
    for _, kind, i in sorted(events):
        if kind == 0:
            est.on_state(
                messages.states.stamps[i],
                messages.states.position_eci[i],
                messages.states.velocity_eci[i],
            )
        else:
            stamp, q = messages.attitudes.stamps[i], messages.attitudes.quaternion_xyzw[i]
            samples.append(est.on_attitude(stamp, q))
    return samples


def test_the_solar_and_total_wrenches_are_written_as_the_estimator_makes_them(tmp_path):
    messages = scenario.generate(
        scenario.Scenario(duration_s=40, rate_hz=2, state_rate_hz=1, attitude="tumble")
    )
    bag_io.write_scenario_bag(messages, tmp_path / "in")
    models = [
        ("plain", WrenchSettings.from_parameters(PLAIN)),
        ("sunlit", WrenchSettings.from_parameters(SOLAR)),
    ]
    analyze_bag(
        tmp_path / "in",
        models=models,
        out_bag=tmp_path / "out",
        out_csv=tmp_path / "out.csv",
        workers=2,
    )
    expected = direct_samples(messages, models[1][1])
    assert len(expected) == 81 and all(s.solar is not None for s in expected)

    topics = {}
    with Reader(tmp_path / "out") as reader:
        for conn, _, raw in reader.messages():
            topics.setdefault(conn.topic, []).append(bag_io.deserialize(raw, conn.msgtype))
    assert "/adbsat/plain/solar_wrench" not in topics
    solar = [m.wrench for m in topics["/adbsat/sunlit/solar_wrench"]]
    total = [m.wrench for m in topics["/adbsat/sunlit/total_wrench"]]
    for got, want in ((solar, [s.solar for s in expected]), (total, expected)):
        forces = [[w.force.x, w.force.y, w.force.z] for w in got]
        torques = [[w.torque.x, w.torque.y, w.torque.z] for w in got]
        if want is expected:
            want_forces = [s.total_force for s in want]
            want_torques = [s.total_torque for s in want]
        else:
            want_forces = [s.force for s in want]
            want_torques = [s.torque for s in want]
        np.testing.assert_array_equal(forces, want_forces)
        np.testing.assert_array_equal(torques, want_torques)
    # the aerodynamic wrench is the same with and without sunlight
    np.testing.assert_array_equal(
        [[m.wrench.force.x, m.wrench.force.y] for m in topics["/adbsat/plain/wrench"]],
        [[m.wrench.force.x, m.wrench.force.y] for m in topics["/adbsat/sunlit/wrench"]],
    )
    pushing = np.linalg.norm([s.solar.force for s in expected], axis=1)
    lit = np.array([s.solar.lit_fraction for s in expected])
    assert np.all(pushing[lit > 0] > 1e-7) and np.all(pushing[lit == 0] == 0.0)

    with open(tmp_path / "out.csv", newline="", encoding="utf-8") as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    header, body = rows[0], rows[1:]
    assert header[4:] == [f"plain.{c}" for c in MODEL_COLUMNS] + [
        f"sunlit.{c}" for c in MODEL_COLUMNS + SOLAR_COLUMNS
    ]
    column = {name: i for i, name in enumerate(header)}
    np.testing.assert_array_equal(
        [float(r[column["sunlit.solar_force_x_N"]]) for r in body],
        [s.solar.force[0] for s in expected],
    )
    np.testing.assert_array_equal([float(r[column["sunlit.sun_lit_fraction"]]) for r in body], lit)
    statuses = [st for d in topics["/diagnostics"] for st in d.status if "sunlit" in st.name]
    assert any(kv.key == "solar_lit_fraction" for kv in statuses[-1].values)
