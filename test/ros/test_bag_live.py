"""Live rosbag tools with real rclpy: play and record round trips, a bag played into the node
against the offline analysis of the same bag, and the errors of ``bag play`` / ``bag record``.

Everything runs on the test run's own ROS_DOMAIN_ID with discovery limited to localhost
(conftest.py); each play/record call makes its own rclpy Context.
"""

import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

import dataclasses
import threading
import time

import numpy as np
import rclpy
from geometry_msgs.msg import WrenchStamped
from rclpy.qos import QoSProfile, ReliabilityPolicy
from ros_harness import HANG_TIMEOUT, make_context, spinning

from adbsat_ros.bags import io as bag_io
from adbsat_ros.bags import scenario
from adbsat_ros.bags.analysis import analyze_bag
from adbsat_ros.bags.io import BagError
from adbsat_ros.cli import main as cli_main
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.ros import bag_play
from adbsat_ros.ros.bag_play import play
from adbsat_ros.ros.bag_record import record
from adbsat_ros.ros.graph import message_class
from adbsat_ros.ros.node import AdbsatNode

MS = 1_000_000
T0_NS = 1_750_000_000 * 1_000_000_000  # a UNIX time in 2025


def stamp_ns(stamp) -> int:
    """builtin_interfaces/Time as integer nanoseconds."""
    return int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec)


def as_plain(value):
    """A rosbags message (nested dataclasses, numpy arrays) as nested tuples, for comparisons."""
    if dataclasses.is_dataclass(value):
        return tuple(
            (f.name, as_plain(getattr(value, f.name)))
            for f in dataclasses.fields(value)
            if f.name != "__msgtype__"
        )
    if isinstance(value, np.ndarray):
        return tuple(value.tolist())
    if isinstance(value, (list, tuple)):
        return tuple(as_plain(v) for v in value)
    return value


def read_bag(path):
    """{topic: [(log time ns, message)]} of a bag, read with rosbags."""
    out = {}
    reader = bag_io.open_bag(path)
    try:
        for conn, t, raw in reader.messages():
            out.setdefault(conn.topic, []).append((t, bag_io.deserialize(raw, conn.msgtype)))
    finally:
        reader.close()
    return out


def small_bag(path, storage="mcap"):
    """20 attitudes every 50 ms and 10 odometries every 100 ms (25 ms after), distinct contents."""
    records = []
    for k in range(20):
        t = T0_NS + k * 50 * MS
        angle = 0.1 * k
        q = (0.0, 0.0, np.sin(angle / 2), np.cos(angle / 2))
        records.append(("/attitude", t, bag_io.quaternion_stamped_message(t, "eci", q)))
    for k in range(10):
        t = T0_NS + k * 100 * MS + 25 * MS
        records.append(
            (
                "/state",
                t,
                bag_io.odometry_message(
                    t,
                    "eci",
                    "body",
                    (6.7e6 + k, -2.0 * k, 0.5),
                    (1.0, 7.6e3 - k, 0.25 * k),
                    (0.0, 0.6, 0.0, 0.8),
                    angular_velocity=(0.01 * k, 0.0, -0.02),
                ),
            )
        )
    records.sort(key=lambda r: r[1])
    return bag_io.write_bag(path, records, storage=storage)


class Recorder:
    """record() running in a thread until stop(); its summary afterwards."""

    def __init__(self, out, topics, storage):
        self.stop_event, self.ready = threading.Event(), threading.Event()
        self.summary = self.error = None

        def run():
            try:
                self.summary = record(
                    out, topics, storage=storage, stop=self.stop_event, ready=self.ready
                )
            except Exception as exc:  # reported by stop()
                self.error = exc

        self.thread = threading.Thread(target=run, daemon=True)
        self.thread.start()

    def stop(self):
        self.stop_event.set()
        self.thread.join(timeout=HANG_TIMEOUT)
        assert not self.thread.is_alive()
        if self.error:
            raise self.error
        return self.summary


