"""The commands of the shell blocks of README.md and docs/*.md run as written after the README's
install: ``.venv/bin/`` is the venv this suite runs in, the working directory a new one holding
the checkout's config/. One-shot commands exit 0, a block's commands in order in one directory;
the node of the docs' own command starts, answers the commands that need it (``param``,
``echo``) and stops on Ctrl-C with 0; a block that starts its own node in the background runs
whole, on this run's ROS domain. :data:`NOT_RUN` names the commands left out and why;
:data:`CHEAP` those run with ``--help`` after their options (argparse checks every option before
it) instead of in full, and why."""

import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

from waiting import HANG_TIMEOUT

ROOT = Path(__file__).resolve().parents[2]
#: The venv's scripts: the README installs into ./.venv, the suite runs in the venv it made.
BIN = Path(sys.executable).parent
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]

#: Commands not run (a regular expression searched in the command) and why.
NOT_RUN = {
    r"^python3 -m venv": "the README's install (and its test command, which .ci/run runs): this "
    "suite runs in the venv it makes; test_demo.py runs the demo",
    r"^(rosdep|colcon|pip|mkdir|source|\. |install/)": "a ROS 2 workspace built with rosdep and "
    "colcon (docs/ros-workspace.md), not the README's install",
    r"adbsat_node --ros-args -p qos_overrides\.": "a node with QoS overrides runs until stopped "
    "(test/ros/test_node_graph.py starts one with overrides and checks the endpoints)",
    r"^export ": "only sets the environment of the commands after it (a block that starts its own "
    "node runs whole, its exports too)",
}
#: Commands run with --help after their options instead, and why.
CHEAP = {
    r" coeff .*--method (both|tpmc)": "test particles to 0.1 % run for minutes "
    "(test/physics/test_tpmc.py runs the solver)",
    r" (simulate|bag analyze) ": "a flight of 90 minutes or 3 days and its analysis "
    "(test_cli_simulate.py and test_cli_bag.py run short ones)",
}
#: The docs' command that starts the node, and those that need it running.
NODE = r"/adbsat_node --ros-args --params-file config/adbsat\.yaml$"
NEEDS_NODE = r"/adbsat-ros (param|echo) "


def shell_blocks() -> list:
    """(file, [command, ...]) of every bash, sh or console block, continuation lines joined."""
    out = []
    for path in DOCS:
        text = path.read_text(encoding="utf-8")
        for block in re.findall(r"^```(?:bash|sh|console)\n(.*?)^```", text, re.S | re.M):
            commands, command = [], ""
            for line in block.splitlines():
                line = line.removeprefix("$ ").rstrip()
                command += line.removesuffix("\\").strip() + " "
                if not line.endswith("\\"):
                    commands.append(command.strip())
                    command = ""
            out.append((path.name, [c for c in commands if c]))
    return out


BLOCKS = shell_blocks()


def kind(command: str) -> str:
    """ "not run", "cheap", "node", "needs node" or "run"."""
    if any(re.search(p, command) for p in NOT_RUN):
        return "not run"
    if any(re.search(p, command) for p in CHEAP):
        return "cheap"
    if re.search(NODE, command):
        return "node"
    return "needs node" if re.search(NEEDS_NODE, command) else "run"


def in_background(commands) -> bool:
    """Whether a block starts a job in the background (then it runs whole, as a script)."""
    return any(c.endswith("&") for c in commands)


def as_installed(command: str) -> str:
    return command.replace(".venv/bin/", f"{BIN}/")


def run(command: str, cwd: Path) -> subprocess.CompletedProcess:
    proc = subprocess.run(
        ["bash", "-c", as_installed(command)],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=HANG_TIMEOUT * 10,
    )
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, (command, proc.stderr)
    return proc


@pytest.fixture
def workdir(tmp_path):
    (tmp_path / "config").symlink_to(ROOT / "config")
    return tmp_path


def test_every_command_is_written_to_run_and_run_or_named_with_its_reason():
    commands = [c for _, block in BLOCKS for c in block]
    assert len(commands) > 20 and {kind(c) for c in commands} == {
        "not run",
        "cheap",
        "node",
        "needs node",
        "run",
    }
    for pattern in (*NOT_RUN, *CHEAP):  # no stale entries
        assert any(re.search(pattern, c) for c in commands), pattern
    bare = [c for c in commands if re.match(r"(adbsat-ros|adbsat_node|adbsat_\w+) ", c)]
    assert not bare, f"not found after the README's install (use .venv/bin/): {bare}"


ONE_SHOT = [
    pytest.param(block, id=f"{name}:{block[0][:50]}")
    for name, block in BLOCKS
    if not in_background(block) and {kind(c) for c in block} & {"run", "cheap"}
]


@pytest.mark.parametrize("block", ONE_SHOT)
def test_a_blocks_commands_run_as_written(block, workdir):
    for command in block:
        if kind(command) == "run":
            assert run(command, workdir).stdout.strip(), f"{command}: printed nothing"
        elif kind(command) == "cheap":
            help_text = run(re.sub(r"\s+#.*$", "", command) + " --help", workdir).stdout
            assert help_text.startswith("usage: adbsat-ros"), command


def test_the_node_starts_answers_the_commands_that_need_it_and_stops_on_ctrl_c(workdir):
    node = [c for _, block in BLOCKS for c in block if kind(c) == "node"]
    needing = [c for _, block in BLOCKS for c in block if kind(c) == "needs node"]
    assert len(set(node)) == 1 and needing
    proc = subprocess.Popen(
        ["bash", "-c", f"exec {as_installed(node[0])}"],
        cwd=workdir,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    try:
        lines = []
        deadline = time.monotonic() + HANG_TIMEOUT
        while time.monotonic() < deadline:  # up once it says what it publishes
            lines.append(proc.stdout.readline())
            if "publishing" in lines[-1] or not lines[-1]:
                break
        assert "publishing" in lines[-1], "".join(lines)
        for command in needing:
            run(command, workdir)
    finally:
        proc.send_signal(signal.SIGINT)
        out, _ = proc.communicate(timeout=HANG_TIMEOUT)
    assert proc.returncode == 0 and "Traceback" not in out, out


@pytest.mark.parametrize(
    "block", [pytest.param(b, id=f"{n}:{b[1][:40]}") for n, b in BLOCKS if in_background(b)]
)
def test_a_block_with_its_own_node_runs_whole_on_this_runs_domain(block, workdir):
    domain = os.environ["ROS_DOMAIN_ID"]
    script = re.sub(r"ROS_DOMAIN_ID=\d+", f"ROS_DOMAIN_ID={domain}", "\n".join(block))
    proc = run(script + "\nwait", workdir)  # (the node's own exit status, after the kill)
    assert proc.stdout.strip()
