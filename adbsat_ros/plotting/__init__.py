"""Figures on Agg-canvas Figures (:mod:`adbsat_ros.plotting.figures`), never through pyplot.

``make_*_figure`` returns a Figure, ``plot_*`` writes PNG files:

* :mod:`~adbsat_ros.plotting.coefficients`: a database's coefficients against angle of attack;
* :mod:`~adbsat_ros.plotting.panels`: the mesh coloured by panel pressure coefficient;
* :mod:`~adbsat_ros.plotting.time_series`: force, torque, density and drag coefficient against
  time, one line per model; :mod:`~adbsat_ros.plotting.envelope` the bounded min/max summary of
  a long flight they are drawn from (no matplotlib).
"""
