"""Bag analysis: a simulated 10-minute flight through analyze_bag, cross-checked against direct
AeroWrenchEstimator calls, the written bag (read back with rosbags), the CSV and closed forms."""

import csv
import gc
import math
import os
import signal
from pathlib import Path

import numpy as np
import pytest
from meshes import grid_box
from rosbags.rosbag2 import Reader

from adbsat_ros import tasks
from adbsat_ros.bags import io as bag_io
from adbsat_ros.bags import scenario
from adbsat_ros.bags import worker as bag_worker
from adbsat_ros.bags.analysis import analyze_bag
from adbsat_ros.bags.planning import safe_split_points
from adbsat_ros.bags.table import MODEL_COLUMNS
from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS
from adbsat_ros.estimator.samples import Rejection
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.geometry.mesh import panels_from_arrays
from adbsat_ros.messages.stamps import stamp_seconds
from adbsat_ros.processes import usable_cpus

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
            est.on_state(
                messages.states.stamps[i],
                messages.states.position_eci[i],
                messages.states.velocity_eci[i],
            )
        else:
            try:
                s = est.on_attitude(
                    messages.attitudes.stamps[i], messages.attitudes.quaternion_xyzw[i]
                )
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
    sc = scenario.Scenario(
        duration_s=600, rate_hz=1.0, state_rate_hz=1.0, altitude_km=350, inclination_deg=51.6
    )
    messages = scenario.generate(sc)
    bag_io.write_scenario_bag(messages, root / "in", storage="mcap")
    settings = WrenchSettings.from_parameters(FAST)
    reports = {}
    for storage in ("mcap", "sqlite3"):
        reports[storage] = analyze_bag(
            root / "in",
            "/attitude",
            "/state",
            [("fast", settings)],
            out_bag=root / f"out_{storage}",
            out_csv=root / f"out_{storage}.csv",
            plots_dir=root / f"plots_{storage}",
            storage=storage,
        )
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
        assert (
            types["/adbsat/fast/wrench"]
            == types["/adbsat/fast/coefficients"]
            == bag_io.WRENCH_STAMPED
        )
        assert types["/diagnostics"] == bag_io.DIAGNOSTIC_ARRAY
        assert (
            len(topics["/adbsat/fast/wrench"]) == len(topics["/adbsat/fast/coefficients"]) == n_att
        )
        assert (
            len(topics["/attitude"]) == n_att and len(topics["/state"]) == n_state
        )  # inputs copied
        # wrench stamped like its attitude message, logged at the attitude's log time
        for (t_w, w), (t_a, a) in zip(topics["/adbsat/fast/wrench"], topics["/attitude"]):
            assert t_w == t_a and (w.header.stamp.sec, w.header.stamp.nanosec) == (
                a.header.stamp.sec,
                a.header.stamp.nanosec,
            )
            assert w.header.frame_id == "base_link"
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
        np.testing.assert_array_equal(
            data(f"fast.force_{axis}_N"), [vec(m.wrench.force)[i] for _, m in wrenches]
        )
        np.testing.assert_array_equal(
            data(f"fast.torque_{axis}_Nm"), [vec(m.wrench.torque)[i] for _, m in wrenches]
        )
        np.testing.assert_array_equal(
            data(f"fast.cf_{axis}"), [vec(m.wrench.force)[i] for _, m in coefficients]
        )
        np.testing.assert_array_equal(
            data(f"fast.cm_{axis}"), [vec(m.wrench.torque)[i] for _, m in coefficients]
        )
    np.testing.assert_array_equal(data("stamp_s"), messages.attitudes.stamps)
    np.testing.assert_allclose(data("time_s"), np.arange(601.0), atol=1e-9)
    assert rows[0][col["utc"]] == "2026-01-01T00:00:00+00:00"
    # F = q A_ref C_F with q = rho V^2 / 2 and A_ref from the diagnostics
    diag = {kv.key: kv.value for kv in topics["/diagnostics"][-1][1].status[0].values}
    a_ref = float(diag["reference_area_m2"])
    q = 0.5 * data("fast.density_kg_m3") * data("fast.relative_speed_m_s") ** 2
    np.testing.assert_allclose(data("fast.force_x_N"), q * a_ref * data("fast.cf_x"), rtol=1e-12)
    # the relative wind has the relative speed as norm; altitude of the circular orbit above the
    # ellipsoid
    wind = np.stack([data(f"fast.wind_body_{a}_m_s") for a in "xyz"], axis=1)
    np.testing.assert_allclose(
        np.linalg.norm(wind, axis=1), data("fast.relative_speed_m_s"), rtol=1e-12
    )
    alt = data("fast.altitude_m")
    assert (
        350e3 - 1 < alt.min() and alt.max() < 350e3 + 22e3
    )  # the ellipsoid is lower at high latitude


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
    cf = np.stack([data(f"fast.cf_{a}") for a in "xyz"], axis=1)
    wind = np.stack([data(f"fast.wind_body_{a}_m_s") for a in "xyz"], axis=1)
    cd = np.sum(cf * wind, axis=1) / data(
        "fast.relative_speed_m_s"
    )  # C_D: C_F along the gas motion
    np.testing.assert_allclose(data("fast.drag_coefficient"), cd, rtol=1e-12)
    assert np.all(cd > 0)


