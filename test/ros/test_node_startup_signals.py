"""adbsat_node (plain and --managed) and adbsat_orbit_publisher signalled in their start-up, from
the first instruction of their console scripts on: exit status 0, one line that says so, no
traceback."""

from __future__ import annotations

import signal

import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

from signal_probes import console_script, signal_in_start_up  # noqa: E402

#: How far into its start-up each run signals: once it has mapped this many more files (0: as
#: soon as it handles signals; rclpy, the messages and the mesh come later).
START_UP_POINTS = (0, 20, 60, 120, 180)


def own_lines(err: str) -> list:
    """stderr without the ROS log lines (``[INFO] [...] [adbsat_node]: ...``)."""
    return [line for line in err.strip().splitlines() if not line.startswith("[")]


@pytest.mark.parametrize(
    "script, args",
    [
        ("adbsat_node", ["--ros-args", "-p", "mesh:=example", "-r", "__ns:=/startup_signal"]),
        ("adbsat_node", ["--managed", "--ros-args", "-r", "__ns:=/startup_signal_managed"]),
        ("adbsat_orbit_publisher", ["--duration", "600", "--ros-args", "-r", "__ns:=/startup"]),
    ],
    ids=["node", "managed", "orbit_publisher"],
)
def test_a_signal_in_start_up_stops_the_tool_cleanly(script, args):
    hit = 0
    for k, more in enumerate(START_UP_POINTS):
        signum = signal.SIGTERM if k % 2 else signal.SIGINT
        ended = signal_in_start_up([*console_script(script), *args], more, signum)
        if ended is None:
            continue
        hit += 1
        status, _, err = ended
        assert status == 0, (script, more, status, err)
        assert "Traceback" not in err and "ExceptionWrapper" not in err, (script, more, err)
        assert own_lines(err) == [f"{script}: stopped by {signum.name}"], (script, more, err)
    assert hit == len(START_UP_POINTS)


@pytest.mark.parametrize(
    "argv, expected",
    [
        (["bag", "record", "{out}/rec", "--topics", "/startup_rec:std_msgs/msg/String"], 0),
        (["bag", "play", "{bag}", "--rate", "0.01"], 0),
        (["echo", "/startup_echo", "--timeout", "600"], 0),
        (["param", "list", "startup_nobody", "--timeout", "600"], 1),
        (["demo", "--duration", "600", "--out-dir", "{out}/demo"], 1),
    ],
    ids=["bag record", "bag play", "echo", "param", "demo"],
)
def test_a_signal_in_start_up_ends_a_live_tool_with_its_status(argv, expected, tmp_path):
    """The tools that run until stopped (bag play, bag record, echo) exit with 0, the others
    with 1 (they did not finish); no traceback, and one line on stderr or the tool's own
    summary says it was stopped."""
    from adbsat_ros.bags import io as bag_io
    from adbsat_ros.bags import scenario

    bag = tmp_path / "in"
    bag_io.write_scenario_bag(scenario.generate(scenario.Scenario(duration_s=60)), bag)
    hit = 0
    for k, more in enumerate(START_UP_POINTS):
        out = tmp_path / str(k)
        out.mkdir()
        args = [a.format(out=out, bag=bag) for a in argv]
        signum = signal.SIGTERM if k % 2 else signal.SIGINT
        ended = signal_in_start_up([*console_script("adbsat-ros"), *args], more, signum)
        if ended is None:
            continue
        hit += 1
        status, stdout, err = ended
        assert status == expected, (argv, more, status, err)
        assert "Traceback" not in err, (argv, more, err)
        said = [line for line in own_lines(err) if "stopped" in line or "interrupted" in line]
        said += [line for line in stdout.splitlines() if line.startswith(("stopped", "wrote"))]
        said += [line for line in stdout.splitlines() if "interrupted" in line]
        assert said, (argv, more, stdout, err)
    assert hit >= 1
