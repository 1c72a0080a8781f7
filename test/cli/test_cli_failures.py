"""How a command that cannot do its work ends: one line ``adbsat-ros COMMAND: error: ...`` and
status 1 (a value not allowed: status 2), whatever the command."""

from __future__ import annotations

import importlib

import pytest

from adbsat_ros.cli import main
from adbsat_ros.cli import options as cli_options


@pytest.fixture
def without_ros(monkeypatch):
    """The ROS tools as on a machine without the ROS 2 Python packages."""
    real = importlib.import_module

    def import_module(name, *args):
        if name.startswith("adbsat_ros.ros."):
            raise ImportError("No module named 'rclpy'")
        return real(name, *args)

    monkeypatch.setattr(cli_options.importlib, "import_module", import_module)


@pytest.mark.parametrize(
    "argv, command",
    [
        (["echo", "/wrench"], "echo"),
        (["param", "list", "adbsat_node"], "param"),
        (["bag", "play", "somewhere"], "bag play"),
        (["bag", "record", "out", "--topics", "/attitude"], "bag record"),
        (["demo", "--duration", "1"], "demo"),
    ],
)
def test_a_live_tool_without_ros_says_what_to_install(argv, command, without_ros, capsys):
    assert main(argv) == 1
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and captured.out == ""
    assert lines[0].startswith(f"adbsat-ros {command}: error: needs the ROS 2 Python packages")
    assert "No module named 'rclpy'" in lines[0] and "pip install 'adbsat_ros[ros]'" in lines[0]


@pytest.mark.parametrize(
    "argv, message",
    [
        (["bag", "play", "b", "--rate", "0"], "--rate must be a finite number > 0, got '0'"),
        (["bag", "record", "o", "--topics", "/a", "--storage", "zip"], "invalid choice: 'zip'"),
        (["echo", "/w", "--count", "0"], "--count must be a whole number >= 1, got '0'"),
        (["param", "list", "n", "--timeout", "-1"], "--timeout must be a finite number > 0"),
        (["simulate", "--out", "x", "--rate", "0"], "--rate"),
        (["simulate", "--out", "x", "--attitude-topic", "a//b"], "must be a ROS topic name"),
        (["plot", "db.npz", "--aoa", "inf"], "--aoa must be a finite angle in degrees"),
    ],
)
def test_an_option_value_out_of_range_is_a_usage_error_naming_the_option(argv, message, capsys):
    with pytest.raises(SystemExit) as stop:
        main(argv)
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and message in err


def test_the_shared_options_keep_their_defaults():
    from adbsat_ros.cli import build_parser

    parser = build_parser(("bag", "echo", "param", "simulate"))
    play = parser.parse_args(["bag", "play", "b"])
    record = parser.parse_args(["bag", "record", "o", "--topics", "/a"])
    assert (play.qos_depth, play.rate, play.wait_timeout) == (1000, 1.0, 30.0)
    assert (record.qos_depth, record.storage, record.duration) == (1000, "mcap", None)
    assert parser.parse_args(["echo", "/w"]).timeout == 5.0
    assert parser.parse_args(["echo", "/w"]).count is None  # (until Ctrl-C)
    assert parser.parse_args(["param", "list", "n"]).timeout == 5.0
    simulate = parser.parse_args(["simulate", "--out", "x"])
    assert (simulate.storage, simulate.overwrite, simulate.state_topic) == ("mcap", False, "/state")


def test_the_echo_rate_summary():
    from adbsat_ros.cli.echo import rate_summary

    assert rate_summary([]) == "0 messages" and rate_summary([3.0]) == "1 message"
    assert rate_summary([1.0, 1.5, 2.0, 3.0]) == "4 messages, mean rate 1.5 Hz over 2.000 s"