def test_plots_written(flight):
    root, _, _, reports = flight
    plots = reports["mcap"].outputs["plots"]
    assert len(plots) == 4 and all(
        Path(p).is_file() and Path(p).stat().st_size > 1000 for p in plots
    )
    assert not list(root.glob(".*partial"))  # no temporary leftovers


def test_multi_model_comparison_columns_and_topics(tmp_path):
    messages = scenario.generate(scenario.Scenario(duration_s=20, rate_hz=1, state_rate_hz=1))
    bag_io.write_scenario_bag(messages, tmp_path / "in")
    models = [
        ("diffuse", WrenchSettings.from_parameters(FAST)),
        ("specular", WrenchSettings.from_parameters(dict(FAST, gsi_model="maxwell", alpha=0.2))),
    ]
    report = analyze_bag(
        tmp_path / "in", models=models, out_bag=tmp_path / "out", out_csv=tmp_path / "out.csv"
    )
    assert [m.wrenches for m in report.models] == [21, 21]
    header, rows = read_csv(tmp_path / "out.csv")
    assert (
        sum(h.startswith("diffuse.") for h in header)
        == sum(h.startswith("specular.") for h in header)
        == len(MODEL_COLUMNS)
    )
    col = {name: i for i, name in enumerate(header)}
    cd = {
        m: np.array([float(r[col[f"{m}.drag_coefficient"]]) for r in rows])
        for m in ("diffuse", "specular")
    }
    assert np.all(np.abs(cd["diffuse"] - cd["specular"]) > 1e-3)
    topics, _ = read_bag(tmp_path / "out")
    for label, settings in models:
        forces, _ = direct_wrenches(messages, settings)
        np.testing.assert_array_equal(
            [vec(m.wrench.force) for _, m in topics[f"/adbsat/{label}/wrench"]], forces
        )
    assert {s.name for _, d in topics["/diagnostics"] for s in d.status} == {
        "adbsat_node/diffuse: aerodynamic wrench",
        "adbsat_node/specular: aerodynamic wrench",
    }


def test_an_attitude_only_the_general_deserialiser_reads_is_analysed_with_its_stamp(tmp_path):
    """An attitude with CDR padding after its last field is refused by the fast codec and read by
    rosbags' deserialiser: it still gets its wrench, and the CSV row carries its header stamp."""
    messages = scenario.generate(scenario.Scenario(duration_s=4, rate_hz=1, state_rate_hz=1))
    bag_io.write_scenario_bag(messages, tmp_path / "plain")
    padded_stamp = int(messages.attitudes.stamps_ns[2]) + 250_000_000  # between two attitudes
    with Reader(tmp_path / "plain") as reader, bag_io.BagWriter(tmp_path / "in") as writer:
        for conn, t, raw in reader.messages():
            writer.write_raw(writer.connection(conn.topic, conn.msgtype), t, raw)
            if conn.topic == "/attitude" and t == messages.attitudes.stamps_ns[2]:
                msg = bag_io.quaternion_stamped_message(
                    padded_stamp, "eci", messages.attitudes.quaternion_xyzw[2]
                )
                padded = bytes(bag_io.serialize(msg)) + b"\0\0"
                writer.write_raw(writer.connection("/attitude", conn.msgtype), t + 1, padded)
    report = analyze_bag(
        tmp_path / "in",
        models=[("m", WrenchSettings.from_parameters(FAST))],
        out_csv=tmp_path / "out.csv",
    )
    assert report.error is None and report.models[0].wrenches == 5 + 1
    header, rows = read_csv(tmp_path / "out.csv")
    stamps = [float(r[header.index("stamp_s")]) for r in rows]
    assert padded_stamp * 1e-9 in stamps and stamps == sorted(stamps)


