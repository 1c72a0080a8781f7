"""The key/values of the estimator's diagnostics (the node's DiagnosticStatus, bag analysis)."""

from __future__ import annotations

import math

import numpy as np


def nearest_rank_percentiles(values) -> tuple | None:
    """``(p50, p99, max)`` of ``values`` (not modified) by nearest rank (the ceil(p n)-th smallest),
    or None if empty."""
    array = values if isinstance(values, np.ndarray) else np.fromiter(values, dtype=float)
    n = array.size
    if not n:
        return None
    ranks = [max(math.ceil(0.50 * n) - 1, 0), max(math.ceil(0.99 * n) - 1, 0), n - 1]
    return tuple(np.partition(array, ranks)[ranks].tolist())


def diagnostic_values(estimator, last_sample, compute_ms) -> dict:
    """Key/values of an estimator's diagnostics (the keys of docs/node.md, ``/diagnostics``): its
    settings, counters, reference, database, the ``compute_ms`` [ms] p50, p99 and max, the
    ``last_sample``'s conditions and solar wrench, joint counters and ``rejected_<reason>``."""
    s = estimator.settings
    knots = estimator.knots
    reference = estimator.method.reference
    cache = estimator.model.cache  # (None without shading or with a database)
    values = {
        "gsi_model": s.gsi_model,
        "coefficients_source": s.coefficients_source,
        "shading": s.shading,
        "space_weather": s.space_weather,
        "atmosphere_model": s.atmosphere_model,
        "published": estimator.published,
        "shading_cache_hits": 0 if cache is None else cache.hits,
        "shading_cache_misses": 0 if cache is None else cache.misses,
        "conditions_prepared_used": knots.prepared_used,
        "conditions_knot_hits": knots.hits,
        "conditions_knot_misses": knots.misses,
        "conditions_evaluations": knots.evaluations,
        "reference_area_m2": reference.area,
        "reference_length_m": reference.length,
    }
    database = estimator.database
    if database is not None:
        values["database_path"] = database.path
        values["database_speed_ratio"] = database.speed_ratio
        for key in ("force_coefficient", "moment_coefficient"):
            if key in database.error_bound:
                values[f"database_{key}_error"] = database.error_bound[key]
    percentiles = nearest_rank_percentiles(compute_ms)
    if percentiles is not None:
        values["compute_ms_p50"], values["compute_ms_p99"], values["compute_ms_max"] = percentiles
    if last_sample is not None:
        c = last_sample.conditions
        values.update(
            density_kg_m3=c.mass_density,
            temperature_K=c.temperature,
            altitude_m=c.altitude,
            relative_speed_m_s=c.speed,
            speed_ratio=c.speed_ratio,
            alpha=c.alpha,
            drag_coefficient=last_sample.drag_coefficient,
        )
        weather = c.space_weather  # (the indices in force at its stamp)
        if weather is not None:
            values.update(f107=weather.f107, f107a=weather.f107a, ap=weather.ap)
        values.update(last_sample.solar_diagnostics or {})
    if estimator.joints is not None:  # an articulated body
        values["joint_states_accepted"] = estimator.joints.accepted
        if cache is not None:
            values["joint_configurations_shaded"] = cache.configuration_misses
            values["joint_configuration_hits"] = cache.configuration_hits
    for reason in sorted(estimator.rejections):
        values[f"rejected_{reason}"] = estimator.rejections[reason]
    return values
