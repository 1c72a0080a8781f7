"""Aerodynamic databases: the panel method's coefficients over a grid of aoa and sideslip.

* :mod:`~adbsat_ros.database.format`: the database (:class:`AeroDatabase`), its ``.npz`` and CSV
  files, and :func:`load_database`;
* :mod:`~adbsat_ros.database.build`: :func:`build_database`, the sweep on a process pool;
* :mod:`~adbsat_ros.database.metadata`: the set-up recorded in a database, and rebuilt from it;
* :mod:`~adbsat_ros.database.interpolation`: the bilinear interpolant and the stated
  interpolation error of a grid;
* :mod:`~adbsat_ros.database.lookup`: :class:`CoefficientLookup`, coefficients at any attitude;
* :mod:`~adbsat_ros.database.matching`: a database checked against the node's set-up, as the
  wrench estimator's source of coefficients.
"""
