"""The node's logic without ROS: from attitude and state messages to the aerodynamic wrench.

Modules:

- :mod:`~adbsat_ros.estimator.estimator`: :class:`AeroWrenchEstimator`, the per-attitude
  computation (flight conditions, flow direction in the body, the model's coefficients);
  :mod:`~adbsat_ros.estimator.wrench`, :mod:`~adbsat_ros.estimator.sunlight`,
  :mod:`~adbsat_ros.estimator.joints`: the sample, solar pressure and joint positions.
- :mod:`~adbsat_ros.estimator.handling`: :class:`MessageHandler`, one decoded message through the
  estimator to a named outcome with the bytes to publish: the path shared by the node and bag
  analysis.
- :mod:`~adbsat_ros.estimator.parameters`: the parameter table (name, default, kind, set-up
  field, range, meaning); :mod:`~adbsat_ros.estimator.parameter_kinds`: the check of each kind;
  :mod:`~adbsat_ros.estimator.settings`: :class:`WrenchSettings` made from the table, shared by
  the node, its YAML and bag analysis, and the set-up it describes.
- :mod:`~adbsat_ros.estimator.samples`: what one message gives (a sample or a rejection).
- :mod:`~adbsat_ros.estimator.state`, :mod:`~adbsat_ros.estimator.timing`,
  :mod:`~adbsat_ros.estimator.conditions`: accepting inputs, stamps to UTC, the exact flight
  conditions of a state.
- :mod:`~adbsat_ros.estimator.diagnostics` and :mod:`~adbsat_ros.estimator.health`: the
  diagnostic key/values and their level, written once for the node and bag analysis.

Imports everything below it (database, environment, physics, shading, geometry, messages), and
no ROS.
"""
