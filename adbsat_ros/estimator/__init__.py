"""The node's logic without ROS: from attitude and state messages to the aerodynamic wrench.

Modules:

- :mod:`~adbsat_ros.estimator.estimator`: :class:`AeroWrenchEstimator`, the per-attitude
  computation.
- :mod:`~adbsat_ros.estimator.wrench`, :mod:`~adbsat_ros.estimator.sunlight`,
  :mod:`~adbsat_ros.estimator.joints`: the sample, solar pressure and joint positions.
- :mod:`~adbsat_ros.estimator.handling`: :class:`MessageHandler`, one decoded message to a
  named outcome: the path shared by the node and bag analysis.
- :mod:`~adbsat_ros.estimator.parameters`, :mod:`~adbsat_ros.estimator.parameter_kinds`,
  :mod:`~adbsat_ros.estimator.settings`: the parameter table, the check of each kind, and
  :class:`WrenchSettings` with the set-up it describes.
- :mod:`~adbsat_ros.estimator.samples`: what one message gives (a sample or a rejection).
- :mod:`~adbsat_ros.estimator.state`, :mod:`~adbsat_ros.estimator.timing`,
  :mod:`~adbsat_ros.estimator.conditions`: accepting inputs, stamps to UTC, flight conditions.
- :mod:`~adbsat_ros.estimator.diagnostics`, :mod:`~adbsat_ros.estimator.health`: the
  diagnostic key/values and their level.

Imports the layers below it (database, environment, physics, shading, geometry, messages), and
no ROS.
"""
