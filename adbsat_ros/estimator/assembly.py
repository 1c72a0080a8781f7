"""What the estimator is made of for its settings: the body, the panel method and the coefficient
database.

Each builder checks its settings against the mesh and raises ValueError naming the parameter
that cannot be applied, before anything of the estimator changes.
"""

from __future__ import annotations

from adbsat_ros.database.matching import DatabaseCoefficients
from adbsat_ros.estimator.settings import WrenchSettings, materials_from_settings
from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.loading import articulated_body, is_urdf, resolve_mesh
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.physics.articulated_method import ArticulatedMethod
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.gsi_models import ModelOptions
from adbsat_ros.physics.panel_method import PanelMethod


def load_body(settings: WrenchSettings, mesh: PanelMesh | ArticulatedBody | None = None) -> tuple:
    """``(body, mesh)``: the articulated body of ``robot_description`` (or of a URDF as
    ``mesh``) and its panels at zero joint positions, or None and the rigid mesh (``mesh`` if
    given, else loaded from the settings). An ArticulatedBody given as ``mesh`` is taken as it
    is (e.g. one read with a finer ``max_edge_fraction``).

    Raises
    ------
    MeshError
        If the mesh or URDF cannot be loaded (or ``mesh_scale`` is set for a URDF).
    """
    if isinstance(mesh, ArticulatedBody):
        return mesh, mesh.mesh()
    if settings.robot_description:
        body = ArticulatedBody.from_urdf(
            settings.robot_description,
            accept_size=settings.mesh_accept_size,
            source="robot_description",
        )
        return body, body.mesh()
    if is_urdf(settings.mesh):
        if settings.mesh_scale != 1.0:
            resolve_mesh(settings.mesh, settings.mesh_scale)  # (refuses it, naming the mesh)
        body = articulated_body(settings.mesh, settings.mesh_accept_size)
        return body, body.mesh()
    if mesh is None:
        mesh = resolve_mesh(settings.mesh, settings.mesh_scale, settings.mesh_accept_size)
    return None, mesh


def panel_method(
    mesh: PanelMesh, settings: WrenchSettings, body: ArticulatedBody | None = None
) -> PanelMethod | ArticulatedMethod:
    """The panel method of the settings' model, materials, options and centre of mass; for an
    articulated ``body`` (whose zero-configuration panels ``mesh`` are) its
    :class:`ArticulatedMethod`.

    Raises
    ------
    ValueError
        Naming ``material_overrides`` if it names a material the mesh does not have, or, for an
        articulated body, ``solar_pressure`` (not yet computed for moving parts).
    """
    materials = materials_from_settings(settings)
    unknown = materials.check_names(mesh.material_names)
    if unknown:
        raise ValueError(
            "parameter material_overrides: the mesh has no material "
            f"{', '.join(map(repr, unknown))}; its materials are {', '.join(mesh.material_names)}"
        )
    options = ModelOptions(settings.incident_temperature, settings.adbsat_compat)
    # (the centre of mass near the body: ten body sizes, docs/physics.md section 11)
    reference = Reference(moment_point=settings.center_of_mass).resolved(
        mesh, "parameter center_of_mass: center_of_mass"
    )
    if body is None:
        return PanelMethod(
            mesh, settings.gsi_model, materials, options=options, reference=reference
        )
    if settings.solar_pressure:
        raise ValueError(
            "parameter solar_pressure: not available for an articulated body (the solar "
            "radiation pressure is computed for rigid bodies only); set it false"
        )
    return ArticulatedMethod(
        body, settings.gsi_model, materials, options=options, reference=reference, shading="none"
    )


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
