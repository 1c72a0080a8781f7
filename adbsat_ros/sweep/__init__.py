"""Design-space sweeps on Dask: N-dimensional aerodynamic databases in Zarr.

:mod:`~adbsat_ros.sweep.spec` reads the YAML spec, :mod:`~adbsat_ros.sweep.evaluate` computes a
chunk on a worker, :mod:`~adbsat_ros.sweep.store` keeps the result (xarray in Zarr) and
:mod:`~adbsat_ros.sweep.engine` runs the chunks on Dask. ``adbsat-ros sweep`` is the command line.
"""