@pytest.mark.parametrize("storage, rate", [("mcap", 1.0), ("sqlite3", 2.0)])
def test_play_then_record_round_trip(tmp_path, storage, rate, monkeypatch):
    """Every message comes back as it was; play() holds each until its time in the bag over the
    rate after the first (its schedule), and none is received before that time."""
    source = small_bag(tmp_path / "source")
    out = tmp_path / "recorded"
    schedule = []  # the time.monotonic() play() waits for before each message, in bag order
    sleep_until = bag_play._sleep_until

    def scheduled_sleep(deadline, stop):
        schedule.append(deadline)
        return sleep_until(deadline, stop)

    monkeypatch.setattr(bag_play, "_sleep_until", scheduled_sleep)
    recorder = Recorder(out, ["/attitude", "/state:nav_msgs/msg/Odometry"], storage)
    # the recorder stamps receive times with time.time_ns(): its offset from time.monotonic_ns()
    wall_offset_ns = time.time_ns() - time.monotonic_ns()
    played = play(source, rate=rate, wait_for_subscribers=1, wait_timeout=HANG_TIMEOUT)
    # play() returns once the recorder acknowledged every message; record() drains its queues
    # when stopped
    summary = recorder.stop()
    assert played.published == {"/attitude": 20, "/state": 10}
    assert summary.recorded == {"/attitude": 20, "/state": 10}
    assert summary.types == {"/attitude": bag_io.QUATERNION_STAMPED, "/state": bag_io.ODOMETRY}
    assert (out / "metadata.yaml").exists()
    assert any(p.suffix == (".mcap" if storage == "mcap" else ".db3") for p in out.iterdir())

    original, copy = read_bag(source), read_bag(out)
    assert set(copy) == {"/attitude", "/state"}
    bag_times = sorted(t for msgs in original.values() for t, _ in msgs)
    # the schedule keeps the recorded spacing, scaled by the rate
    np.testing.assert_allclose(
        np.subtract(schedule, schedule[0]),
        np.subtract(bag_times, bag_times[0]) * 1e-9 / rate,
        rtol=0,
        atol=1e-9,
    )
    due_ns = {t: round(deadline * 1e9) + wall_offset_ns for t, deadline in zip(bag_times, schedule)}
    for topic in original:
        assert [as_plain(m) for _, m in copy[topic]] == [as_plain(m) for _, m in original[topic]], (
            topic
        )
        # each received no earlier than its time (however much later the machine's load makes it;
        # the clocks' offset is read to well within the 1 ms allowed here)
        for (t, _), (received, _) in zip(original[topic], copy[topic]):
            assert received >= due_ns[t] - MS, (topic, t)


def test_loop_restarts_from_the_beginning(tmp_path):
    source = small_bag(tmp_path / "source")
    ctx, executor = make_context()
    stamps, stop = [], threading.Event()
    node = rclpy.create_node("loop_listener", context=ctx)

    def on_attitude(raw):
        msg = bag_io.deserialize(raw, bag_io.QUATERNION_STAMPED)
        stamps.append(stamp_ns(msg.header.stamp))
        if len(stamps) >= 45:
            stop.set()

    node.create_subscription(
        message_class(bag_io.QUATERNION_STAMPED),
        "/attitude",
        on_attitude,
        QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE),
        raw=True,
    )
    executor.add_node(node)
    try:
        with spinning(executor):
            summary = play(
                source,
                rate=4.0,
                loop=True,
                topics=["attitude"],
                wait_for_subscribers=1,
                wait_timeout=HANG_TIMEOUT,
                stop=stop,
            )
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown(context=ctx)
    one_pass = [T0_NS + k * 50 * MS for k in range(20)]
    assert summary.passes >= 3 and summary.interrupted
    assert set(summary.published) == {"/attitude"}
    assert stamps[:45] == (one_pass * 3)[:45]


def test_played_bag_through_the_node_equals_the_offline_analysis(tmp_path):
    """THE check of the rosbag tools: a simulated flight played live into adbsat_node gives, wrench
    by wrench and bit for bit, what `bag analyze` computes from the same bag without ROS."""
    sim = scenario.Scenario(
        epoch_utc="2025-06-21T12:00:00Z",
        duration_s=4.0,
        rate_hz=10.0,
        state_rate_hz=2.0,
        altitude_km=300.0,
        attitude="tumble",
        tumble_rate_deg_s=1.0,
        tumble_axis=(0.3, 1.0, 0.2),
    )
    messages = scenario.generate(sim)
    # States 50 ms before the attitudes that share their stamps: each state comes before the
    # attitude of its stamp in the bag, so the node, served in arrival order, handles them in
    # bag order, as the analysis does.
    states = messages.states
    messages = scenario.ScenarioMessages(
        sim,
        scenario.StateRecords(states.stamps_ns - 50 * MS, states.position_eci, states.velocity_eci),
        messages.attitudes,
    )
    bag = bag_io.write_scenario_bag(messages, tmp_path / "flight")
    n_attitudes = len(messages.attitudes.stamps_ns)

    settings = WrenchSettings.from_parameters(
        {}
    )  # the node's defaults: example satellite, raycast shading
    report = analyze_bag(bag, models=[("offline", settings)], out_bag=tmp_path / "analysed")
    offline = {
        stamp_ns(m.header.stamp): m
        for _, m in read_bag(tmp_path / "analysed")["/adbsat/offline/wrench"]
    }
    assert report.wrenches == len(offline) == n_attitudes

    # the events executor (the node's default) serves messages in the order they arrive, which
    # is bag order, whether or not the node keeps up with the bag's pace
    ctx, executor = make_context("events")
    node = AdbsatNode(
        context=ctx, parameter_overrides=[rclpy.parameter.Parameter("qos_depth", value=1000)]
    )
    listener = rclpy.create_node("wrench_listener", context=ctx)
    live = {}
    listener.create_subscription(
        WrenchStamped,
        "/wrench",
        lambda m: live.setdefault(stamp_ns(m.header.stamp), m),
        QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE),
    )
    executor.add_node(node)
    executor.add_node(listener)
    try:
        with spinning(executor):
            deadline = time.monotonic() + HANG_TIMEOUT
            while node.wrench_pub.get_subscription_count() < 1 and time.monotonic() < deadline:
                time.sleep(0.02)
            played = play(bag, rate=1.0, wait_for_subscribers=1, wait_timeout=HANG_TIMEOUT)
            deadline = time.monotonic() + HANG_TIMEOUT
            while len(live) < n_attitudes and time.monotonic() < deadline:
                time.sleep(0.02)
        estimator = node.estimator
        rejections = {k: v for k, v in estimator.rejections.items() if v}
        counts = estimator.diagnostic_values(None, [])
        hits, misses = counts["shading_cache_hits"], counts["shading_cache_misses"]
    finally:
        executor.shutdown()
        listener.destroy_node()
        node.destroy_node()
        rclpy.try_shutdown(context=ctx)

    assert played.published == {"/attitude": n_attitudes, "/state": len(states.stamps_ns)}
    assert rejections == {}
    assert hits > 0 and misses > 0  # the shading cache was used both ways
    assert sorted(live) == sorted(offline)
    for stamp, msg in live.items():
        ref = offline[stamp]
        for part in ("force", "torque"):
            got = np.array([getattr(getattr(msg.wrench, part), c) for c in "xyz"])
            want = np.array([getattr(getattr(ref.wrench, part), c) for c in "xyz"])
            assert np.linalg.norm(want) > 0
            np.testing.assert_array_equal(got, want, err_msg=f"{part} at stamp {stamp} ns")