def test_raycast_tumbling_flight_equals_direct_calls(tmp_path):
    messages = scenario.generate(
        scenario.Scenario(
            duration_s=30,
            rate_hz=2,
            state_rate_hz=1,
            attitude="tumble",
            tumble_rate_deg_s=6.0,
            seed=3,
        )
    )
    bag_io.write_scenario_bag(messages, tmp_path / "in", storage="sqlite3")
    settings = WrenchSettings.from_parameters({"shading": "raycast", "shading_samples": 4})
    report = analyze_bag(tmp_path / "in", models=[("ray", settings)], out_bag=tmp_path / "out")
    assert report.models[0].wrenches == 61
    topics, _ = read_bag(tmp_path / "out")
    forces, torques = direct_wrenches(messages, settings)
    np.testing.assert_array_equal(
        [vec(m.wrench.force) for _, m in topics["/adbsat/ray/wrench"]], forces
    )
    np.testing.assert_array_equal(
        [vec(m.wrench.torque) for _, m in topics["/adbsat/ray/wrench"]], torques
    )
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
        records.append(
            (
                "/state",
                int(t),
                bag_io.odometry_message(int(t), "eci", "body", st.position_eci[i], v_body, q),
            )
        )
    bag_io.write_bag(tmp_path / "in", records)
    settings = WrenchSettings.from_parameters(dict(FAST, attitude_source="odometry"))
    report = analyze_bag(tmp_path / "in", models=[("odo", settings)], out_bag=tmp_path / "out")
    assert report.models[0].wrenches == 6
    topics, _ = read_bag(tmp_path / "out")
    forces, _ = direct_wrenches(messages, WrenchSettings.from_parameters(FAST))
    np.testing.assert_allclose(
        [vec(m.wrench.force) for _, m in topics["/adbsat/odo/wrench"]],
        forces,
        rtol=1e-9,
        atol=1e-12 * np.abs(forces).max(),
    )


def bag_io_rotate_inverse(q, v):
    from scipy.spatial.transform import Rotation

    return Rotation.from_quat(q).apply(v, inverse=True)


def test_odometry_from_a_bag_follows_the_node_frame_rules():
    """Bag messages (rosbags types) go through the estimator's own Odometry rules, as the node's
    do."""
    settings = WrenchSettings.from_parameters(dict(PARAMETER_DEFAULTS, shading="none"))
    est = AeroWrenchEstimator(
        settings, panels_from_arrays(*grid_box((0, 0, 0), (1, 1, 1), (1, 1, 1)))
    )
    with pytest.raises(Rejection, match="state_frame is eci"):
        est.on_odometry(
            bag_io.odometry_message(1_500_000_000, "ecef", "eci", [6.7e6, 2, 3], [4, 5, 6])
        )
    with pytest.raises(Rejection, match="child_frame_id 'sensor'"):
        est.on_odometry(
            bag_io.odometry_message(1_500_000_000, "eci", "sensor", [6.7e6, 2, 3], [4, 5, 6])
        )
    h = math.sqrt(0.5)  # body turned 90 deg about z: body x is state y
    state, q = est.on_odometry(
        bag_io.odometry_message(
            1_500_000_000,
            "eci",
            "body",
            [6.7e6, 2, 3],
            [4, 5, 6],
            orientation_xyzw=[0.0, 0.0, h, h],
        )
    )
    assert state.stamp == 1.5 and q == [0.0, 0.0, h, h]
    np.testing.assert_allclose(state.velocity, [-5.0, 4.0, 6.0], atol=1e-12)
    state, _ = est.on_odometry(
        bag_io.odometry_message(2_000_000_000, "eci", "eci", [6.7e6, 2, 3], [4, 5, 6])
    )
    np.testing.assert_allclose(state.velocity, [4.0, 5.0, 6.0])
    assert math.isclose(
        stamp_seconds(bag_io.time_message(1_767_225_600_123_456_789)), 1_767_225_600.123456789
    )


