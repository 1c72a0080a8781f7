"""The physics core (mesh, models, shading, atmosphere, estimator, CLI) imports no rclpy."""

import subprocess
import sys

CORE_MODULES = [
    "adbsat_ros",
    "adbsat_ros.geometry.mesh",
    "adbsat_ros.physics.gsi_models",
    "adbsat_ros.physics.panel_method",
    "adbsat_ros.shading.shader",
    "adbsat_ros.shading.cache",
    "adbsat_ros.physics.solar",
    "adbsat_ros.environment.atmosphere",
    "adbsat_ros.environment.flight_conditions",
    "adbsat_ros.environment.accommodation",
    "adbsat_ros.estimator.estimator",
    "adbsat_ros.estimator.settings",
    "adbsat_ros.cli",
    "adbsat_ros.database.build",
    "adbsat_ros.database.lookup",
    "adbsat_ros.database.matching",
    "adbsat_ros.plotting.coefficients",
    "adbsat_ros.bags.scenario",
    "adbsat_ros.bags.io",
    "adbsat_ros.bags.analysis",
    "adbsat_ros.environment.earth_frames",
    "adbsat_ros.physics.freestream",
]


def test_core_imports_no_rclpy():
    code = (
        "import importlib, sys\n"
        f"for m in {CORE_MODULES!r}: importlib.import_module(m)\n"
        "from adbsat_ros.cli import build_parser; build_parser()\n"
        "bad = sorted(m for m in sys.modules if m.split('.')[0] in ('rclpy', 'rosidl_runtime_py', 'geometry_msgs'))\n"
        "print(','.join(bad))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "", f"core imported ROS modules: {out.stdout}"


def test_node_module_does_import_rclpy():
    """The check above can fail: the node module really pulls rclpy in."""
    code = "import sys, adbsat_ros.ros.node; print('rclpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.stdout.strip() == "True", out.stderr
