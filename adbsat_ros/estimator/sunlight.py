"""Solar radiation pressure at one message: the Sun, the Earth's shadow, the sunlit panels.

The Sun's direction (GCRS, through the ITRS for an ECEF state) turned into the body frame, the
self-shadowing from the model's shading cache, Luthcke's flat plate: docs/physics.md, section 7.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from adbsat_ros.environment.conditions import FlightConditions
from adbsat_ros.environment.earth_frames import rotation_terms
from adbsat_ros.environment.sun import SunTrack, sun_state
from adbsat_ros.environment.time_scales import seconds_of_day, utc_day
from adbsat_ros.estimator.samples import Rejection, SolarSample, WrenchSample
from adbsat_ros.physics.model import Model


class SolarPressureSource:
    """Solar radiation pressure of a rigid ``model`` per message (``orientation_options``: the
    flight conditions' checked Earth-orientation options, for an ECEF ``state_frame``)."""

    def __init__(self, model: Model, state_frame: str, orientation_options):
        self.model = model
        self.state_frame = state_frame
        self.orientation_options = orientation_options
        self.sun_track = SunTrack()

    def sample(self, conditions: FlightConditions, rotation) -> SolarSample:
        """Sunlight's wrench at ``conditions``; ``rotation``: body to state frame, row-major."""
        sun = sun_state(
            conditions.time, conditions.position_eci, self.sun_track.position(conditions.time)
        )
        direction = sun.direction_eci
        if self.state_frame == "ecef":
            utc = conditions.time
            jd1, tt_minus_utc, _ = utc_day(utc.year, utc.month, utc.day)
            matrix, _, _ = rotation_terms(
                jd1, seconds_of_day(utc) / 86400.0, tt_minus_utc, *self.orientation_options
            )
            direction = np.array(matrix).reshape(3, 3) @ direction
        sun_body = np.array(rotation).reshape(3, 3).T @ direction
        sun_body /= np.linalg.norm(sun_body)
        if sun.lit_fraction <= 0.0:
            zero = np.zeros(3)
            return SolarSample(zero, zero.copy(), sun_body, 0.0, sun.pressure, 0.0)
        coefficients = self.model.solar(sun_body)
        reference = self.model.method.reference
        scale = sun.pressure * sun.lit_fraction * reference.area
        return SolarSample(
            force=scale * coefficients.Cf_G,
            torque=(scale * reference.length) * coefficients.Cm_G,
            sun_direction_body=sun_body,
            lit_fraction=sun.lit_fraction,
            pressure=sun.pressure,
            area_lit=coefficients.area_lit,
        )

    def with_sunlight(self, sample: WrenchSample, t0: float) -> WrenchSample:
        """``sample`` with its solar wrench (time from ``t0``); Rejection compute_error."""
        try:
            solar = self.sample(sample.conditions, sample.rotation)
        except ValueError as exc:
            raise Rejection("compute_error", f"solar radiation pressure: {exc}") from None
        if not all(map(math.isfinite, [*solar.force.tolist(), *solar.torque.tolist()])):
            raise Rejection("compute_error", "the solar wrench is not finite: nothing published")
        return dataclasses.replace(sample, solar=solar, compute_seconds=time.perf_counter() - t0)