# ------------------------------------------------------------------------- parallel analysis
def test_safe_split_points_closed_forms():
    S, A = 0, 1
    # time-ordered: every state but the first
    assert safe_split_points(
        [S, A, A, S, A, A, S, A], [0, 0, 1, 2, 2, 3, 4, 4], ["attitude_topic"]
    ).tolist() == [3, 6]
    # the attitude stamped 3 after one stamped 5: no split before it (sequential would reject it,
    # fresh not)
    kinds, stamps = [S, A, A, S, A, S, A], [0, 1, 5, 2, 3, 6, 7]
    assert safe_split_points(kinds, stamps, ["attitude_topic"]).tolist() == [5]
    # a state going back (5 after 10) is no split point; the next one, later than all, is
    assert safe_split_points(
        [S, A, S, A, S, A], [10, 10, 5, 11, 12, 12], ["attitude_topic"]
    ).tolist() == [4]
    # attitude from odometry: state stamps are the attitude stamps
    assert safe_split_points([S, S, S, S], [0, 2, 1, 3], ["odometry"]).tolist() == [1, 3]
    # (an odometry attitude stamped 1 after ones at 2 and 3: conservatively, no split before it)
    assert safe_split_points([S, S, S, S], [0, 2, 3, 1], ["odometry"]).tolist() == [1]
    assert safe_split_points([S, S, S, S], [0, 2, 3, 1], ["attitude_topic"]).tolist() == [1, 2]
    # every model's rule applies
    kinds, stamps = [S, A, S, A], [0, 3, 2, 2.5]
    assert safe_split_points(kinds, stamps, ["odometry"]).tolist() == [2]
    assert safe_split_points(kinds, stamps, ["attitude_topic"]).tolist() == []
    assert safe_split_points(kinds, stamps, ["attitude_topic", "odometry"]).tolist() == []


def messy_flight(path):
    """40 s at 4 Hz attitude / 1 Hz state with every kind of bad input, and revisited shading cells:
    attitudes before the first state, a state in an unknown frame, an attitude and a state stamped
    back in time, a gap in the states, a non-unit quaternion, a NaN position, an unrelated topic."""
    sc = dict(duration_s=40, rate_hz=4, state_rate_hz=1)
    nadir = scenario.generate(scenario.Scenario(**sc))
    tumble = scenario.generate(
        scenario.Scenario(**sc, attitude="tumble", tumble_rate_deg_s=2.0, seed=5)
    )
    st, att = nadir.states, nadir.attitudes
    quats = [
        tumble.attitudes.quaternion_xyzw[i] if i % 4 >= 2 else att.quaternion_xyzw[i]
        for i in range(len(att.stamps_ns))
    ]
    s = 1_000_000_000
    records = []
    for i, t in enumerate(st.stamps_ns):
        t = int(t)
        rel = (t - int(st.stamps_ns[0])) // s
        if rel in (0, 30, 31):
            continue  # no state at first, and a gap
        stamp, child, position = t, "eci", np.array(st.position_eci[i])
        if rel == 10:
            child = "sensor"
        if rel == 20:
            stamp = t - 3 * s
        if rel == 37:
            position[1] = math.nan
        records.append(
            (
                "/state",
                t,
                bag_io.odometry_message(
                    stamp, "eci", child, position, st.velocity_eci[i], quats[4 * i]
                ),
            )
        )
    for i, t in enumerate(att.stamps_ns):
        t = int(t)
        rel = (t - int(att.stamps_ns[0])) / s
        stamp, q = t, np.array(quats[i])
        if rel == 12:
            stamp = (
                t - 2 * s
            )  # right after the state at 12 s: sequential resets (time_backwards), fresh not
        if rel == 35:
            q = 1.1 * q
        records.append(("/attitude", t, bag_io.quaternion_stamped_message(stamp, "eci", q)))
        if i % 40 == 7:
            records.append(("/other", t, bag_io.quaternion_stamped_message(t, "x", q)))
    records.sort(key=lambda r: (r[1], r[0] != "/state"))
    bag_io.write_bag(path, records)
    return records


