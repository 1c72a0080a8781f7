"""Where the satellite is and what gas it meets (formulas and sources: docs/physics.md, section 5).

- :mod:`.flight_conditions`: :func:`flight_conditions`; :mod:`.conditions`: the result;
  :mod:`.circular_orbit`: ADBSat's recipe; :mod:`.knots`, :mod:`.interpolation`: the cache.
- :mod:`.atmosphere`: NRLMSISE-00, NRLMSIS 2.x, the indices; :mod:`.space_weather`: their sources
  (fixed, historical); :mod:`.accommodation`: energy accommodation.
- :mod:`.earth_frames`: GCRF/ITRF; :mod:`.geodetic`: WGS-84; :mod:`.time_scales`: UTC/TT/UT1;
  :mod:`.sun`: the Sun and Earth's shadow; :mod:`.kinematics`: a knot's frames in floats.
"""
