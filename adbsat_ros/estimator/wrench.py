"""The wrench at one attitude once the flight conditions are known: from the coefficient
database, or from the panel method with the shading cache. Both take the gas motion relative to
the body in body axes.
"""

from __future__ import annotations

import datetime as _dt
import time
from typing import NamedTuple

from adbsat_ros.database.matching import DatabaseCoefficients
from adbsat_ros.environment.conditions import FlightConditions
from adbsat_ros.estimator.joints import JointConfiguration
from adbsat_ros.estimator.samples import JointSample, Rejection, WrenchSample
from adbsat_ros.estimator.shading import ShadingSource
from adbsat_ros.geometry.frames import unit_vector


class Moment(NamedTuple):
    """What a sample records of its message: stamp [s], UTC, conditions, attitude (body to state
    frame, row-major) and when its computation began (``time.perf_counter``)."""

    stamp: float
    time: _dt.datetime
    conditions: FlightConditions
    rotation: tuple
    started: float


def database_wrench(
    database: DatabaseCoefficients, reference, gas_body, q: float, moment: Moment
) -> WrenchSample:
    """The wrench of the database's coefficients at the flow direction ``gas_body`` (body axes)
    and dynamic pressure q [Pa].

    Raises
    ------
    Rejection
        ``outside_database``.
    """
    u_body = unit_vector(gas_body)
    try:
        cf, cm = database.body_coefficients(u_body)
    except ValueError as exc:
        raise Rejection("outside_database", str(exc)) from None
    return WrenchSample(
        stamp=moment.stamp,
        time=moment.time,
        force=q * reference.area * cf,
        torque=(q * reference.area * reference.length) * cm,
        force_coefficients=cf,
        moment_coefficients=cm,
        reference_area=reference.area,
        reference_length=reference.length,
        dynamic_pressure=q,
        conditions=moment.conditions,
        coefficients=None,
        flow_direction_body=u_body,
        shading_cache_hit=None,
        compute_seconds=time.perf_counter() - moment.started,
        rotation=moment.rotation,
    )


def panel_wrench(
    method,
    shading: ShadingSource,
    gas_body,
    flow,
    alpha: float | None,
    joints: JointConfiguration | None,
    moment: Moment,
) -> WrenchSample:
    """The wrench of the panel method (articulated: at ``joints``) at the flow direction
    ``gas_body`` (body axes); ``alpha`` from an accommodation model, or None for the materials'.

    Raises
    ------
    Rejection
        ``compute_error`` for what the panel method refuses.
    """
    # (the caches key on the direction)
    if joints is None:
        lighting, hit = shading.lighting(gas_body)
    else:
        lighting, hit = shading.lighting(gas_body, joints.positions, joints.vertices)
    surface = None if alpha is None else method.surface_with(alpha=alpha, alpha_n=alpha)
    q = flow.dynamic_pressure()
    sample = None
    try:  # (the panel method makes the direction a unit vector)
        if joints is None:
            coefficients = method.coefficients(
                flow, flow_direction=gas_body, lighting=lighting, surface=surface
            )
        else:
            articulated = method.coefficients(
                flow, joints.posed, flow_direction=gas_body, lighting=lighting, surface=surface
            )
            coefficients = articulated.total
            sample = joint_sample(method.body, articulated, q)
    except ValueError as exc:
        raise Rejection("compute_error", str(exc)) from None
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
        coefficients=coefficients,
        flow_direction_body=coefficients.flow_direction,
        shading_cache_hit=hit,
        compute_seconds=time.perf_counter() - moment.started,
        rotation=moment.rotation,
        joints=sample,
    )


def joint_sample(body, articulated, q: float) -> JointSample:
    """The joints and links of ``articulated`` coefficients at dynamic pressure q [Pa]."""
    return JointSample(articulated, q, body.links)
