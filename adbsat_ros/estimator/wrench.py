"""The wrench at one attitude once the flight conditions are known: the model's coefficients at
the gas motion relative to the body, body axes."""

from __future__ import annotations

import datetime as _dt
import time
from typing import NamedTuple

from adbsat_ros.environment.conditions import FlightConditions
from adbsat_ros.estimator.samples import JointSample, Rejection, WrenchSample
from adbsat_ros.physics.model import Model
from adbsat_ros.physics.model_evaluate import Joints


class Moment(NamedTuple):
    """What a sample records of its message: stamp [s], UTC, conditions, attitude (body to state
    frame, row-major) and when its computation began (``time.perf_counter``)."""

    stamp: float
    time: _dt.datetime
    conditions: FlightConditions
    rotation: tuple
    started: float


def wrench_sample(
    model: Model, gas_body, flow, changes: dict | None, joints: Joints | None, moment: Moment
) -> WrenchSample:
    """The wrench of ``model`` (at ``joints``) for the gas motion ``gas_body`` (body axes).

    ``changes``: the surface's ``alpha`` and ``alpha_n``, or None. Rejection ``outside_database`` or
    ``compute_error``.
    """
    q = flow.dynamic_pressure()
    try:
        coefficients = model.evaluate(flow, gas_body, joints, changes=changes)
    except ValueError as exc:
        reason = "outside_database" if model.lookup is not None else "compute_error"
        raise Rejection(reason, str(exc)) from None
    sample = None
    if joints is not None:
        sample = JointSample(coefficients, q, model.body.links)
        coefficients = coefficients.total
    reference = coefficients.reference
    return WrenchSample(
        stamp=moment.stamp,
        time=moment.time,
        force=coefficients.force(q),
        torque=coefficients.torque(q),
        force_coefficients=coefficients.Cf_G,
        moment_coefficients=coefficients.Cm_G,
        reference_area=reference.area,
        reference_length=reference.length,
        dynamic_pressure=q,
        conditions=moment.conditions,
        coefficients=None if model.lookup is not None else coefficients,
        flow_direction_body=coefficients.flow_direction,
        compute_seconds=time.perf_counter() - moment.started,
        rotation=moment.rotation,
        joints=sample,
    )