def sequential(records, settings):
    """The node's handling, message by message, with one estimator: forces, rejections, cache
    counts."""
    est = AeroWrenchEstimator(settings)
    forces = []
    for topic, _, msg in records:
        try:
            if topic == "/state":
                state, q = est.on_odometry(msg)
                stamp = state.stamp
                if settings.attitude_source != "odometry":
                    continue
            elif topic == "/attitude" and settings.attitude_source == "attitude_topic":
                q = msg.quaternion
                stamp, q = stamp_seconds(msg.header.stamp), [q.x, q.y, q.z, q.w]
            else:
                continue
            forces.append(est.on_attitude(stamp, q).force)
        except Rejection:
            pass
    return np.array(forces), dict(est.rejections), est


def test_workers_and_chunks_give_identical_outputs(tmp_path, monkeypatch):
    """One process, small chunks, a pool of two, and the default: chunks here, the pool for the
    rest once it pays (here never; always): the same outputs."""
    records = messy_flight(tmp_path / "in")
    models = [
        (
            "att",
            WrenchSettings.from_parameters(
                {
                    "shading": "projection",
                    "shading_cache_resolution_deg": 1.0,
                    "shading_cache_size": 3,
                }
            ),
        ),
        ("odo", WrenchSettings.from_parameters(dict(FAST, attitude_source="odometry"))),
        (  # (the Sun's reads share the small cache, uncounted: the merge replays them too)
            "sun",
            WrenchSettings.from_parameters(
                {
                    "shading": "projection",
                    "shading_cache_resolution_deg": 1.0,
                    "shading_cache_size": 3,
                    "solar_pressure": True,
                }
            ),
        ),
    ]
    runs = {}
    cases = (
        ("one", 1, None),
        ("chunks", 1, 1),
        ("pool", 2, 7),
        ("here", None, 7),
        ("auto", None, 7),
    )
    pool_class = bag_worker.ProcessPoolExecutor
    for name, workers, chunk in cases:
        if name == "here":  # a pool that would never pay: none is made
            monkeypatch.setattr(bag_worker, "POOL_START_S", math.inf)
            monkeypatch.setattr(bag_worker, "ProcessPoolExecutor", None)
        if name == "auto":
            monkeypatch.setattr(bag_worker, "ProcessPoolExecutor", pool_class)
            monkeypatch.setattr(tasks, "worth_workers", lambda left, start, count: True)
        report = analyze_bag(
            tmp_path / "in",
            models=models,
            out_bag=tmp_path / name,
            out_csv=tmp_path / f"{name}.csv",
            workers=workers,
            chunk_messages=chunk,
        )
        runs[name] = report, (tmp_path / f"{name}.csv").read_bytes()
    one, pool = runs["one"][0], runs["pool"][0]
    assert one.chunks == 1 and one.workers == 1
    # chunk_messages=1 splits at every safe state: all 38 but those at 10 s (unknown frame) and
    # 37 s (NaN), 11 and 12 s (an attitude stamped 10 s follows), 20 s (stamped 17 s) and, for the
    # odometry model, 19 s (its attitude stamps then go back to 17 s; at 18 s they do not go below
    # the 17 s before)
    assert runs["chunks"][0].chunks == 1 + 38 - 6
    assert 3 < pool.chunks and pool.workers == 2
    assert runs["here"][0].workers == 1 and runs["here"][0].chunks == pool.chunks
    assert runs["auto"][0].workers == (2 if usable_cpus() > 1 else 1)
    for name in ("chunks", "pool", "here", "auto"):
        assert runs[name][1] == runs["one"][1]  # CSV byte for byte
        assert [
            (m.triggers, m.wrenches, m.rejections, m.first_rejection) for m in runs[name][0].models
        ] == [(m.triggers, m.wrenches, m.rejections, m.first_rejection) for m in one.models]
        assert runs[name][0].warnings == one.warnings
    # the output bags: every message the same, diagnostics but for the measured compute times
    contents = {}
    for name in runs:
        topics = {}
        with Reader(tmp_path / name) as reader:
            for conn, t, raw in reader.messages():
                if conn.topic == "/diagnostics":
                    msg = bag_io.deserialize(raw, conn.msgtype)
                    item = [
                        (
                            s.level,
                            s.name,
                            s.message,
                            s.hardware_id,
                            [
                                (kv.key, kv.value)
                                for kv in s.values
                                if not kv.key.startswith("compute_ms")
                            ],
                        )
                        for s in msg.status
                    ]
                else:
                    item = bytes(raw)
                topics.setdefault(conn.topic, []).append((t, item))
        contents[name] = topics
    assert contents["chunks"] == contents["one"] and contents["pool"] == contents["one"]
    assert contents["here"] == contents["one"] and contents["auto"] == contents["one"]
    # and the sequential node logic gives those wrenches, rejections and cache counts
    diags = contents["one"]["/diagnostics"]
    for k, (label, settings) in enumerate(models):
        forces, rejections, est = sequential(records, settings)
        assert one.models[k].rejections == rejections
        bag_f = [
            bag_io.deserialize(raw, bag_io.WRENCH_STAMPED).wrench.force
            for _, raw in contents["one"][f"/adbsat/{label}/wrench"]
        ]
        np.testing.assert_array_equal([vec(f) for f in bag_f], forces)
        final = dict([d for _, d in diags if d[0][1].startswith(f"adbsat_node/{label}:")][-1][0][4])
        assert int(final["published"]) == len(forces)
        counts = est.diagnostic_values(None, [])  # (the node's, at the end)
        for key in ("shading_cache_hits", "shading_cache_misses"):
            assert int(final[key]) == counts[key]
    att_rejections = one.models[0].rejections
    assert set(att_rejections) == {
        "no_state",
        "time_backwards",
        "stale_state",
        "bad_state_frame",
        "non_finite",
        "bad_quaternion",
    }
    hits, misses = (
        int(final_att(diags)["shading_cache_hits"]),
        int(final_att(diags)["shading_cache_misses"]),
    )
    assert hits > 0 and misses > 3  # the cache of 3 entries evicted some cells


