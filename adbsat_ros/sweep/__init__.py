"""Design-space sweeps on Dask: N-dimensional aerodynamic databases in Zarr (docs/sweeps.md).

- :mod:`.spec`: the YAML spec; :mod:`.axes`: its inputs and ranges; :mod:`.gas`: a point's gas.
- :mod:`.evaluate`: a chunk on a worker; :mod:`.engine`: the chunks on Dask.
- :mod:`.store`: the result (xarray in Zarr); :mod:`.lookup`: coefficients inside it.
"""
