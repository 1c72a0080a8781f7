"""Where the satellite is and what gas it meets: Earth frames, atmosphere, flight conditions.

Modules:

- :mod:`~adbsat_ros.environment.flight_conditions`: :func:`flight_conditions` of an orbital state.
- :mod:`~adbsat_ros.environment.conditions`: :class:`FlightConditions`, the result.
- :mod:`~adbsat_ros.environment.circular_orbit`: ADBSat's circular-orbit recipe.
- :mod:`~adbsat_ros.environment.knots`: :class:`KnotGrid`, the per-message cache of conditions.
- :mod:`~adbsat_ros.environment.interpolation`: the linear mix of two knots.
- :mod:`~adbsat_ros.environment.atmosphere`: NRLMSISE-00 and the space weather.
- :mod:`~adbsat_ros.environment.accommodation`: energy accommodation models.
- :mod:`~adbsat_ros.environment.earth_frames`: GCRF/ITRF with pyerfa.
- :mod:`~adbsat_ros.environment.geodetic`: WGS-84; :mod:`~adbsat_ros.environment.time_scales`:
  UTC/TT/UT1; :mod:`~adbsat_ros.environment.sun`: the Sun and Earth's shadow.

Formulas and sources: docs/physics.md, section 5.
"""
