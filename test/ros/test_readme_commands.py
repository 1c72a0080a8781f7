"""The README's shell commands run as written (from the repository root, with its .venv): the
one-shot commands finish with status 0; the node starts, reaches its spin loop and stops
cleanly on Ctrl-C. The two set-up commands (a fresh venv each) are what .ci/run itself runs
(the test command verbatim) or what test_demo.py runs (the demo)."""

import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

import re
import signal
import subprocess
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
VENV_TOOL = ROOT / ".venv" / "bin" / "adbsat-ros"


def readme_commands() -> list:
    """Every command of the README's bash blocks, continuation lines joined."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    commands = []
    for block in re.findall(r"```bash\n(.*?)```", text, re.S):
        command = ""
        for line in block.splitlines():
            command += line.rstrip("\\").strip() + " "
            if not line.endswith("\\"):
                commands.append(command.strip())
                command = ""
    return [c for c in commands if c]


COMMANDS = [c for c in readme_commands() if "python3 -m venv" not in c]


def test_the_readme_has_the_commands_this_test_runs():
    commands = readme_commands()
    assert sum("python3 -m venv" in c for c in commands) == 2  # the two set-up commands
    assert any("adbsat_node" in c for c in COMMANDS) and len(COMMANDS) >= 2


@pytest.mark.skipif(not VENV_TOOL.exists(), reason="the README's commands use ./.venv")
@pytest.mark.parametrize("command", COMMANDS)
def test_a_readme_command_runs_as_written(command):
    if command.startswith(".venv/bin/adbsat_node"):
        proc = subprocess.Popen(
            ["bash", "-c", f"exec {command}"],
            cwd=ROOT,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )
        lines = []
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:  # up once it says what it publishes
            line = proc.stdout.readline()
            lines.append(line)
            if "publishing" in line or not line:
                break
        assert any("publishing" in line for line in lines), "".join(lines)
        proc.send_signal(signal.SIGINT)
        out, _ = proc.communicate(timeout=30)
        assert proc.returncode == 0 and "Traceback" not in out, out
        return
    proc = subprocess.run(
        ["bash", "-c", command], cwd=ROOT, capture_output=True, text=True, timeout=600
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip(), "the command printed nothing"
