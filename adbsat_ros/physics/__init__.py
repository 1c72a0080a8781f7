"""The panel method: gas-surface models, free stream, surfaces, and the force and moment sums.

Modules:

- :mod:`~adbsat_ros.physics.setup`: :class:`Setup`, one configured body as a value, checked once;
  :mod:`~adbsat_ros.physics.model`: :func:`build_model`, its panels, panel method, shader and
  test-particle solver.
- :mod:`~adbsat_ros.physics.panel_method`: :class:`PanelMethod`, force and moment coefficients of
  a mesh at any attitude; :mod:`~adbsat_ros.physics.coefficients` holds its result and reference
  quantities, :mod:`~adbsat_ros.physics.facets` the grouping of coplanar panels (and the one cache
  of facet sums), :mod:`~adbsat_ros.physics.incidence` the incidence of the flow on panels.
- :mod:`adbsat_ros.physics.tpmc`: the test-particle Monte Carlo solver of the same problem with
  every reflection (concave bodies), by module: inflow, kernels, tracing, batches, results,
  method.
- :mod:`~adbsat_ros.physics.panel_loads`: each panel's force and where it acts (for the loads on
  the links and joints of an articulated body).
- :mod:`~adbsat_ros.physics.gsi_models`: the registry of gas-surface models; the formulas are in
  :mod:`adbsat_ros.physics.models`, by family.
- :mod:`~adbsat_ros.physics.freestream`: :class:`FreeStream`, the gas met (speed, temperature,
  composition, density).
- :mod:`~adbsat_ros.physics.surface`: per-material surface properties.
- :mod:`~adbsat_ros.physics.solar`: solar radiation pressure (Luthcke et al. 1997).
- :mod:`~adbsat_ros.physics.knudsen`: mean free path and Knudsen number (how free-molecular
  the flow is).
- :mod:`~adbsat_ros.physics.constants`: physical constants and species data.

Imports geometry, shading and processes (the test particles' worker pool). Formulas and
sources: docs/physics.md.
"""
