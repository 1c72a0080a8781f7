"""adbsat_ros: ADBSat's free-molecular panel method, fast, as a library, CLI and ROS 2 node.

The physics core imports no rclpy. Start with::

    from adbsat_ros import FreeStream, PanelMethod, load_mesh

    mesh = load_mesh("satellite.obj")
    flow = FreeStream(7700.0, 900.0, mean_mass_amu=16.0)
    result = PanelMethod(mesh, "sentman").coefficients(flow)
    print(result.drag, result.Cf_w, result.Cm_B)

* meshes: :func:`load_mesh`, :func:`panels_from_arrays`, :func:`panels_from_trimesh`,
  :func:`example_satellite`, :class:`PanelMesh`, :class:`MeshError`; URDF bodies:
  :class:`ArticulatedBody`, :class:`ArticulatedMethod`; :func:`panel_loads`;
* the panel method: :class:`PanelMethod`, :class:`AeroCoefficients`, :class:`Reference`,
  :class:`ModelOptions`, :data:`MODELS`, :class:`MaterialTable`, :class:`SurfaceProperties`;
  test particles: :class:`TestParticleMethod`, :class:`TpmcCoefficients`;
* shading: :func:`make_shader`, :class:`Shader`, :class:`ShadingCache`, :class:`PanelLighting`;
* the gas: :class:`FreeStream`, :func:`flight_conditions`,
  :func:`flight_conditions_circular_orbit`, :class:`FlightConditions`, :class:`SpaceWeather`;
* the node's logic without ROS: :class:`AeroWrenchEstimator`, :class:`WrenchSettings`;
* databases: :func:`build_database`, :func:`load_database`, :class:`AeroDatabase`,
  :class:`CoefficientLookup`.

Loaded on first use (PEP 562), so ``import adbsat_ros`` imports no numpy, trimesh or scipy.
"""

from __future__ import annotations

import importlib

from adbsat_ros._version import __version__

#: Module that defines each public name.
_EXPORTS = {
    "load_mesh": "adbsat_ros.geometry.loading",
    "panels_from_trimesh": "adbsat_ros.geometry.loading",
    "panels_from_arrays": "adbsat_ros.geometry.mesh",
    "PanelMesh": "adbsat_ros.geometry.mesh",
    "MeshError": "adbsat_ros.geometry.mesh",
    "example_satellite": "adbsat_ros.geometry.example_satellite",
    "ArticulatedBody": "adbsat_ros.geometry.articulated",
    "ArticulatedMethod": "adbsat_ros.physics.articulated_method",
    "panel_loads": "adbsat_ros.physics.panel_loads",
    "PanelMethod": "adbsat_ros.physics.panel_method",
    "AeroCoefficients": "adbsat_ros.physics.coefficients",
    "Reference": "adbsat_ros.physics.coefficients",
    "ModelOptions": "adbsat_ros.physics.gsi_models",
    "MODELS": "adbsat_ros.physics.gsi_models",
    "MaterialTable": "adbsat_ros.physics.surface",
    "SurfaceProperties": "adbsat_ros.physics.surface",
    "TestParticleMethod": "adbsat_ros.physics.tpmc.method",
    "TpmcCoefficients": "adbsat_ros.physics.tpmc.results",
    "make_shader": "adbsat_ros.shading.shader",
    "Shader": "adbsat_ros.shading.shader",
    "ShadingCache": "adbsat_ros.shading.cache",
    "PanelLighting": "adbsat_ros.shading.lighting",
    "FreeStream": "adbsat_ros.physics.freestream",
    "flight_conditions": "adbsat_ros.environment.flight_conditions",
    "flight_conditions_circular_orbit": "adbsat_ros.environment.circular_orbit",
    "FlightConditions": "adbsat_ros.environment.flight_conditions",
    "SpaceWeather": "adbsat_ros.environment.atmosphere",
    "AeroWrenchEstimator": "adbsat_ros.estimator.estimator",
    "WrenchSettings": "adbsat_ros.estimator.settings",
    "build_database": "adbsat_ros.database.build",
    "load_database": "adbsat_ros.database.format",
    "AeroDatabase": "adbsat_ros.database.format",
    "CoefficientLookup": "adbsat_ros.database.lookup",
}

__all__ = ["__version__", *sorted(_EXPORTS)]


def __getattr__(name: str):
    """Import the module defining the public ``name`` on first use and return the object."""
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value  # later look-ups find it without calling this function
    return value


def __dir__() -> list:
    """The module's attributes and every public name, loaded or not."""
    return sorted(set(globals()) | set(__all__))
