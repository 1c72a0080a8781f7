"""launch/adbsat_managed.launch.py (for ROS installations; the launch package is not among the
pip wheels, so it cannot run here): what it names exists, and it is installed."""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LAUNCH = ROOT / "launch" / "adbsat_managed.launch.py"


def keyword_values(tree, call: str) -> dict:
    """The literal keyword arguments of the first call of ``call`` in ``tree``."""
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and getattr(node.func, "id", None) == call:
            values = {}
            for k in node.keywords:
                try:
                    values[k.arg] = ast.literal_eval(k.value)
                except ValueError:  # (not a literal: a substitution)
                    pass
            return values
    raise AssertionError(f"no call of {call}")


def test_the_launch_file_names_what_exists_and_is_installed():
    tree = ast.parse(LAUNCH.read_text(encoding="utf-8"))
    node = keyword_values(tree, "LifecycleNode")
    package_name = re.search(r"<name>(.+?)</name>", (ROOT / "package.xml").read_text()).group(1)
    assert node["package"] == package_name == "adbsat_ros"
    setup = (ROOT / "setup.py").read_text(encoding="utf-8")
    assert f'"{node["executable"]} = adbsat_ros.ros.entry_points:adbsat_node"' in setup
    assert node["name"] == "adbsat_node" and node["arguments"] == ["--managed"]
    assert '"launch/*.launch.py"' in setup  # installed to share/adbsat_ros/launch
    # the default parameters file it joins from the package's share directory
    assert '"config", "adbsat.yaml"' in LAUNCH.read_text(encoding="utf-8")
    assert (ROOT / "config" / "adbsat.yaml").is_file()
    for dependency in ("launch", "launch_ros", "lifecycle_msgs", "ament_index_python"):
        assert f"<exec_depend>{dependency}</exec_depend>" in (ROOT / "package.xml").read_text()
    assert "generate_launch_description" in {
        f.name for f in tree.body if isinstance(f, ast.FunctionDef)
    }
