"""The articulated demo (``adbsat-ros demo --articulated``): nadir-pointing ``example-finned``.

The pitch fins deflect by :data:`AMPLITUDE_DEG` sin(2 pi t / T); yaw fins lag a quarter period.
"""

from __future__ import annotations

import math
from pathlib import Path

from adbsat_ros.plotting.figures import new_figure, save_png

#: The bundled body of the articulated demo.
BODY = "example-finned"
#: Its moving joints, in the URDF's order.
JOINTS = ("fin_py_hinge", "fin_ny_hinge", "fin_pz_hinge", "fin_nz_hinge")
#: Largest fin deflection [deg] (the hinges allow 34 deg).
AMPLITUDE_DEG = 10.0
#: The shading's configuration grid [deg] for fins that move with every message, its points
#: blended (``joint_shading_interpolation``) so that the torques are continuous in the
#: deflections (the nearest point would step them a cell at a time).
SHADING_GRID_DEG = 2.0


def fin_positions(fraction: float) -> tuple:
    """The four fins' positions [rad] at ``fraction`` of the run (0 to 1)."""
    amplitude = math.radians(AMPLITUDE_DEG)
    pitch = amplitude * math.sin(2.0 * math.pi * fraction)
    yaw = amplitude * math.sin(2.0 * math.pi * fraction + 0.5 * math.pi)
    return (pitch, pitch, yaw, yaw)


def joint_state(cls, stamp_ns: int, positions):
    """A sensor_msgs/JointState (class ``cls``) of :data:`JOINTS` at ``positions``."""
    msg = cls()
    msg.header.stamp.sec, msg.header.stamp.nanosec = divmod(int(stamp_ns), 1_000_000_000)
    msg.name = list(JOINTS)
    msg.position = [float(p) for p in positions]
    return msg


#: The table's extra columns: heading, unit row.
TABLE_HEADER = (f"{'pitch fin':>9} {'hinge T':>10}", f"{'[deg]':>9} {'[N m]':>10}")


def table_cells(sample) -> str:
    """The pitch fin's deflection and hinge torque of a WrenchSample (blank without joints)."""
    joints = None if sample is None else sample.joints
    if joints is None:
        return f"{'':>9} {'':>10}"
    return f"{math.degrees(joints.positions[0]):9.2f} {joints.efforts[0]:10.3e}"


#: CSV columns added per joint NAME.
CSV_COLUMNS = tuple(f"{name}_{c}" for name in JOINTS for c in ("deg", "torque_Nm"))


def csv_values(sample) -> tuple:
    """The :data:`CSV_COLUMNS` of a WrenchSample (NaN without joints)."""
    joints = sample.joints
    if joints is None:
        return (math.nan,) * len(CSV_COLUMNS)
    out = []
    for position, effort in zip(joints.positions, joints.efforts):
        out += [math.degrees(position), effort]
    return tuple(out)


def plot_hinge_torques(time_s, table, out_path: Path) -> Path:
    """Every fin's hinge torque and the pitch fins' deflection against time, as a PNG."""
    fig = new_figure()
    ax = fig.add_subplot()
    for k, name in enumerate(JOINTS):
        ax.plot(time_s, table[:, 2 * k + 1], label=name.replace("_hinge", ""))
    ax.set_xlabel("simulated time [s]")
    ax.set_ylabel("aerodynamic hinge torque [N m]")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", fontsize="small")
    twin = ax.twinx()
    twin.plot(time_s, table[:, 0], "k:", label="pitch fins' deflection")
    twin.set_ylabel("pitch fins' deflection [deg]")
    twin.legend(loc="upper right", fontsize="small")
    ax.set_title("Fin hinge torques while the fins steer (adbsat_node, live)")
    return save_png(fig, out_path)
