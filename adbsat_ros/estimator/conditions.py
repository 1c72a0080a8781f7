"""The exact flight conditions of an accepted orbital state at a message stamp, per the settings.

The latest state is propagated to the stamp at constant velocity (first order: a state comes
every ~0.1 s and is 0.1 s old at most, where the neglected gravity term is 5 cm) and evaluated
by :func:`adbsat_ros.environment.flight_conditions.evaluate_flight_conditions` with the settings'
space weather and options (frame, wind, Earth rotation, anomalous oxygen, accommodation model),
checked once (:func:`~adbsat_ros.environment.flight_conditions.conditions_options`). This is what
the estimator's :class:`~adbsat_ros.environment.knots.KnotGrid` evaluates at its knots.
"""

from __future__ import annotations

from adbsat_ros.environment.atmosphere import SpaceWeather
from adbsat_ros.environment.conditions import FlightConditions
from adbsat_ros.environment.flight_conditions import conditions_options, evaluate_flight_conditions
from adbsat_ros.estimator.samples import OrbitalState
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.estimator.timing import stamp_utc

#: Precession-nutation is evaluated once per minute of TT (error < 1e-9 rad; see earth_frames).
PRECESSION_NUTATION_STEP_S = 60.0


class PropagatedConditions:
    """``conditions(state, stamp)``: the flight conditions of a state propagated to a stamp.

    Parameters
    ----------
    settings : WrenchSettings
        The space weather (f107, f107a, ap, ap_history), ``state_frame``, ``earth_rotation``,
        ``wind_ecef``, ``anomalous_oxygen``, ``accommodation_model`` and ``alpha``, and the time
        mapping (``time_mode``, ``epoch_utc``).

    Raises
    ------
    ValueError
        For space weather indices that are not allowed (naming them).
    """

    def __init__(self, settings: WrenchSettings):
        self.settings = settings
        self.weather = SpaceWeather(settings.f107, settings.f107a, settings.ap, settings.ap_history)
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
        )

    def __call__(self, state: OrbitalState, stamp: float) -> FlightConditions:
        """The flight conditions of ``state`` propagated to ``stamp`` [s].

        Raises
        ------
        ValueError
            From :func:`evaluate_flight_conditions` (e.g. an altitude outside the atmosphere
            model).
        """
        s = self.settings
        position = state.position + state.velocity * (stamp - state.stamp)
        return evaluate_flight_conditions(
            stamp_utc(stamp, s.time_mode, s.epoch_utc),
            position,
            state.velocity,
            self.weather,
            self.options,
        )
