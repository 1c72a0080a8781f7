"""What the estimator is made of for its settings: the panel method and the coefficient database.

Each builder checks its settings against the mesh and raises ValueError naming the parameter
that cannot be applied, before anything of the estimator changes.
"""

from __future__ import annotations

from adbsat_ros.database.matching import DatabaseCoefficients
from adbsat_ros.estimator.settings import WrenchSettings, materials_from_settings
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.gsi_models import ModelOptions
from adbsat_ros.physics.panel_method import PanelMethod


def panel_method(mesh: PanelMesh, settings: WrenchSettings) -> PanelMethod:
    """The panel method of the settings' model, materials, options and centre of mass.

    Raises
    ------
    ValueError
        Naming ``material_overrides`` if it names a material the mesh does not have.
    """
    materials = materials_from_settings(settings)
    unknown = materials.check_names(mesh.material_names)
    if unknown:
        raise ValueError(
            "parameter material_overrides: the mesh has no material "
            f"{', '.join(map(repr, unknown))}; its materials are {', '.join(mesh.material_names)}"
        )
    return PanelMethod(
        mesh,
        settings.gsi_model,
        materials,
        options=ModelOptions(settings.incident_temperature, settings.adbsat_compat),
        reference=Reference(moment_point=settings.center_of_mass),
    )


def coefficient_database(
    settings: WrenchSettings, method: PanelMethod
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
    if settings.accommodation_model != "fixed":
        raise ValueError(
            "parameter accommodation_model: coefficients_source database needs a fixed "
            "accommodation (the database was made at one alpha), got "
            f"{settings.accommodation_model}"
        )
    return DatabaseCoefficients(settings.database_path, method)  # checked against the method
