"""The panel method: gas-surface models, free stream, surfaces, and the force and moment sums.

Modules:

- :mod:`~adbsat_ros.physics.setup`: :class:`Setup`, one configured body as a checked value;
  :mod:`~adbsat_ros.physics.model`: :func:`build_model` and the :class:`Model` that owns the
  body, its one shading cache and ``evaluate`` (every backend's sums in
  :mod:`~adbsat_ros.physics.model_evaluate`).
- :mod:`~adbsat_ros.physics.panel_method`: :class:`PanelMethod`, coefficients at any attitude;
  :mod:`~adbsat_ros.physics.coefficients` its result and reference quantities,
  :mod:`~adbsat_ros.physics.facets` coplanar panels grouped (one cache of facet sums),
  :mod:`~adbsat_ros.physics.incidence` the incidence of the flow on panels.
- :mod:`adbsat_ros.physics.tpmc`: the test-particle Monte Carlo solver (concave bodies).
- :mod:`~adbsat_ros.physics.panel_loads`: each panel's force and where it acts.
- :mod:`~adbsat_ros.physics.gsi_models`: the registry of gas-surface models
  (formulas in :mod:`adbsat_ros.physics.models`).
- :mod:`~adbsat_ros.physics.freestream`: :class:`FreeStream`, the gas met.
- :mod:`~adbsat_ros.physics.surface`: per-material surface properties.
- :mod:`~adbsat_ros.physics.solar`: solar radiation pressure (Luthcke et al. 1997).
- :mod:`~adbsat_ros.physics.knudsen`: mean free path and Knudsen number.
- :mod:`~adbsat_ros.physics.constants`: physical constants and species data.

Imports geometry, shading and processes. Formulas and sources: docs/physics.md.
"""
