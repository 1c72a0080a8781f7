"""What the estimator is made of: the body, the panel method and the coefficient database.

Each builder raises ValueError naming the parameter that cannot be applied, before anything of
the estimator changes.
"""

from __future__ import annotations

from adbsat_ros.database.matching import DatabaseCoefficients
from adbsat_ros.estimator.settings import WrenchSettings, setup_from_settings
from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.physics.articulated_method import ArticulatedMethod
from adbsat_ros.physics.model import build_model
from adbsat_ros.physics.model import load_body as load_panels
from adbsat_ros.physics.panel_method import PanelMethod


def load_body(settings: WrenchSettings, mesh: PanelMesh | ArticulatedBody | None = None) -> tuple:
    """``(body, panels at zero joint positions)`` of ``robot_description``/a URDF, else
    ``(None, rigid mesh)``; a ``mesh`` given (PanelMesh or ArticulatedBody) is taken as it is.

    Raises
    ------
    MeshError
        If the mesh or URDF cannot be loaded (or ``mesh_scale`` is set for a URDF).
    """
    body, panels = load_panels(setup_from_settings(settings).body, mesh)
    return body, panels if body is None else body.mesh()


def panel_method(
    mesh: PanelMesh, settings: WrenchSettings, body: ArticulatedBody | None = None
) -> PanelMethod | ArticulatedMethod:
    """The panel method of the settings' set-up (an :class:`ArticulatedMethod` for ``body``).

    Raises
    ------
    ValueError
        Naming ``material_overrides`` if it names a material the mesh does not have, or, for an
        articulated body, ``solar_pressure`` (not yet computed for moving parts).
    """
    method = build_model(setup_from_settings(settings), (body, mesh)).method
    if body is not None and settings.solar_pressure:
        raise ValueError(
            "parameter solar_pressure: not available for an articulated body (the solar "
            "radiation pressure is computed for rigid bodies only); set it false"
        )
    return method


def coefficient_database(
    settings: WrenchSettings, method: PanelMethod | ArticulatedMethod
) -> DatabaseCoefficients | None:
    """The database of ``database_path`` when ``coefficients_source`` is database, else None.

    Raises
    ------
    ValueError
        Naming ``accommodation_model`` unless it is fixed (a database is made at one alpha), or
        from :class:`DatabaseCoefficients` if the file does not fit ``method``.
    """
    if settings.coefficients_source != "database":
        return None
    if isinstance(method, ArticulatedMethod):
        raise ValueError(
            "parameter coefficients_source: a database is made for one rigid mesh; an "
            "articulated body needs coefficients_source panel"
        )
    if settings.accommodation_model != "fixed":
        raise ValueError(
            "parameter accommodation_model: coefficients_source database needs a fixed "
            "accommodation (the database was made at one alpha), got "
            f"{settings.accommodation_model}"
        )
    return DatabaseCoefficients(settings.database_path, method)  # checked against the method
