"""The gas-surface interaction models by family (the registry: adbsat_ros.physics.gsi_models);
each maps a panel's incidence c = cos(delta), sigma = sin(delta) to c_p and c_tau per q
(docs/physics.md, section 3).

- :mod:`.hyperthermal`: newton, cook, storch; :mod:`.diffuse`: sentman, schaaf, dria;
  :mod:`.maxwell`: the specular/diffuse mixture; :mod:`.cll`: Cercignani-Lampis-Lord.
- :mod:`.options`: the evaluation options; :mod:`.mixture`: the mixing of species.
"""
