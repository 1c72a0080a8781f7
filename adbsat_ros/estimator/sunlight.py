"""Solar radiation pressure at one message: the Sun, the Earth's shadow, the sunlit panels.

The Sun's direction (GCRS, through the ITRS for an ECEF state) is turned into the body frame
with the attitude; the body's self-shadowing comes from a shading cache of its own, made like
the flow's; the force is Luthcke's flat plate. Formulas: docs/physics.md, section 7.
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
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.estimator.shading import ShadingSource
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.physics.solar import solar_coefficients


class SolarPressureSource:
    """Solar radiation pressure of the settings' body, per message.

    Parameters
    ----------
    method : PanelMethod
        Mesh, materials (``specular_reflectivity``, ``diffuse_reflectivity``) and reference
        (A_ref, L_ref, the centre of mass as moment point).
    settings : WrenchSettings
        ``state_frame`` and the shading settings (the Sun's cache is made like the flow's).
    orientation_options : tuple
        The checked Earth-orientation options of the flight conditions (for an ECEF state).
    shading : ShadingSource, optional
        The Sun's shading source of earlier settings, kept if its settings are the same.
    """

    def __init__(
        self,
        method: PanelMethod,
        settings: WrenchSettings,
        orientation_options,
        shading: ShadingSource | None = None,
    ):
        self.method = method
        self.state_frame = settings.state_frame
        self.orientation_options = orientation_options
        if shading is None or shading.key != ShadingSource.key_of(settings):
            shading = ShadingSource(method.mesh, settings)
        self.shading = shading
        self.sun_track = SunTrack()

    def sample(self, conditions: FlightConditions, rotation) -> SolarSample:
        """The wrench of sunlight at ``conditions`` (time and ECI position) for the attitude
        ``rotation`` (body to state frame, 9 floats row-major)."""
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
        lighting, _ = self.shading.lighting(-sun_body)  # photons travel away from the Sun
        coefficients = solar_coefficients(self.method, sun_body, lighting=lighting)
        reference = self.method.reference
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
        """``sample`` with its solar wrench, compute time counted from ``t0`` (perf_counter).

        Raises
        ------
        Rejection
            ``compute_error`` if the solar wrench cannot be made or is not finite.
        """
        try:
            solar = self.sample(sample.conditions, sample.rotation)
        except ValueError as exc:
            raise Rejection("compute_error", f"solar radiation pressure: {exc}") from None
        if not all(map(math.isfinite, [*solar.force.tolist(), *solar.torque.tolist()])):
            raise Rejection("compute_error", "the solar wrench is not finite: nothing published")
        return dataclasses.replace(sample, solar=solar, compute_seconds=time.perf_counter() - t0)
