"""Aerodynamic databases: the panel method's coefficients over a grid of aoa and sideslip.

- :mod:`.format`: :class:`AeroDatabase` and its files; :mod:`.build`: :func:`build_database`.
- :mod:`.metadata`: the recorded set-up; :mod:`.interpolation`: bilinear and the stated error.
- :mod:`.lookup`: :class:`CoefficientLookup`; :mod:`.matching`: matched to the node's set-up.
- :mod:`.sweep_reader`: a sweep's Zarr store read as databases.
"""
