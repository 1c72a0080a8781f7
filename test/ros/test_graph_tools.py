"""`adbsat-ros param` and `adbsat-ros echo` against a running adbsat_node process, with real
rclpy: what `ros2 param` and `ros2 topic echo` do, without the ros2 command."""

import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

import re
import signal
import subprocess
import sys

from ros_harness import HANG_TIMEOUT

from adbsat_ros.cli import main

#: --timeout for the commands that must find the node: they end as soon as it answers
WAIT = ["--timeout", str(HANG_TIMEOUT)]


@pytest.fixture(scope="module")
def node_process():
    """adbsat_node (the example, no shading, /diagnostics every 0.2 s) as its own process."""
    cmd = [sys.executable, "-m", "adbsat_ros.ros.node", "--ros-args"]
    cmd += ["-p", "shading:=none", "-p", "diagnostics_period:=0.2"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:  # (whatever happens, the process goes: a stray node would answer other tests)
        # up when it answers (however long this machine takes to start it)
        assert main(["param", "get", "adbsat_node", "mesh", *WAIT]) == 0, "the node did not answer"
        yield proc
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=HANG_TIMEOUT)
        except subprocess.TimeoutExpired:
            proc.kill()


def test_param_gets_sets_and_shows_a_rejection(node_process, capsys):
    capsys.readouterr()
    assert main(["param", "get", "adbsat_node", "f107", *WAIT]) == 0
    assert capsys.readouterr().out.strip() == "150.0"
    assert main(["param", "set", "adbsat_node", "f107", "200", *WAIT]) == 0
    assert capsys.readouterr().out.strip() == "set f107 = 200.0"
    assert main(["param", "get", "adbsat_node", "f107", *WAIT]) == 0
    assert capsys.readouterr().out.strip() == "200.0"
    assert main(["param", "set", "adbsat_node", "f107", "5000", *WAIT]) == 1
    err = capsys.readouterr().err
    assert "rejected f107=5000" in err and "f107 must be in [50, 500] sfu" in err
    assert main(["param", "get", "adbsat_node", "f107", *WAIT]) == 0
    assert capsys.readouterr().out.strip() == "200.0"  # the old value kept
    assert main(["param", "list", "adbsat_node", *WAIT]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert "mesh: 'example'" in lines and "shading: 'none'" in lines
    assert main(["param", "get", "adbsat_node", "no_such", *WAIT]) == 1
    assert "has no parameter 'no_such'" in capsys.readouterr().err


def test_param_names_a_missing_node(capsys):
    assert main(["param", "get", "nobody_here", "f107", "--timeout", "1"]) == 1
    err = capsys.readouterr().err
    assert "node nobody_here: its parameter services did not appear within 1 s" in err


def test_echo_prints_the_diagnostics(node_process, capsys):
    capsys.readouterr()
    assert main(["echo", "/diagnostics", "--count", "2", *WAIT]) == 0
    out = capsys.readouterr().out
    assert out.count("\n---") == 2 and "status:" in out and "  name: 'adbsat_node" in out
    assert "- level: 2" in out or "- level: 1" in out or "- level: 0" in out  # (a number)
    assert main(["echo", "/no_such_topic", "--timeout", "1"]) == 1
    assert "not in the ROS graph within 1 s" in capsys.readouterr().err


def test_echo_streams_until_sigint_and_says_the_rate(node_process):
    """Without --count it prints every message as it comes; SIGINT ends it with status 0 and
    the count and mean rate on stderr."""
    cmd = [sys.executable, "-m", "adbsat_ros.cli", "echo", "/diagnostics", *WAIT]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        ends = 0
        while ends < 3:  # (each line as it is printed: the stream is flushed message by message)
            line = proc.stdout.readline()
            assert line, f"echo ended: {proc.stderr.read()}"
            ends += line.strip() == "---"
        proc.send_signal(signal.SIGINT)
        rest, err = proc.communicate(timeout=HANG_TIMEOUT)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == 0, err
    summary = re.search(r"^adbsat-ros echo: stopped by SIGINT; (\d+) messages, mean rate (\S+) "
                        r"Hz over (\S+) s$", err, re.MULTILINE)  # fmt: skip
    assert summary, err
    count, rate, span = int(summary[1]), float(summary[2]), float(summary[3])
    assert count == 3 + rest.count("\n---")
    assert rate * span == pytest.approx(count - 1, rel=5e-3)  # (the mean interval, as printed)


def test_a_request_whose_answer_is_lost_is_sent_again(monkeypatch):
    """A server that has not matched the client's reply reader yet drops its reply: the tools
    send the request again until one answer comes, and return that one."""
    from rclpy.task import Future

    from adbsat_ros.ros import graph_tools

    monkeypatch.setattr(graph_tools, "RESEND_S", 0.0)
    sent = []

    def request():
        future = Future()
        sent.append(future)
        if len(sent) == 3:  # (the first two replies lost)
            future.set_result("answer")
        return future

    def spin():
        pass

    assert graph_tools._wait(spin, request, HANG_TIMEOUT, "node x") == "answer"
    assert len(sent) == 3 and not any(f.done() for f in sent[:2])
