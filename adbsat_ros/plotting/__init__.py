"""Figures: aerodynamic databases, per-panel pressure on the mesh, and rosbag time series.

Everything here draws on :class:`matplotlib.figure.Figure` objects with the Agg canvas
(:mod:`adbsat_ros.plotting.figures`), never through pyplot, so it works headless and leaves no
global state behind. Each figure has a ``make_*_figure`` function that returns the Figure (for
tests and notebooks) and a ``plot_*`` function that writes PNG files (about 8 x 5 in at 100 dpi,
small enough to commit):

* :mod:`~adbsat_ros.plotting.coefficients`: a database's force and moment coefficients against
  angle of attack, one line per sideslip angle;
* :mod:`~adbsat_ros.plotting.panels`: the mesh coloured by panel pressure coefficient at one
  attitude, with the panels shaded from the flow marked;
* :mod:`~adbsat_ros.plotting.time_series`: force, torque, density and drag coefficient against
  time, one line per model (bag analysis and the demo);
  :mod:`~adbsat_ros.plotting.envelope` the bounded min/max summary of a long flight that bag
  analysis draws them from (no matplotlib).
"""
