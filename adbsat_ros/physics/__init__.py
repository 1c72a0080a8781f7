"""One configured body and the panel method (formulas and sources: docs/physics.md).

- :mod:`.setup`: :class:`Setup`, the checked set-up; :mod:`.model`: :func:`build_model` and the
  :class:`Model` (its evaluation: :mod:`.model_evaluate`).
- :mod:`.panel_method`: :class:`PanelMethod`; :mod:`.coefficients`: its result and reference;
  :mod:`.facets`: coplanar panels grouped; :mod:`.incidence`: the flow's incidence on panels.
- :mod:`.articulated_method`, :mod:`.posed_facets`, :mod:`.link_loads`,
  :mod:`.articulated_results`: an articulated body's panel method.
- :mod:`.tpmc`: test-particle Monte Carlo; :mod:`.panel_loads`: each panel's force.
- :mod:`.gsi_models`, :mod:`.models`: the gas-surface models; :mod:`.freestream`: the gas;
  :mod:`.surface`: materials; :mod:`.solar`: solar pressure; :mod:`.knudsen`: Knudsen number;
  :mod:`.constants`: constants and species data.
"""
