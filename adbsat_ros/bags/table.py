"""The bag analysis's table: its CSV columns, and a model's cells and plot numbers of one message.

One row per message that asked some model for a wrench (attitudes; states for models whose
``attitude_source`` is odometry): the columns :data:`COMMON_COLUMNS`, then per model ``LABEL``
the group :data:`MODEL_COLUMNS` prefixed with ``LABEL.``. Numbers are written with ``repr``
(exact round trip); a model without a wrench for the message has its status (the rejection
reason, or empty if the message was not for it) and NaN.
"""

from __future__ import annotations

import math

import numpy as np

from adbsat_ros.geometry.frames import angles_of_flow

#: Columns shared by all models.
COMMON_COLUMNS = ("stamp_s", "utc", "time_s", "topic")
#: Columns of each model's group, prefixed with "LABEL." in the CSV. wind_body is the velocity of
#: the gas relative to the body in body axes; aoa/aos are ADBSat's angles of that flow (frames.py).
MODEL_COLUMNS = (
    "status",
    "altitude_m",
    "density_kg_m3",
    "temperature_K",
    "relative_speed_m_s",
    "wind_body_x_m_s",
    "wind_body_y_m_s",
    "wind_body_z_m_s",
    "aoa_deg",
    "aos_deg",
    "drag_coefficient",
    "CF_x",
    "CF_y",
    "CF_z",
    "CM_x",
    "CM_y",
    "CM_z",
    "force_x_N",
    "force_y_N",
    "force_z_N",
    "torque_x_Nm",
    "torque_y_Nm",
    "torque_z_Nm",
)
#: The columns of MODEL_COLUMNS plotted (force, torque, density, drag coefficient), in order.
PLOT_COLUMNS = (
    "force_x_N",
    "force_y_N",
    "force_z_N",
    "torque_x_Nm",
    "torque_y_Nm",
    "torque_z_Nm",
    "density_kg_m3",
    "drag_coefficient",
)
_PLOT_INDEX = [MODEL_COLUMNS.index(c) for c in PLOT_COLUMNS]
_NAN_CELLS = ",nan" * (len(MODEL_COLUMNS) - 1)
_NAN_PLOT = [math.nan] * len(PLOT_COLUMNS)


def header(labels) -> list:
    """The CSV header for the models ``labels``."""
    return list(COMMON_COLUMNS) + [f"{label}.{c}" for label in labels for c in MODEL_COLUMNS]


def row_values(status: str, sample) -> list:
    """A model's cells (``status``, then floats; NaN where nothing was computed) of a
    WrenchSample, or of None."""
    if sample is None:
        return [status] + [math.nan] * (len(MODEL_COLUMNS) - 1)
    c = sample.conditions
    u = sample.flow_direction_body
    wind = u * c.speed
    if np.any(u):
        aoa, aos = angles_of_flow(u)
        aoa, aos = math.degrees(aoa), math.degrees(aos)
    else:
        aoa = aos = math.nan
    # plain Python floats: the csv module writes them (repr, exact round trip) far faster than
    # numpy's
    return [
        status,
        float(c.altitude),
        float(c.mass_density),
        float(c.temperature),
        float(c.speed),
        *wind.tolist(),
        aoa,
        aos,
        float(sample.drag_coefficient),
        *np.concatenate(
            [sample.force_coefficients, sample.moment_coefficients, sample.force, sample.torque]
        ).tolist(),
    ]


def model_cells(outcomes) -> tuple[str, list]:
    """The models' cells of one row as CSV text, and their plot numbers (PLOT_COLUMNS per model,
    in order), from each model's :class:`~adbsat_ros.estimator.handling.Outcome`."""
    cells, plot = [], []
    for outcome in outcomes:
        sample = outcome.sample
        if sample is None:
            status = outcome.status
            cells.append(("" if status is None else status) + _NAN_CELLS)
            plot.extend(_NAN_PLOT)
        else:
            values = row_values("ok", sample)
            cells.append(",".join(["ok", *map(repr, values[1:])]))
            plot.extend(values[i] for i in _PLOT_INDEX)
    return ",".join(cells), plot


def utc_text(utc_of, stamp_s: float) -> str:
    """``utc_of(stamp_s)`` in ISO format, or empty if the stamp has no UTC."""
    try:
        return utc_of(stamp_s).isoformat()
    except (OverflowError, ValueError, OSError):
        return ""
