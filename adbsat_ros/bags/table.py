"""CSV columns: :data:`COMMON_COLUMNS`, then per model ``LABEL.`` + :data:`MODEL_COLUMNS`.

Numbers written with ``repr`` (exact round trip); a model without a wrench: its status and NaN.
"""

from __future__ import annotations

import math

import numpy as np

from adbsat_ros.geometry.frames import angles_of_flow

#: Columns shared by all models.
COMMON_COLUMNS = ("stamp_s", "utc", "time_s", "topic")
#: Force [N] and torque [N m] columns, body frame: ``force_x_N`` ... ``torque_z_Nm``.
WRENCH_COLUMNS = tuple(
    f"{q}_{a}_{unit}" for q, unit in (("force", "N"), ("torque", "Nm")) for a in "xyz"
)
#: The force and moment coefficients, body frame.
COEFFICIENT_COLUMNS = ("cf_x", "cf_y", "cf_z", "cm_x", "cm_y", "cm_z")
#: Columns of each model's group, prefixed with "LABEL." in the CSV. wind_body is the velocity of
#: the gas relative to the body in body axes; aoa/aos are ADBSat's angles of that flow (frames.py).
MODEL_COLUMNS = (
    "status",
    "altitude_m",
    "density_kg_m3",
    "temperature_K",
    "relative_speed_m_s",
    *(f"wind_body_{a}_m_s" for a in "xyz"),
    "aoa_deg",
    "aos_deg",
    "drag_coefficient",
    *COEFFICIENT_COLUMNS,
    *WRENCH_COLUMNS,
)
#: Columns appended to the group of a model with ``solar_pressure`` on: the fraction of the solar
#: disc visible past the Earth, and the solar radiation force and torque (body frame).
SOLAR_COLUMNS = ("sun_lit_fraction", *(f"solar_{c}" for c in WRENCH_COLUMNS))
#: Columns first in the group of a model with ``space_weather`` historical: the indices in force.
WEATHER_COLUMNS = ("f107_sfu", "f107a_sfu", "ap")
#: The columns of MODEL_COLUMNS plotted (force, torque, density, drag coefficient), in order.
PLOT_COLUMNS = (*WRENCH_COLUMNS, "density_kg_m3", "drag_coefficient")
#: Plotted after them: the drag (the force along the flow) [N], and F10.7 and Ap in force.
WEATHER_PLOT = ("drag_N", "f107", "ap")
#: The plotted numbers of each model, in order.
PLOT_SERIES = len(PLOT_COLUMNS) + len(WEATHER_PLOT)
_PLOT_INDEX = [MODEL_COLUMNS.index(c) - 1 for c in PLOT_COLUMNS]  # (in row_values: no status)
_NAN_CELLS = ",nan" * (len(MODEL_COLUMNS) - 1)
_NAN_PLOT = [math.nan] * PLOT_SERIES
#: The columns of each moving joint ``NAME`` of an articulated body, as ``joint.NAME.<suffix>``:
#: its position and the aerodynamic effort on it, a revolute joint's, then a prismatic one's.
JOINT_COLUMNS = {"revolute": ("position_rad", "effort_Nm"), "prismatic": ("position_m", "effort_N")}


def extra_columns(solar: bool, joints=None, weather: bool = False) -> tuple:
    """A model's columns after :data:`MODEL_COLUMNS`: space weather, solar ones, every joint's
    (``joints``: name to joint, with its ``kind``)."""
    joints = tuple(
        f"joint.{name}.{c}"
        for name, joint in (joints or {}).items()
        for c in JOINT_COLUMNS["prismatic" if joint.kind == "prismatic" else "revolute"]
    )
    return (WEATHER_COLUMNS if weather else ()) + (SOLAR_COLUMNS if solar else ()) + joints


def model_extra_columns(estimator) -> tuple:
    """The :func:`extra_columns` of a model's AeroWrenchEstimator."""
    body = estimator.body
    s = estimator.settings
    joints = None if body is None else body.joints
    return extra_columns(s.solar_pressure, joints, s.space_weather != "fixed")


