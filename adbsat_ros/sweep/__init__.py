"""Design-space sweeps on Dask: N-dimensional aerodynamic databases in Zarr.

:mod:`~adbsat_ros.sweep.spec` reads what to sweep (a YAML spec), :mod:`~adbsat_ros.sweep.evaluate`
computes one chunk of the grid where a worker runs it, :mod:`~adbsat_ros.sweep.store` keeps the
result (an xarray Dataset in Zarr, written chunk by chunk) and :mod:`~adbsat_ros.sweep.engine`
runs the chunks on Dask (a LocalCluster here, or any running scheduler). ``adbsat-ros sweep``
is the command line.
"""
