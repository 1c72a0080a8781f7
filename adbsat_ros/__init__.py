"""adbsat_ros: ADBSat's free-molecular panel method, fast, as a library, CLI and ROS 2 node.

The physics core (mesh, models, shading, atmosphere, databases) imports no rclpy. Start with::

    from adbsat_ros import load_mesh, PanelMethod, FreeStream
    mesh = load_mesh("satellite.obj")
    result = PanelMethod(mesh, "sentman").coefficients(FreeStream(7700.0, 900.0, mean_mass_amu=16.0))
    print(result.drag, result.Cf_w, result.Cm_B)
"""

from adbsat_ros.geometry.loading import load_mesh, panels_from_trimesh
from adbsat_ros.geometry.mesh import MeshError, PanelMesh, panels_from_arrays
from adbsat_ros.physics.coefficients import AeroCoefficients, Reference
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.gsi_models import MODELS, ModelOptions
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.physics.surface import MaterialTable, SurfaceProperties
from adbsat_ros.shading.cache import ShadingCache
from adbsat_ros.shading.lighting import PanelLighting
from adbsat_ros.shading.shader import Shader, make_shader

__version__ = "0.1.0"

__all__ = [
    "AeroCoefficients",
    "FreeStream",
    "MODELS",
    "MaterialTable",
    "MeshError",
    "ModelOptions",
    "PanelLighting",
    "PanelMesh",
    "PanelMethod",
    "Reference",
    "Shader",
    "ShadingCache",
    "SurfaceProperties",
    "load_mesh",
    "make_shader",
    "panels_from_arrays",
    "panels_from_trimesh",
]