def header(labels, extras=()) -> list:
    """The CSV header for the models ``labels`` (``extras``: each model's :func:`extra_columns`)."""
    extras = tuple(extras) or ((),) * len(labels)
    return list(COMMON_COLUMNS) + [
        f"{label}.{c}"
        for label, more in zip(labels, extras, strict=True)
        for c in MODEL_COLUMNS + tuple(more)
    ]


def row_values(sample) -> list:
    """A model's numbers (the cells after its status) of a WrenchSample; NaN where undefined."""
    c = sample.conditions
    u = sample.flow_direction_body
    speed = float(c.speed)
    ux, uy, uz = u.tolist()
    if ux or uy or uz:
        aoa, aos = angles_of_flow(u)
        aoa, aos = math.degrees(aoa), math.degrees(aos)
    else:
        aoa = aos = math.nan
    # plain Python floats for the csv module
    return [
        float(c.altitude),
        float(c.mass_density),
        float(c.temperature),
        speed,
        ux * speed,
        uy * speed,
        uz * speed,
        aoa,
        aos,
        float(sample.drag_coefficient),
        *sample.force_coefficients.tolist(),
        *sample.moment_coefficients.tolist(),
        *sample.force.tolist(),
        *sample.torque.tolist(),
    ]


def extra_values(sample, columns) -> list:
    """A WrenchSample's values for :func:`extra_columns` (NaN for what it lacks, e.g. no joints)."""
    out = []
    if columns[: len(WEATHER_COLUMNS)] == WEATHER_COLUMNS:
        w = sample.conditions.space_weather
        out += [math.nan] * 3 if w is None else [float(w.f107), float(w.f107a), float(w.ap)]
        columns = columns[len(WEATHER_COLUMNS) :]
    if columns[: len(SOLAR_COLUMNS)] == SOLAR_COLUMNS:
        solar = sample.solar
        columns = columns[len(SOLAR_COLUMNS) :]
        if solar is None:
            out += [math.nan] * len(SOLAR_COLUMNS)
        else:
            out += [float(solar.lit_fraction), *solar.force.tolist(), *solar.torque.tolist()]
    joints = sample.joints
    if joints is None:
        out += [math.nan] * len(columns)
    else:
        out += np.column_stack([joints.positions, joints.efforts]).ravel().tolist()
    return out


def model_cells(outcomes, extras=()) -> tuple[str, list]:
    """The models' cells of one row as CSV text, and their plot numbers, from their Outcomes."""
    cells, plot = [], []
    extras = tuple(extras) or ((),) * len(outcomes)
    for outcome, more in zip(outcomes, extras, strict=True):
        sample = outcome.sample
        if sample is None:
            status = outcome.status
            cells.append(("" if status is None else status) + _NAN_CELLS + ",nan" * len(more))
            plot.extend(_NAN_PLOT)
        else:
            values = row_values(sample)
            if more:
                values += extra_values(sample, more)
            cells.append(",".join(["ok", *map(repr, values)]))
            plot.extend(values[i] for i in _PLOT_INDEX)
            wind, force = values[4:7], values[16:19]  # (the gas's velocity, the force: body)
            speed = values[3]
            drag = sum(f * w for f, w in zip(force, wind)) / speed if speed else math.nan
            weather = sample.conditions.space_weather
            f107, ap = (math.nan, math.nan) if weather is None else (weather.f107, weather.ap)
            plot += (drag, f107, ap)
    return ",".join(cells), plot


def utc_text(utc_of, stamp_s: float, sample=None) -> str:
    """``utc_of(stamp_s)`` in ISO format, or empty; ``sample``'s time is used if at ``stamp_s``."""
    if sample is not None and sample.stamp == stamp_s:
        return sample.time.isoformat()
    try:
        return utc_of(stamp_s).isoformat()
    except (OverflowError, ValueError, OSError):
        return ""
