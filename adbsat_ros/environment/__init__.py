"""Where the satellite is and what gas it meets: Earth frames, atmosphere, flight conditions.

Modules:

- :mod:`~adbsat_ros.environment.flight_conditions`: :func:`flight_conditions` of an orbital state
  (ECI or ECEF) at a UTC instant; :mod:`~adbsat_ros.environment.conditions` holds the result,
  :class:`FlightConditions`.
- :mod:`~adbsat_ros.environment.circular_orbit`: ADBSat's circular-orbit recipe (altitude,
  latitude, longitude, flight direction).
- :mod:`~adbsat_ros.environment.knots`: :class:`KnotGrid`, the per-message cache of flight
  conditions (exact at fixed stamps, interpolated in between);
  :mod:`~adbsat_ros.environment.interpolation`: the linear mix of two knots.
- :mod:`~adbsat_ros.environment.atmosphere`: NRLMSISE-00 and the space weather.
- :mod:`~adbsat_ros.environment.accommodation`: energy accommodation models (fixed, Langmuir,
  Goodman, SESAM).
- :mod:`~adbsat_ros.environment.earth_frames`, :mod:`~adbsat_ros.environment.geodetic`,
  :mod:`~adbsat_ros.environment.time_scales`: GCRF/ITRF with pyerfa, WGS-84, UTC/TT/UT1.

Formulas and sources: docs/physics.md, section 5.
"""
