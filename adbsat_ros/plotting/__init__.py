"""Figures: aerodynamic databases, per-panel pressure on the mesh, and rosbag time series.

Drawn on Agg-canvas Figures (:mod:`adbsat_ros.plotting.figures`), never through pyplot: headless,
no global state. ``make_*_figure`` returns a Figure, ``plot_*`` writes PNG files:

* :mod:`~adbsat_ros.plotting.coefficients`: a database's force and moment coefficients against
  angle of attack, one line per sideslip angle;
* :mod:`~adbsat_ros.plotting.panels`: the mesh coloured by panel pressure coefficient at one
  attitude, with the panels shaded from the flow marked;
* :mod:`~adbsat_ros.plotting.time_series`: force, torque, density and drag coefficient against
  time, one line per model (bag analysis and the demo);
  :mod:`~adbsat_ros.plotting.envelope` the bounded min/max summary of a long flight that bag
  analysis draws them from (no matplotlib).
"""
