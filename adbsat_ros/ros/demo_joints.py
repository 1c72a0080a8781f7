"""The articulated demo (``adbsat-ros demo --articulated``): nadir-pointing ``example-finned``.

The pitch fins deflect by :data:`AMPLITUDE_DEG` sin(2 pi t / T); yaw fins lag a quarter period.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

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


#: The table's extra columns: heading, unit row.
TABLE_HEADER = (f"{'pitch fin':>9} {'hinge T':>10}", f"{'[deg]':>9} {'[N m]':>10}")


def table_cells(sample) -> str:
    """The pitch fin's deflection and hinge torque of a WrenchSample (blank without joints)."""
    joints = None if sample is None else sample.joints
    if joints is None:
        return f"{'':>9} {'':>10}"
    return f"{math.degrees(joints.positions[0]):9.2f} {joints.efforts[0]:10.3e}"


#: CSV columns added per joint NAME, as bag analysis names them (docs/outputs.md).
CSV_COLUMNS = tuple(f"joint.{name}.{c}" for name in JOINTS for c in ("position_rad", "effort_Nm"))


def csv_values(sample) -> tuple:
    """The :data:`CSV_COLUMNS` of a WrenchSample (NaN without joints)."""
    joints = sample.joints
    if joints is None:
        return (math.nan,) * len(CSV_COLUMNS)
    return tuple(np.column_stack([joints.positions, joints.efforts]).ravel().tolist())


#: Each fin's line style and marker: the fins of a pair take the same torques, so the second line
#: of a pair is drawn over the first with a different dash and marker.
FIN_STYLES = (("-", "o"), ("--", "x"), ("-", "s"), ("--", "+"))


def plot_hinge_torques(table, out_path: Path) -> Path:
    """Every fin's hinge torque against its deflection [deg], as a PNG (``table``: the rows'
    :data:`CSV_COLUMNS`)."""
    fig = new_figure()
    ax = fig.add_subplot()
    for k, (name, (line, marker)) in enumerate(zip(JOINTS, FIN_STYLES)):
        ax.plot(
            np.degrees(table[:, 2 * k]),
            table[:, 2 * k + 1],
            ls=line,
            marker=marker,
            markevery=max(1, len(table) // 12),
            mfc="none",
            label=name.replace("_hinge", ""),
        )
    ax.set_xlabel("fin deflection [deg]")
    ax.set_ylabel("aerodynamic hinge torque [N m]")
    ax.grid(True, alpha=0.3)
    ax.legend(title="fin (py, ny: pitch; pz, nz: yaw)", fontsize="small")
    ax.set_title("Fin hinge torques against deflection (adbsat_node, live)")
    return save_png(fig, out_path)
