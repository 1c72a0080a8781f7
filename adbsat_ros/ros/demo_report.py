"""The demo's result record, the node's samples by stamp, and the CSV and plots it writes."""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from adbsat_ros.bags.table import COEFFICIENT_COLUMNS, WRENCH_COLUMNS
from adbsat_ros.plotting.panels import plot_panel_pressure
from adbsat_ros.plotting.time_series import plot_time_series
from adbsat_ros.ros import demo_joints


@dataclass
class DemoResult:
    """What the demo did: counts, timing, the files written."""

    attitudes_sent: int = 0
    states_sent: int = 0
    wrenches_received: int = 0
    rejected: dict = field(default_factory=dict)
    mismatched: int = 0
    compute_ms_p50: float = math.nan
    latency_ms_p50: float = math.nan
    latency_ms_p99: float = math.nan
    files: list = field(default_factory=list)
    interrupted: bool = False


class SampleLog:
    """Keeps every WrenchSample the node publishes, by stamp [ns] (a node sample listener)."""

    def __init__(self):
        self.samples: dict = {}

    def __call__(self, sample):
        """Keep ``sample`` (a WrenchSample) under its stamp [ns]."""
        self.samples[round(sample.stamp * 1e9)] = sample


def vector(v):
    """(x, y, z) of a geometry_msgs Vector3."""
    return (v.x, v.y, v.z)


CSV_COLUMNS = (
    "time_s",
    "stamp_s",
    "altitude_m",
    "density_kg_m3",
    "relative_speed_m_s",
    "drag_coefficient",
    *WRENCH_COLUMNS,
    *COEFFICIENT_COLUMNS,
    "compute_ms",
    "latency_ms",
)


def table_rows(received, samples, sent_wall, t0_ns, result: DemoResult, joints=False) -> list:
    """One row per wrench received, in stamp order; fills ``result``'s figures."""
    rows = []
    for key in sorted(received):
        wrench, coefficients, wall = received[key]
        if wrench is None or coefficients is None:
            continue
        sample = samples.get(key)
        force, torque = (np.array(vector(v)) for v in (wrench.wrench.force, wrench.wrench.torque))
        if sample is None or not (
            np.array_equal(force, sample.force) and np.array_equal(torque, sample.torque)
        ):
            result.mismatched += 1
            continue
        c = sample.conditions
        rows.append(
            (
                (key - t0_ns) * 1e-9,
                key * 1e-9,
                c.altitude,
                c.mass_density,
                c.speed,
                sample.drag_coefficient,
                *force,
                *torque,
                *vector(coefficients.wrench.force),
                *vector(coefficients.wrench.torque),
                1e3 * sample.compute_seconds,
                1e3 * (wall - sent_wall[key]) if key in sent_wall else math.nan,
                *(demo_joints.csv_values(sample) if joints else ()),
            )
        )
    result.wrenches_received = sum(1 for v in received.values() if v[0] is not None)
    if rows:
        table = np.array(rows)
        compute, latency = CSV_COLUMNS.index("compute_ms"), CSV_COLUMNS.index("latency_ms")
        result.compute_ms_p50 = float(np.median(table[:, compute]))
        result.latency_ms_p50 = float(np.nanpercentile(table[:, latency], 50))
        result.latency_ms_p99 = float(np.nanpercentile(table[:, latency], 99))
    return rows


def write_outputs(rows, out_dir: Path, picture=None, joints=False) -> list:
    """Write demo_wrench.csv and the PNGs in ``out_dir`` (more with picture, joints); the paths."""
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "demo_wrench.csv"
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(CSV_COLUMNS + (demo_joints.CSV_COLUMNS if joints else ()))
        # (repr: each number exactly, the UNIX stamps with their fraction of a second)
        writer.writerows([[repr(float(v)) for v in row] for row in rows])
    table = np.array(rows)
    col = {name: i for i, name in enumerate(CSV_COLUMNS)}
    run = {
        "force": table[:, col["force_x_N"] : col["force_z_N"] + 1],
        "torque": table[:, col["torque_x_Nm"] : col["torque_z_Nm"] + 1],
        "density": table[:, col["density_kg_m3"]],
        "drag_coefficient": table[:, col["drag_coefficient"]],
    }
    plots = plot_time_series(
        table[:, col["time_s"]], {"adbsat_node (live)": run}, out_dir, prefix="demo_"
    )
    if joints:
        plots.append(
            demo_joints.plot_hinge_torques(
                table[:, len(CSV_COLUMNS) :],
                out_dir / "demo_hinge_torques.png",
            )
        )
    if picture is not None:
        model, mesh, flow, coefficients = picture
        plots.append(
            plot_panel_pressure(
                model,
                flow,
                math.degrees(coefficients.aoa),
                math.degrees(coefficients.aos),
                out_dir / "demo_panel_pressure.png",
                result=coefficients,
                mesh=mesh,
            )
        )
    return [path, *plots]
