"""Bag analysis: a simulated 10-minute flight through analyze_bag, cross-checked against direct
AeroWrenchEstimator calls, the written bag (read back with rosbags), the CSV and closed forms."""

import csv
import math
from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag2 import Reader

from adbsat_ros import bag_io, scenario
from adbsat_ros.aero_wrench import AeroWrenchEstimator, Rejection
from adbsat_ros.bag_analysis import MODEL_COLUMNS, analyze_bag
from adbsat_ros.wrench_settings import WrenchSettings

FAST = {"shading": "none"}


def read_bag(path):
    """{topic: [(log time ns, message)]} and {topic: msgtype} of a bag, read with rosbags."""
    out, types = {}, {}
    with Reader(path) as reader:
        for conn, t, raw in reader.messages():
            out.setdefault(conn.topic, []).append((t, bag_io.deserialize(raw, conn.msgtype)))
            types[conn.topic] = conn.msgtype
    return out, types


def read_csv(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    return rows[0], rows[1:]


def direct_wrenches(messages, settings):
    """The estimator fed straight from the generator's arrays (no bag, no decoding)."""
    est = AeroWrenchEstimator(settings)
    events = [(t, 0, i) for i, t in enumerate(messages.states.stamps_ns)]
    events += [(t, 1, i) for i, t in enumerate(messages.attitudes.stamps_ns)]
    forces, torques = [], []
    for _, kind, i in sorted(events):
        if kind == 0:
            est.on_state(messages.states.stamps[i], messages.states.position_eci[i], messages.states.velocity_eci[i])
        else:
            try:
                s = est.on_attitude(messages.attitudes.stamps[i], messages.attitudes.quaternion_xyzw[i])
            except Rejection:
                continue
            forces.append(s.force)
            torques.append(s.torque)
    return np.array(forces), np.array(torques)


def vec(v):
    return [v.x, v.y, v.z]


@pytest.fixture(scope="module")
def flight(tmp_path_factory):
    """A 10-minute nadir flight at 1 Hz (state and attitude), analysed into mcap and db3."""
    root = tmp_path_factory.mktemp("flight")
    sc = scenario.Scenario(duration_s=600, rate_hz=1.0, state_rate_hz=1.0, altitude_km=350, inclination_deg=51.6)
    messages = scenario.generate(sc)
    bag_io.write_scenario_bag(messages, root / "in", storage="mcap")
    settings = WrenchSettings.from_parameters(FAST)
    reports = {}
    for storage in ("mcap", "sqlite3"):
        reports[storage] = analyze_bag(root / "in", "/attitude", "/state", [("fast", settings)],
                                       out_bag=root / f"out_{storage}", out_csv=root / f"out_{storage}.csv",
                                       plots_dir=root / f"plots_{storage}", storage=storage)
    return root, messages, settings, reports


def test_wrench_per_attitude_and_bag_reads_back(flight):
    root, messages, _, reports = flight
    n_att, n_state = len(messages.attitudes.stamps_ns), len(messages.states.stamps_ns)
    for storage, suffix in (("mcap", ".mcap"), ("sqlite3", ".db3")):
        report = reports[storage]
        assert report.error is None and report.warnings == []
        assert report.models[0].wrenches == n_att == 601
        bag = root / f"out_{storage}"
        assert (bag / f"out_{storage}{suffix}").is_file()
        topics, types = read_bag(bag)
        assert types["/adbsat/fast/wrench"] == types["/adbsat/fast/coefficients"] == bag_io.WRENCH_STAMPED
        assert types["/diagnostics"] == bag_io.DIAGNOSTIC_ARRAY
        assert len(topics["/adbsat/fast/wrench"]) == len(topics["/adbsat/fast/coefficients"]) == n_att
        assert len(topics["/attitude"]) == n_att and len(topics["/state"]) == n_state  # inputs copied
        # wrench stamped like its attitude message, logged at the attitude's log time
        for (t_w, w), (t_a, a) in zip(topics["/adbsat/fast/wrench"], topics["/attitude"]):
            assert t_w == t_a and (w.header.stamp.sec, w.header.stamp.nanosec) == (a.header.stamp.sec, a.header.stamp.nanosec)
            assert w.header.frame_id == "body"
        # one DiagnosticArray per second of bag time, plus one at the end with the final counts
        diags = topics["/diagnostics"]
        assert len(diags) == 600 + 1
        final = {kv.key: kv.value for kv in diags[-1][1].status[0].values}
        assert int(final["published"]) == n_att and diags[-1][1].status[0].level == 0


def test_analysis_equals_direct_estimator_calls(flight):
    root, messages, settings, _ = flight
    forces, torques = direct_wrenches(messages, settings)
    topics, _ = read_bag(root / "out_mcap")
    bag_f = np.array([vec(m.wrench.force) for _, m in topics["/adbsat/fast/wrench"]])
    bag_t = np.array([vec(m.wrench.torque) for _, m in topics["/adbsat/fast/wrench"]])
    np.testing.assert_array_equal(bag_f, forces)
    np.testing.assert_array_equal(bag_t, torques)
    assert np.all(np.linalg.norm(forces, axis=1) > 0)


def test_csv_matches_bag_and_closed_forms(flight):
    root, messages, _, _ = flight
    header, rows = read_csv(root / "out_mcap.csv")
    assert header[:4] == ["stamp_s", "utc", "time_s", "topic"]
    assert header[4:] == [f"fast.{c}" for c in MODEL_COLUMNS]
    col = {name: i for i, name in enumerate(header)}
    data = lambda name: np.array([float(r[col[name]]) for r in rows])  # noqa: E731
    topics, _ = read_bag(root / "out_mcap")
    wrenches = topics["/adbsat/fast/wrench"]
    coefficients = topics["/adbsat/fast/coefficients"]
    assert len(rows) == len(wrenches)
    for axis, i in (("x", 0), ("y", 1), ("z", 2)):
        np.testing.assert_array_equal(data(f"fast.force_{axis}_N"), [vec(m.wrench.force)[i] for _, m in wrenches])
        np.testing.assert_array_equal(data(f"fast.torque_{axis}_Nm"), [vec(m.wrench.torque)[i] for _, m in wrenches])
        np.testing.assert_array_equal(data(f"fast.CF_{axis}"), [vec(m.wrench.force)[i] for _, m in coefficients])
        np.testing.assert_array_equal(data(f"fast.CM_{axis}"), [vec(m.wrench.torque)[i] for _, m in coefficients])
    np.testing.assert_array_equal(data("stamp_s"), messages.attitudes.stamps)
    np.testing.assert_allclose(data("time_s"), np.arange(601.0), atol=1e-9)
    assert rows[0][col["utc"]] == "2026-01-01T00:00:00+00:00"
    # F = q A_ref C_F with q = rho V^2 / 2 and A_ref from the diagnostics
    diag = {kv.key: kv.value for kv in topics["/diagnostics"][-1][1].status[0].values}
    a_ref = float(diag["reference_area_m2"])
    q = 0.5 * data("fast.density_kg_m3") * data("fast.relative_speed_m_s") ** 2
    np.testing.assert_allclose(data("fast.force_x_N"), q * a_ref * data("fast.CF_x"), rtol=1e-12)
    # the relative wind has the relative speed as norm; altitude of the circular orbit above the ellipsoid
    wind = np.stack([data(f"fast.wind_body_{a}_m_s") for a in "xyz"], axis=1)
    np.testing.assert_allclose(np.linalg.norm(wind, axis=1), data("fast.relative_speed_m_s"), rtol=1e-12)
    alt = data("fast.altitude_m")
    assert 350e3 - 1 < alt.min() and alt.max() < 350e3 + 22e3  # the ellipsoid is lower at high latitude


def test_nadir_flight_meets_the_example_satellite_nose_first(flight):
    """Body +x along-track: the gas comes from +x (ADBSat's zero angle of attack), within the
    small angles the Earth's rotation adds; the drag pushes towards -x."""
    root, _, _, _ = flight
    header, rows = read_csv(root / "out_mcap.csv")
    col = {name: i for i, name in enumerate(header)}
    data = lambda name: np.array([float(r[col[name]]) for r in rows])  # noqa: E731
    assert np.all(data("fast.wind_body_x_m_s") < -7000)
    assert np.max(np.abs(data("fast.aoa_deg"))) < 0.5
    assert np.max(np.abs(data("fast.aos_deg"))) < 4.0  # co-rotating air: <= omega r cos(lat) / v
    assert np.all(data("fast.force_x_N") < 0)
    cf = np.stack([data(f"fast.CF_{a}") for a in "xyz"], axis=1)
    wind = np.stack([data(f"fast.wind_body_{a}_m_s") for a in "xyz"], axis=1)
    cd = np.sum(cf * wind, axis=1) / data("fast.relative_speed_m_s")  # C_D: C_F along the gas motion
    np.testing.assert_allclose(data("fast.drag_coefficient"), cd, rtol=1e-12)
    assert np.all(cd > 0)


def test_plots_written(flight):
    root, _, _, reports = flight
    plots = reports["mcap"].outputs["plots"]
    assert len(plots) == 4 and all(Path(p).is_file() and Path(p).stat().st_size > 1000 for p in plots)
    assert not list(root.glob(".*partial"))  # no temporary leftovers


def test_multi_model_comparison_columns_and_topics(tmp_path):
    messages = scenario.generate(scenario.Scenario(duration_s=20, rate_hz=1, state_rate_hz=1))
    bag_io.write_scenario_bag(messages, tmp_path / "in")
    models = [("diffuse", WrenchSettings.from_parameters(FAST)),
              ("specular", WrenchSettings.from_parameters(dict(FAST, gsi_model="maxwell", alpha=0.2)))]
    report = analyze_bag(tmp_path / "in", models=models, out_bag=tmp_path / "out", out_csv=tmp_path / "out.csv")
    assert [m.wrenches for m in report.models] == [21, 21]
    header, rows = read_csv(tmp_path / "out.csv")
    assert sum(h.startswith("diffuse.") for h in header) == sum(h.startswith("specular.") for h in header) == len(MODEL_COLUMNS)
    col = {name: i for i, name in enumerate(header)}
    cd = {m: np.array([float(r[col[f"{m}.drag_coefficient"]]) for r in rows]) for m in ("diffuse", "specular")}
    assert np.all(np.abs(cd["diffuse"] - cd["specular"]) > 1e-3)
    topics, _ = read_bag(tmp_path / "out")
    for label, settings in models:
        forces, _ = direct_wrenches(messages, settings)
        np.testing.assert_array_equal([vec(m.wrench.force) for _, m in topics[f"/adbsat/{label}/wrench"]], forces)
    assert {s.name for _, d in topics["/diagnostics"] for s in d.status} == {
        "adbsat_node/diffuse: aerodynamic wrench", "adbsat_node/specular: aerodynamic wrench"}


def test_raycast_tumbling_flight_equals_direct_calls(tmp_path):
    messages = scenario.generate(scenario.Scenario(duration_s=30, rate_hz=2, state_rate_hz=1, attitude="tumble",
                                                   tumble_rate_deg_s=6.0, seed=3))
    bag_io.write_scenario_bag(messages, tmp_path / "in", storage="sqlite3")
    settings = WrenchSettings.from_parameters({"shading": "raycast", "shading_samples": 4})
    report = analyze_bag(tmp_path / "in", models=[("ray", settings)], out_bag=tmp_path / "out")
    assert report.models[0].wrenches == 61
    topics, _ = read_bag(tmp_path / "out")
    forces, torques = direct_wrenches(messages, settings)
    np.testing.assert_array_equal([vec(m.wrench.force) for _, m in topics["/adbsat/ray/wrench"]], forces)
    np.testing.assert_array_equal([vec(m.wrench.torque) for _, m in topics["/adbsat/ray/wrench"]], torques)
    diag = {kv.key: kv.value for kv in topics["/diagnostics"][-1][1].status[0].values}
    assert diag["shading"] == "raycast" and int(diag["shading_cache_misses"]) > 0


def test_body_frame_twist_and_odometry_attitude_source(tmp_path):
    """The node's Odometry rules: a twist in the body frame is rotated by the pose orientation;
    attitude_source odometry computes at each state message from its pose."""
    messages = scenario.generate(scenario.Scenario(duration_s=5, rate_hz=1, state_rate_hz=1))
    st, att = messages.states, messages.attitudes
    records = []
    for i, t in enumerate(st.stamps_ns):
        q = att.quaternion_xyzw[i]
        v_body = bag_io_rotate_inverse(q, st.velocity_eci[i])
        records.append(("/state", int(t), bag_io.odometry_message(int(t), "eci", "body", st.position_eci[i], v_body, q)))
    bag_io.write_bag(tmp_path / "in", records)
    settings = WrenchSettings.from_parameters(dict(FAST, attitude_source="odometry"))
    report = analyze_bag(tmp_path / "in", models=[("odo", settings)], out_bag=tmp_path / "out")
    assert report.models[0].wrenches == 6
    topics, _ = read_bag(tmp_path / "out")
    forces, _ = direct_wrenches(messages, WrenchSettings.from_parameters(FAST))
    np.testing.assert_allclose([vec(m.wrench.force) for _, m in topics["/adbsat/odo/wrench"]], forces,
                               rtol=1e-9, atol=1e-12 * np.abs(forces).max())


def bag_io_rotate_inverse(q, v):
    from scipy.spatial.transform import Rotation

    return Rotation.from_quat(q).apply(v, inverse=True)


def test_decode_odometry_frame_rules():
    msg = bag_io.odometry_message(1_500_000_000, "ecef", "eci", [1, 2, 3], [4, 5, 6])
    with pytest.raises(Rejection, match="state_frame is eci"):
        bag_io.decode_odometry(msg, "body", "eci")
    msg = bag_io.odometry_message(1_500_000_000, "eci", "sensor", [1, 2, 3], [4, 5, 6])
    with pytest.raises(Rejection, match="child_frame_id 'sensor'"):
        bag_io.decode_odometry(msg, "body", "eci")
    stamp, p, v, in_body, q = bag_io.decode_odometry(
        bag_io.odometry_message(1_500_000_000, "eci", "body", [1, 2, 3], [4, 5, 6]), "body", "eci")
    assert (stamp, p, v, in_body, q) == (1.5, [1, 2, 3], [4, 5, 6], True, [0, 0, 0, 1])
    assert math.isclose(bag_io.stamp_seconds(bag_io.time_message(1_767_225_600_123_456_789)), 1_767_225_600.123456789)
