"""The gas-surface interaction models by family (the registry: adbsat_ros.physics.gsi_models).

Every model maps the incidence of a flat panel, c = cos(delta) and sigma = sin(delta) (delta the
angle between the inward normal -n and the flow direction), to a pressure coefficient c_p
(compressive, along -n) and a shear coefficient c_tau (along the tangential part of the flow),
both normalised by the free-stream dynamic pressure q = rho V^2 / 2:

* :mod:`~adbsat_ros.physics.models.hyperthermal`: newton, cook, storch (the molecules' thermal
  speed neglected against the flow speed);
* :mod:`~adbsat_ros.physics.models.diffuse`: sentman, schaaf and dria (the drifting Maxwellian
  gas, diffuse or partly accommodated re-emission);
* :mod:`~adbsat_ros.physics.models.maxwell`: the specular/diffuse mixture;
* :mod:`~adbsat_ros.physics.models.cll`: Cercignani-Lampis-Lord with the Walker et al. fits;
* :mod:`~adbsat_ros.physics.models.options` and :mod:`~adbsat_ros.physics.models.mixture`: the
  evaluation options and the mixing of species.
"""
