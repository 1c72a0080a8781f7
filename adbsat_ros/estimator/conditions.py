"""The exact flight conditions of an accepted orbital state at a message stamp, per the settings.

The state is propagated to the stamp at constant velocity (a state is at most ~0.1 s old, where
the neglected gravity term is 5 cm); the estimator's knots evaluate this.
"""

from __future__ import annotations

from adbsat_ros.environment.atmosphere import SpaceWeather
from adbsat_ros.environment.conditions import FlightConditions
from adbsat_ros.environment.flight_conditions import conditions_options, evaluate_flight_conditions
from adbsat_ros.environment.space_weather import weather_source
from adbsat_ros.estimator.samples import OrbitalState
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.estimator.timing import stamp_utc

#: Precession-nutation is evaluated once per minute of TT (error < 1e-9 rad; see earth_frames).
PRECESSION_NUTATION_STEP_S = 60.0


class PropagatedConditions:
    """``conditions(state, stamp)``: the flight conditions of a state propagated to a stamp [s];
    ValueError naming space weather indices that are not allowed."""

    def __init__(self, settings: WrenchSettings):
        self.settings = settings
        fixed = SpaceWeather(settings.f107, settings.f107a, settings.ap, settings.ap_history)
        try:
            self.weather = weather_source(
                settings.space_weather, fixed, settings.space_weather_file
            )
        except ValueError as exc:
            raise ValueError(f"parameter {exc}") from None
        self.options = conditions_options(
            frame=settings.state_frame,
            earth_rotation=settings.earth_rotation,
            wind=settings.wind_ecef if any(settings.wind_ecef) else None,
            wind_frame="ecef",
            anomalous_oxygen=settings.anomalous_oxygen,
            accommodation_model=settings.accommodation_model,
            accommodation_options=(
                {"alpha": settings.alpha} if settings.accommodation_model == "fixed" else None
            ),
            precession_nutation_step=PRECESSION_NUTATION_STEP_S,
            atmosphere_model=settings.atmosphere_model,
        )

    def __call__(self, state: OrbitalState, stamp: float) -> FlightConditions:
        """The flight conditions of ``state`` at ``stamp`` [s] (ValueError: e.g. altitude)."""
        s = self.settings
        position = state.position + state.velocity * (stamp - state.stamp)
        return evaluate_flight_conditions(
            stamp_utc(stamp, s.time_mode, s.epoch_utc),
            position,
            state.velocity,
            self.weather,
            self.options,
        )
