"""``adbsat-ros simulate`` and ``adbsat-ros bag analyze`` end to end, and bad bags: each gives a
clear message, a non-zero exit status, and never a half-written output."""

import csv
import os
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag2 import Reader
from signal_probes import descendants, ignores, wait_gone
from waiting import HANG_TIMEOUT, wait_for

from adbsat_ros.bags import io as bag_io
from adbsat_ros.bags import scenario
from adbsat_ros.cli import main

YAML = """adbsat_node:
  ros__parameters:
    shading: "none"
    gsi_model: "{model}"
"""


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def leftovers(directory):
    return sorted(p.name for p in Path(directory).rglob("*") if "partial" in p.name)


def simulate(capsys, path, *extra):
    code, out, err = run(
        capsys, "simulate", "--duration", 10, "--rate", 2, "--state-rate", 1, "--out", path, *extra
    )
    assert code == 0, err
    return out


def test_simulate_then_analyze_two_models(tmp_path, capsys):
    out = simulate(capsys, tmp_path / "sim", "--storage", "sqlite3", "--attitude", "tumble")
    assert "11 Odometry on /state, 21 QuaternionStamped on /attitude" in out
    assert (tmp_path / "sim" / "sim.db3").is_file()
    for model in ("sentman", "newton"):
        (tmp_path / f"{model}.yaml").write_text(YAML.format(model=model))
    code, out, err = run(
        capsys,
        "bag",
        "analyze",
        tmp_path / "sim",
        "--params",
        tmp_path / "sentman.yaml",
        "--params",
        tmp_path / "newton.yaml",
        "--no-plots",
        "--workers",
        2,
    )
    assert code == 0, err
    assert "model sentman: 21 wrenches from 21 inputs" in out and "model newton: 21 wrenches" in out
    out_bag = tmp_path / "sim_aero"
    with Reader(out_bag) as reader:
        counts = {c.topic: c.msgcount for c in reader.connections}
    assert counts["/adbsat/sentman/wrench"] == counts["/adbsat/newton/wrench"] == 21
    assert (out_bag / "sim_aero.mcap").is_file()
    with open(tmp_path / "sim_aero.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 21
    newton = np.array([float(r["newton.force_x_N"]) for r in rows])
    sentman = np.array([float(r["sentman.force_x_N"]) for r in rows])
    assert np.all(newton != sentman)
    # running again without --overwrite refuses and leaves the outputs alone
    code, _, err = run(capsys, "bag", "analyze", tmp_path / "sim", "--no-plots")
    assert code == 1 and "already exists" in err and "--overwrite" in err
    assert leftovers(tmp_path) == []


def test_labels_must_match_params(tmp_path, capsys):
    simulate(capsys, tmp_path / "sim")
    (tmp_path / "a.yaml").write_text(YAML.format(model="sentman"))
    code, _, err = run(
        capsys,
        "bag",
        "analyze",
        tmp_path / "sim",
        "--params",
        tmp_path / "a.yaml",
        "--label",
        "x",
        "--label",
        "y",
    )
    assert code == 2 and "--label" in err
    code, _, err = run(
        capsys, "bag", "analyze", tmp_path / "sim", "--params", tmp_path / "missing.yaml"
    )
    assert code == 2 and "missing.yaml" in err
    with pytest.raises(SystemExit) as exit_info:  # argparse rejects it
        main(["bag", "analyze", str(tmp_path / "sim"), "--workers", "0"])
    assert (
        exit_info.value.code == 2
        and "--workers must be a whole number >= 1, got '0'" in capsys.readouterr().err
    )


def test_missing_topic(tmp_path, capsys):
    simulate(capsys, tmp_path / "sim")
    code, _, err = run(
        capsys, "bag", "analyze", tmp_path / "sim", "--attitude-topic", "/att", "--no-plots"
    )
    assert code == 1
    assert (
        "no topic /att (given by --attitude-topic)" in err
        and "/attitude (geometry_msgs/msg/QuaternionStamped)" in err
    )
    assert not (tmp_path / "sim_aero").exists() and leftovers(tmp_path) == []


def test_topic_with_another_message_type(tmp_path, capsys):
    string = bag_io.TYPESTORE.types["std_msgs/msg/String"]
    records = [
        (
            "/state",
            1_000_000_000,
            bag_io.odometry_message(1_000_000_000, "eci", "eci", [7e6, 0, 0], [0, 7.5e3, 0]),
        ),
        ("/attitude", 1_000_000_000, string(data="not a quaternion")),
    ]
    bag_io.write_bag(tmp_path / "bad", records)
    code, _, err = run(capsys, "bag", "analyze", tmp_path / "bad", "--no-plots")
    assert code == 1
    assert (
        "topic /attitude (given by --attitude-topic) has message type std_msgs/msg/String; "
        "expected geometry_msgs/msg/QuaternionStamped"
    ) in err


@pytest.mark.parametrize("storage, suffix", [("mcap", ".mcap"), ("sqlite3", ".db3")])
def test_truncated_file(tmp_path, capsys, storage, suffix):
    simulate(capsys, tmp_path / "sim", "--storage", storage)
    data_file = tmp_path / "sim" / f"sim{suffix}"
    data = data_file.read_bytes()
    data_file.write_bytes(data[: len(data) * 2 // 3])
    code, _, err = run(capsys, "bag", "analyze", data_file, "--no-plots")
    assert code == 1
    assert f"input bag {data_file}: cannot be read" in err and "complete?" in err
    assert not (tmp_path / "sim_aero").exists() and leftovers(tmp_path) == []


@pytest.mark.parametrize(
    "bad_topic, message, wrenches",
    [
        (
            "/attitude",
            "message 10 on /attitude cannot be decoded as geometry_msgs/msg/QuaternionStamped",
            4,
        ),
        ("/state", "message 9 on /state cannot be decoded as nav_msgs/msg/Odometry", 4),
    ],
)
def test_corrupt_message_gives_partial_outputs(tmp_path, capsys, bad_topic, message, wrenches):
    """An undecodable message stops the replay; what came before is written under names that say
    PARTIAL, and nothing under the final names."""
    r, v = [6.7e6, 0, 0], [0, 7.7e3, 0]
    t0 = 1_767_225_600_000_000_000
    with bag_io.BagWriter(tmp_path / "bad") as writer:
        for k in range(6):
            t = t0 + k * 500_000_000
            if k == 4 and bad_topic == "/state":
                writer.write_raw(
                    writer.connection("/state", bag_io.ODOMETRY), t, b"\x00\x01\x00\x00\x07"
                )
            else:
                writer.write("/state", t, bag_io.odometry_message(t, "eci", "eci", r, v))
            if k == 4 and bad_topic == "/attitude":
                writer.write_raw(
                    writer.connection("/attitude", bag_io.QUATERNION_STAMPED),
                    t,
                    b"\x00\x01\x00\x00\x07",
                )
            else:
                writer.write(
                    "/attitude", t, bag_io.quaternion_stamped_message(t, "eci", [0, 0, 0, 1])
                )
    code, out, err = run(capsys, "bag", "analyze", tmp_path / "bad", "--no-plots")
    assert code == 1
    assert message in err
    assert "PARTIAL" in err and f"model default: {wrenches} wrenches from {wrenches} inputs" in out
    assert not (tmp_path / "bad_aero").exists() and not (tmp_path / "bad_aero.csv").exists()
    assert f"wrote bag: {tmp_path / 'bad_aero.PARTIAL'}" in out
    with Reader(tmp_path / "bad_aero.PARTIAL") as reader:
        counts = {c.topic: c.msgcount for c in reader.connections}
    assert counts["/adbsat/default/wrench"] == wrenches
    with open(tmp_path / "bad_aero.PARTIAL.csv") as fh:
        assert len(fh.readlines()) == 1 + wrenches
    assert leftovers(tmp_path) == []


def test_attitude_before_any_state(tmp_path, capsys):
    t0 = 1_767_225_600_000_000_000
    r, v = [6.7e6, 0, 0], [0, 7.7e3, 0]
    records = [
        (
            "/attitude",
            t0 + k * 100_000_000,
            bag_io.quaternion_stamped_message(t0 + k * 100_000_000, "eci", [0, 0, 0, 1]),
        )
        for k in range(10)
    ]
    records.insert(
        5,
        ("/state", t0 + 450_000_000, bag_io.odometry_message(t0 + 450_000_000, "eci", "eci", r, v)),
    )
    bag_io.write_bag(tmp_path / "late", records)
    code, out, err = run(capsys, "bag", "analyze", tmp_path / "late", "--no-plots")
    assert code == 0
    assert "5 messages on /attitude came before the first usable state on /state" in err
    assert "model default: 5 wrenches from 10 inputs" in out
    with open(tmp_path / "late_aero.csv", newline="") as fh:
        status = [row["default.status"] for row in csv.DictReader(fh)]
    assert status == ["no_state"] * 5 + ["ok"] * 5
    # with no state at all before the last attitude there is nothing to analyse: an error
    records = [rec for rec in records if rec[0] == "/attitude"] + [
        (
            "/state",
            t0 + 2_000_000_000,
            bag_io.odometry_message(t0 + 2_000_000_000, "eci", "eci", r, v),
        )
    ]
    bag_io.write_bag(tmp_path / "never", records)
    code, out, err = run(capsys, "bag", "analyze", tmp_path / "never", "--no-plots")
    assert code == 1 and "10 messages on /attitude came before the first usable state" in err
    assert "no wrench could be computed" in err


def test_missing_input_and_unknown_format(tmp_path, capsys):
    code, _, err = run(capsys, "bag", "analyze", tmp_path / "nothing", "--no-plots")
    assert code == 1 and "no such file or directory" in err
    (tmp_path / "notes.txt").write_text("hello")
    code, _, err = run(capsys, "bag", "analyze", tmp_path / "notes.txt", "--no-plots")
    assert code == 1 and "notes.txt: cannot be read" in err


def test_simulate_rejects_bad_orbit(tmp_path, capsys):
    code, _, err = run(capsys, "simulate", "--out", tmp_path / "x", "--eccentricity", "1.2")
    assert code == 2 and "--eccentricity" in err
    assert not (tmp_path / "x").exists()


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_a_signal_stops_the_analysis_keeping_partial_outputs(tmp_path, signum):
    """Ctrl-C (SIGINT to the whole process group, workers included) or SIGTERM mid-analysis:
    the command stops before the end of the bag with one line and status 1; its outputs so far
    are kept under PARTIAL names, nothing under the final ones, no temporary files, no
    traceback."""
    messages = scenario.generate(scenario.Scenario(duration_s=1200, rate_hz=100, state_rate_hz=10))
    in_bag = len(messages.attitudes.stamps_ns) + len(messages.states.stamps_ns)
    bag_io.write_scenario_bag(messages, tmp_path / "long")
    cmd = [sys.executable, "-m", "adbsat_ros.cli", "bag", "analyze", str(tmp_path / "long")]
    cmd += ["--out", str(tmp_path / "out"), "--no-plots", "--workers", "2"]
    proc = subprocess.Popen(
        cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True
    )
    # the signal comes once rows are being written (the CSV in progress holds a flushed
    # buffer), however long this machine takes to start, read the bag and fork the workers
    assert wait_for(
        lambda: any(p.stat().st_size > 8192 for p in tmp_path.glob(".out.csv.*.partial")), proc
    ), "no rows were written"
    assert proc.poll() is None, "the analysis ended before the signal: give it a longer bag"
    # the workers leave a stop to the analysis: killed while sending a chunk's results, one would
    # leave half a message in the pool's pipe, which the pool would wait for forever
    workers = descendants(proc.pid)
    assert len(workers) >= 2 and all(ignores(p, signum) for p in workers)
    os.killpg(proc.pid, signum)
    out, err = proc.communicate(timeout=HANG_TIMEOUT)
    assert proc.returncode == 1 and "Traceback" not in err
    errors = [line for line in err.splitlines() if "error" in line]
    assert len(errors) == 1 and "stopped by a signal after" in errors[0]
    assert "PARTIAL" in errors[0]
    read = int(errors[0].split("stopped by a signal after ")[1].split()[0])
    assert 0 < read < in_bag  # stopped by the signal, not by the end of the bag
    assert not (tmp_path / "out").exists() and not (tmp_path / "out.csv").exists()
    with Reader(tmp_path / "out.PARTIAL") as reader:
        assert reader.message_count > 0
    assert f"wrote csv: {tmp_path / 'out.PARTIAL.csv'}" in out
    assert leftovers(tmp_path) == []
    assert not wait_gone(workers)


def test_a_flight_across_midnight_gets_each_days_indices_with_historical_space_weather(
    tmp_path, capsys
):
    """``--space-weather historical``: the CSV's f107, f107a, ap are the record's at each stamp,
    and change with the UTC day, as the density does; a plot shows them with the density."""
    import datetime as dt

    from adbsat_ros.environment.space_weather import HistoricalWeather

    simulate(capsys, tmp_path / "sim", "--epoch", "2015-01-18T23:59:55Z")
    options = ["--space-weather", "historical", "--atmosphere-model", "msis2.0"]
    code, _, err = run(capsys, "bag", "analyze", tmp_path / "sim", *options, "--workers", 1)
    assert code == 0, err
    with open(tmp_path / "sim_aero.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    record = HistoricalWeather()
    for row in rows:
        indices = record.at(dt.datetime.fromisoformat(row["utc"]))
        got = [float(row[f"default.{k}"]) for k in ("f107_sfu", "f107a_sfu", "ap")]
        assert got == [indices.f107, indices.f107a, indices.ap]
    first, last = rows[0], rows[-1]
    assert first["utc"].startswith("2015-01-18") and last["utc"].startswith("2015-01-19")
    assert first["default.f107_sfu"] != last["default.f107_sfu"]
    assert first["default.density_kg_m3"] != last["default.density_kg_m3"]
    # the replay's picture: density and drag with F10.7 and Ap
    assert (tmp_path / "sim_aero_plots" / "space_weather.png").stat().st_size > 1000