def final_att(diags):
    return dict([d for _, d in diags if d[0][1].startswith("adbsat_node/att:")][-1][0][4])


def test_the_garbage_collector_is_left_as_found(tmp_path):
    """The analysis keeps the heap out of the collector's passes while it runs (frozen), and
    leaves nothing frozen after it, nor thaws what its caller froze."""
    messages = scenario.generate(scenario.Scenario(duration_s=3, rate_hz=1, state_rate_hz=1))
    bag_io.write_scenario_bag(messages, tmp_path / "in")
    models = [("m", WrenchSettings.from_parameters(FAST))]
    assert gc.get_freeze_count() == 0
    for workers in (1, 2):
        report = analyze_bag(tmp_path / "in", models=models, workers=workers)
        assert report.error is None and report.models[0].wrenches == 4
        assert gc.get_freeze_count() == 0
    gc.freeze()
    try:
        frozen = gc.get_freeze_count()
        analyze_bag(tmp_path / "in", models=models, workers=1)
        assert gc.get_freeze_count() > frozen // 2  # (frozen objects freed by refcount leave)
    finally:
        gc.unfreeze()


def dying_chunk(chunk):
    """A chunk that kills its worker process, as the out-of-memory killer would."""
    os.kill(os.getpid(), signal.SIGKILL)


