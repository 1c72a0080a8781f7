"""The physics core (mesh, models, shading, atmosphere, estimator, CLI) imports no rclpy."""

import subprocess
import sys

CORE_MODULES = [
    "adbsat_ros", "adbsat_ros.mesh", "adbsat_ros.gsi_models", "adbsat_ros.panel_method",
    "adbsat_ros.shading", "adbsat_ros.shading_cache", "adbsat_ros.solar", "adbsat_ros.atmosphere",
    "adbsat_ros.flight_conditions", "adbsat_ros.accommodation", "adbsat_ros.aero_wrench",
    "adbsat_ros.wrench_settings", "adbsat_ros.cli", "adbsat_ros.database", "adbsat_ros.coefficient_lookup",
    "adbsat_ros.database_coefficients", "adbsat_ros.plots", "adbsat_ros.scenario", "adbsat_ros.bag_io",
    "adbsat_ros.bag_analysis", "adbsat_ros.earth_frames", "adbsat_ros.freestream",
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
    code = "import sys, adbsat_ros.node; print('rclpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.stdout.strip() == "True", out.stderr
