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

#: The public names by the module that defines each.
_MODULES = {
    "geometry.loading": ("load_mesh", "panels_from_trimesh"),
    "geometry.mesh": ("panels_from_arrays", "PanelMesh", "MeshError"),
    "geometry.example_satellite": ("example_satellite",),
    "geometry.articulated": ("ArticulatedBody",),
    "physics.articulated_method": ("ArticulatedMethod",),
    "physics.panel_loads": ("panel_loads",),
    "physics.panel_method": ("PanelMethod",),
    "physics.coefficients": ("AeroCoefficients", "Reference"),
    "physics.gsi_models": ("ModelOptions", "MODELS"),
    "physics.surface": ("MaterialTable", "SurfaceProperties"),
    "physics.tpmc.method": ("TestParticleMethod",),
    "physics.tpmc.results": ("TpmcCoefficients",),
    "shading.shader": ("make_shader", "Shader"),
    "shading.cache": ("ShadingCache",),
    "shading.lighting": ("PanelLighting",),
    "physics.freestream": ("FreeStream",),
    "environment.flight_conditions": ("flight_conditions", "FlightConditions"),
    "environment.circular_orbit": ("flight_conditions_circular_orbit",),
    "environment.atmosphere": ("SpaceWeather",),
    "estimator.estimator": ("AeroWrenchEstimator",),
    "estimator.settings": ("WrenchSettings",),
    "database.build": ("build_database",),
    "database.format": ("load_database", "AeroDatabase"),
    "database.lookup": ("CoefficientLookup",),
}
_EXPORTS = {name: f"adbsat_ros.{module}" for module, names in _MODULES.items() for name in names}

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
