"""What ``adbsat_node --help`` prints (from the table of :mod:`adbsat_ros.estimator.parameters`)."""

from __future__ import annotations

from adbsat_ros.estimator.parameters import PARAMETERS, READ_ONLY_PARAMETERS, parameter_range_text

NODE_NAME = "adbsat_node"

#: The node's topics: (name, type, direction, meaning), for ``adbsat_node --help``.
TOPICS = (
    ("attitude", "geometry_msgs/QuaternionStamped", "in", "body orientation in the state frame"),
    ("state", "nav_msgs/Odometry", "in", "orbital state, ECI or ECEF (state_frame)"),
    ("joint_states", "sensor_msgs/JointState", "in", "joint positions (articulated body)"),
    ("wrench", "geometry_msgs/WrenchStamped", "out", "force [N], torque about the CoM [N m]"),
    ("coefficients", "geometry_msgs/WrenchStamped", "out", "C_F and C_M (while subscribed)"),
    ("wrench_inertial", "geometry_msgs/WrenchStamped", "out", "force in the state frame [N]"),
    ("acceleration", "geometry_msgs/AccelStamped", "out", "force / mass [m/s^2] (with a mass)"),
    ("solar_wrench", "geometry_msgs/WrenchStamped", "out", "solar pressure (solar_pressure)"),
    ("total_wrench", "geometry_msgs/WrenchStamped", "out", "aerodynamic + solar (solar_pressure)"),
    (
        "joint_torques",
        "sensor_msgs/JointState",
        "out",
        "aerodynamic torque per joint (effort; while subscribed)",
    ),
    ("panel_marker", "visualization_msgs/Marker", "out", "panels coloured by c_p (RViz)"),
    ("/diagnostics", "diagnostic_msgs/DiagnosticArray", "out", "health, every period"),
)


def help_text() -> str:
    """``adbsat_node --help``: usage, topics, every parameter's default, valid range and meaning."""
    lines = [
        f"usage: {NODE_NAME} [--help] [--managed] --ros-args [--params-file FILE] "
        "[-p NAME:=VALUE ...]",
        "",
        "--managed: the managed (lifecycle) node: configure, activate, deactivate, cleanup, "
        "shutdown (ends the process).",
        "",
        "Aerodynamic force and torque of a satellite in free-molecular flow, for every attitude "
        "message.",
        "",
        "topics:",
    ]
    lines += [f"  {n:<16} {d:<4} {t:<32} {m}" for n, t, d, m in TOPICS]
    lines += [
        "  (inputs BEST_EFFORT, which takes RELIABLE publishers too; outputs RELIABLE; set with",
        "  -p qos_overrides./TOPIC.<publisher|subscription>.<reliability|depth|history>:=VALUE)",
    ]
    lines += ["", "parameters (config/adbsat.yaml documents each; read-only ones marked):"]
    for p in PARAMETERS:
        flags = " (read-only)" if p.name in READ_ONLY_PARAMETERS else ""
        lines.append(f"  {p.name} = {p.default!r}{flags}")
        lines.append(f"      {p.text}")
        valid = parameter_range_text(p.name)
        if valid:
            lines.append(f"      valid: {valid}")
    return "\n".join(lines)
