"""``adbsat-ros simulate``'s refusals: sizes, memory, topics and epoch, each before any work with
one line naming the option and exit status 2."""

from __future__ import annotations

import pytest

from adbsat_ros import bounds
from adbsat_ros.bags import scenario
from adbsat_ros.cli import main


def refused(tmp_path, capsys, *argv) -> str:
    """The one line of a simulate refused with status 2 (no bag written)."""
    out = tmp_path / "flight"
    try:
        code = main(["simulate", "--out", str(out), *argv])
    except SystemExit as exited:
        code = exited.code
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert not out.exists()
    return err


@pytest.mark.parametrize("option", ["--rate", "--state-rate"])
def test_a_rate_beyond_a_megahertz_is_refused(option, tmp_path, capsys):
    err = refused(tmp_path, capsys, option, "1e9")
    assert f"{option} must be in {bounds.BOUNDS['message_rate'].text()}" in err


def test_too_many_messages_are_refused_with_their_count(tmp_path, capsys):
    err = refused(tmp_path, capsys, "--duration", "1e7", "--rate", "100")
    assert "--duration x --rate: the attitude messages (duration x rate + 1) must be in" in err
    assert "got 1000000001" in err


def test_a_flight_larger_than_the_memory_is_refused_with_its_estimate(
    tmp_path, capsys, monkeypatch
):
    sc = scenario.Scenario(duration_s=10.0, rate_hz=2.0, state_rate_hz=1.0)
    assert scenario.message_count(sc) == 21 + 11
    monkeypatch.setattr(bounds, "available_memory", lambda: scenario.memory_estimate(sc) - 1)
    err = refused(tmp_path, capsys, "--duration", "10", "--rate", "2", "--state-rate", "1")
    assert "the scenario (32 messages) needs about" in err and "available" in err


@pytest.mark.parametrize("topic", ["not a topic!", "/a//b", "/a/", "/2d", "/a__b", ""])
def test_a_topic_must_be_a_ros_topic_name(topic, tmp_path, capsys):
    err = refused(tmp_path, capsys, "--duration", "1", f"--attitude-topic={topic}")
    assert "--attitude-topic must be a ROS topic name" in err


def test_the_two_streams_need_two_topics(tmp_path, capsys):
    err = refused(
        tmp_path, capsys, "--duration", "1", "--attitude-topic", "/x", "--state-topic", "x"
    )
    assert "--state-topic: x is also the --attitude-topic" in err


def test_stamps_beyond_a_ros_stamps_int32_seconds_are_a_usage_error(tmp_path, capsys):
    err = refused(tmp_path, capsys, "--duration", "10", "--epoch", "2040-01-01T00:00:00Z")
    assert "--epoch: 10.0 s after 2040-01-01T00:00:00Z is beyond 2038-01-19T03:14:07Z" in err
    err = refused(tmp_path, capsys, "--duration", "1e9", "--rate", "0.01", "--state-rate", "0.01")
    assert "--duration: 1000000000.0 s after 2026-01-01T00:00:00Z is beyond 2038" in err
    out = tmp_path / "epoch_mode"
    argv = ["simulate", "--out", str(out), "--duration", "1", "--epoch", "2040-01-01T00:00:00Z"]
    assert main([*argv, "--time-mode", "epoch"]) == 0 and out.exists()


def test_an_epoch_before_1970_is_a_usage_error(tmp_path, capsys):
    err = refused(tmp_path, capsys, "--duration", "1", "--epoch", "1969-12-31T23:59:59Z")
    assert "--epoch: 1969-12-31T23:59:59Z is before 1970-01-01T00:00:00Z" in err
    out = tmp_path / "epoch_mode"
    argv = ["simulate", "--out", str(out), "--duration", "1", "--epoch", "1960-01-01T00:00:00Z"]
    assert main([*argv, "--time-mode", "epoch"]) == 0 and out.exists()
