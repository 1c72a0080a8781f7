"""Aerodynamic databases: the panel method's coefficients over a grid of aoa and sideslip.

* :mod:`~adbsat_ros.database.format`: :class:`AeroDatabase`, its files, :func:`load_database`;
* :mod:`~adbsat_ros.database.build`: :func:`build_database`, the sweep on a process pool;
* :mod:`~adbsat_ros.database.metadata`: the set-up recorded in a database, and rebuilt from it;
* :mod:`~adbsat_ros.database.interpolation`: bilinear interpolation and a grid's stated error;
* :mod:`~adbsat_ros.database.lookup`: :class:`CoefficientLookup`, coefficients at any attitude;
* :mod:`~adbsat_ros.database.matching`: a database checked against the node's set-up;
* :mod:`~adbsat_ros.database.sweep_reader`: a sweep's Zarr store read as databases.
"""