@pytest.mark.skipif(usable_cpus() < 2, reason="needs two usable CPUs")
def test_a_worker_that_dies_ends_the_analysis_with_an_error_and_no_outputs(tmp_path, monkeypatch):
    messages = scenario.generate(scenario.Scenario(duration_s=30, rate_hz=4, state_rate_hz=1))
    bag_io.write_scenario_bag(messages, tmp_path / "in")
    monkeypatch.setattr(bag_worker, "_run_chunk", dying_chunk)  # (the forked workers' too)
    out = dict(out_bag=tmp_path / "out", out_csv=tmp_path / "out.csv")
    model = [("m", WrenchSettings.from_parameters(FAST))]
    with pytest.raises(bag_io.BagError, match=r"^a worker process died \(exit code -9, killed"):
        analyze_bag(tmp_path / "in", models=model, workers=2, chunk_messages=20, **out)
    assert not any(path.exists() for path in out.values())
    assert not list(tmp_path.glob(".*partial"))


class StopAfter:
    """A stop event that is set once it has been asked ``n`` times (a signal mid-walk)."""

    def __init__(self, n):
        self.n = n

    def is_set(self):
        self.n -= 1
        return self.n < 0


@pytest.mark.parametrize("workers", [1, 2])
def test_a_stop_keeps_the_outputs_so_far_as_partial(tmp_path, workers, monkeypatch):
    """Stopped mid-walk, the analysis reports it, writes nothing under the final names, draws no
    plots and keeps what it has under PARTIAL names: a readable bag and CSV with the messages
    so far."""
    import re

    from adbsat_ros.bags import worker

    # the stop is asked at every message (and by the workers, in this process): no waiting poll
    # may ask it too, so that it comes while the messages are written, however slow the machine
    monkeypatch.setattr(worker, "STOP_POLL_S", 1e6)
    messages = scenario.generate(scenario.Scenario(duration_s=30, rate_hz=4, state_rate_hz=1))
    bag_io.write_scenario_bag(messages, tmp_path / "in")
    out = dict(out_bag=tmp_path / "out", out_csv=tmp_path / "out.csv", plots_dir=tmp_path / "p")
    report = analyze_bag(
        tmp_path / "in",
        models=[("m", WrenchSettings.from_parameters(FAST))],
        workers=workers,
        chunk_messages=20,
        stop=StopAfter(60),
        **out,
    )
    read = re.fullmatch(r"stopped by a signal after (\d+) messages", report.error or "")
    assert read is not None and report.partial, report.error
    n_in = len(messages.attitudes.stamps_ns) + len(messages.states.stamps_ns)
    assert 0 < int(read.group(1)) < n_in
    assert not any(path.exists() for path in out.values())
    assert report.outputs["bag"] == tmp_path / "out.PARTIAL"
    assert report.outputs["csv"] == tmp_path / "out.PARTIAL.csv"
    topics, _ = read_bag(tmp_path / "out.PARTIAL")
    _, rows = read_csv(tmp_path / "out.PARTIAL.csv")
    wrenches = report.models[0].wrenches
    assert 0 < wrenches < len(messages.attitudes.stamps_ns)
    assert len(topics["/adbsat/m/wrench"]) == len(rows) == wrenches
    assert len(topics["/attitude"]) + len(topics["/state"]) == int(read.group(1))
    assert "plots" not in report.outputs and not (tmp_path / "p.PARTIAL").exists()
    assert not list(tmp_path.glob(".*partial"))


def test_the_outputs_follow_the_umask(tmp_path):
    """The CSV and plot directory are made under temporary names (mkstemp's 0600, mkdtemp's 0700)
    and renamed: their modes, the bag's and the PNGs' must still be what the user's umask gives."""
    import os
    import stat

    messages = scenario.generate(scenario.Scenario(duration_s=2, rate_hz=1, state_rate_hz=1))
    bag_io.write_scenario_bag(messages, tmp_path / "in")
    old = os.umask(0o027)
    try:
        analyze_bag(
            tmp_path / "in",
            models=[("m", WrenchSettings.from_parameters(FAST))],
            out_csv=tmp_path / "out.csv",
            out_bag=tmp_path / "out",
            plots_dir=tmp_path / "plots",
        )
    finally:
        os.umask(old)

    def mode(path):
        return stat.S_IMODE(path.stat().st_mode)

    assert mode(tmp_path / "out.csv") == 0o640
    assert mode(tmp_path / "plots") == mode(tmp_path / "out") == 0o750
    pngs = list((tmp_path / "plots").glob("*.png"))
    assert pngs and {mode(p) for p in pngs} == {0o640}