# ----------------------------------------------------------------------------- errors
def test_play_missing_bag_and_unknown_topic_fail_clearly(tmp_path, capsys):
    assert cli_main(["bag", "play", str(tmp_path / "nowhere")]) == 1
    err = capsys.readouterr().err
    assert "bag play: error:" in err and "nowhere" in err and "no such file" in err

    source = small_bag(tmp_path / "source")
    assert cli_main(["bag", "play", str(source), "--topics", "/attitude", "/wrench"]) == 1
    err = capsys.readouterr().err
    assert "no topic /wrench" in err and "/attitude, /state" in err


def test_play_message_type_not_installed_names_topic_and_type(tmp_path):
    with bag_io.BagWriter(tmp_path / "custom") as writer:
        conn = writer.connection(
            "/thing", "my_robot_msgs/msg/Thing", msgdef="float64 x\n", digest="RIHS01_" + "0" * 64
        )
        writer.write_raw(conn, T0_NS, bytes([0, 1, 0, 0]) + bytes(8))
    with pytest.raises(
        BagError, match=r"topic /thing: message type 'my_robot_msgs/msg/Thing' is not installed"
    ):
        play(tmp_path / "custom")


def test_play_times_out_without_subscribers(tmp_path):
    source = small_bag(tmp_path / "source")
    with pytest.raises(
        BagError, match=r"no 1 subscriber\(s\) within 0.3 s on topic\(s\) /attitude, /state"
    ):
        play(source, wait_for_subscribers=1, wait_timeout=0.3)


def test_record_without_topics_or_into_an_existing_path_fails_clearly(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        cli_main(["bag", "record", str(tmp_path / "out")])
    assert exc.value.code == 2
    assert "--topics" in capsys.readouterr().err
    assert cli_main(["bag", "record", str(tmp_path / "out"), "--topics", " "]) == 1
    assert "empty topic name" in capsys.readouterr().err
    with pytest.raises(BagError, match="no topics given"):
        record(tmp_path / "out", [])
    existing = small_bag(tmp_path / "existing")
    assert (
        cli_main(["bag", "record", str(existing), "--topics", "/attitude", "--duration", "1"]) == 1
    )
    assert "already exists" in capsys.readouterr().err
    assert (
        cli_main(["bag", "record", str(tmp_path / "out"), "--topics", "/a:no_pkg/msg/Nothing"]) == 1
    )
    assert "'no_pkg/msg/Nothing' is not installed" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_record_for_a_duration_writes_a_readable_empty_bag_and_names_silent_topics(
    tmp_path, capsys
):
    out = tmp_path / "quiet"
    start = time.monotonic()
    assert (
        cli_main(
            [
                "bag",
                "record",
                str(out),
                "--topics",
                "/nobody_publishes_this",
                "--storage",
                "sqlite3",
                "--duration",
                "0.5",
            ]
        )
        == 0
    )
    assert time.monotonic() - start >= 0.5  # (however much longer it takes to stop)
    captured = capsys.readouterr()
    assert "0 messages" in captured.out
    assert "no publisher ever appeared on /nobody_publishes_this" in captured.err
    assert read_bag(out) == {}
