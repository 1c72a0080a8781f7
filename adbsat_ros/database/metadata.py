"""A database's set-up as JSON metadata, and the set-up rebuilt from it."""

from __future__ import annotations

import datetime as _dt
import os

from adbsat_ros._version import __version__
from adbsat_ros.bounds import errors_as
from adbsat_ros.database.format import FORMAT_VERSION, DatabaseError
from adbsat_ros.geometry.example_satellite import EXAMPLE_MESH_NAME
from adbsat_ros.geometry.loading import is_urdf
from adbsat_ros.geometry.mesh import MeshError
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.gsi_models import ModelOptions
from adbsat_ros.physics.model import build_model, load_body
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.physics.setup import BodySpec, Setup, ShadingPolicy, SolverSpec
from adbsat_ros.physics.surface import SURFACE_PARAMETERS, MaterialTable, SurfaceProperties


# ---------------------------------------------------------------------------------- metadata
def surface_values(props: SurfaceProperties) -> dict:
    """Every surface parameter of ``props`` as a float, by name."""
    return {name: float(getattr(props, name)) for name in SURFACE_PARAMETERS}


def model_values(method: PanelMethod) -> dict:
    """The gas-surface model of ``method`` as the metadata records it."""
    return {
        "name": method.model,
        "incident_temperature": method.options.incident_temperature,
        "adbsat_compat": bool(method.options.adbsat_compat),
    }


def material_override_texts(materials: MaterialTable) -> list:
    """``NAME:key=value,...`` texts that rebuild ``materials`` (same default) exactly (``repr``)."""
    texts = []
    for name, props in materials.materials.items():
        items = ",".join(f"{k}={v!r}" for k, v in surface_values(props).items())
        texts.append(f"{name}:{items}")
    return texts


def _flow_dict(flow: FreeStream) -> dict:
    return {
        "speed": float(flow.speed),
        "temperature": float(flow.temperature),
        "mean_mass_amu": None if flow.mean_mass_amu is None else float(flow.mean_mass_amu),
        "number_densities": None if flow.number_densities is None else dict(flow.number_densities),
        "density": None if flow.density is None else float(flow.density),
        "speed_ratio": float(flow.speed_ratio),
    }


def _reload_mesh(spec, scale: float, joints: dict | None):
    body, mesh = load_body(BodySpec(spec, scale))
    if body is None:
        return mesh
    with errors_as(MeshError):  # (a joint position the URDF refuses)
        return body.mesh(joints)


def _mesh_spec_checked(method: PanelMethod, mesh_spec, mesh_scale, joints=None) -> str | None:
    if mesh_spec is None:
        return None
    mesh_spec = os.fspath(mesh_spec)
    with errors_as(ValueError, MeshError, f"mesh_spec {mesh_spec!r}: "):
        reloaded = _reload_mesh(mesh_spec, mesh_scale, joints).fingerprint()
    if reloaded != method.mesh.fingerprint():
        if mesh_spec == EXAMPLE_MESH_NAME:  # the default: the mesh was built some other way
            return None
        raise ValueError(
            f"mesh_spec {mesh_spec!r} (scale {mesh_scale}) does not load the method's mesh "
            "(fingerprints differ)"
        )
    return mesh_spec


def describe_setup(model, flow: FreeStream, mesh_spec, mesh_scale, mesh_joints=None) -> dict:
    """Metadata of a built set-up, ``model`` (:data:`~.format.REQUIRED_METADATA`).

    ``mesh_joints``: [rad or m]. ValueError: ``mesh_spec`` does not reload to the model's mesh.
    """
    method, shading = model.method, model.setup.shading
    mesh, ref = method.mesh, method.reference
    return {
        "format_version": FORMAT_VERSION,
        "created_utc": _dt.datetime.now(_dt.timezone.utc).replace(microsecond=0).isoformat(),
        "adbsat_ros_version": __version__,
        "mesh": {
            "spec": _mesh_spec_checked(method, mesh_spec, mesh_scale, mesh_joints),
            "scale": float(mesh_scale),
            "joints": {str(k): float(v) for k, v in (mesh_joints or {}).items()},
            "source": str(mesh.source),
            "n_panels": int(mesh.n_panels),
            "fingerprint": mesh.fingerprint(),
        },
        "model": model_values(method),
        "materials": {
            "default": surface_values(method.materials.default),
            "overrides": material_override_texts(method.materials),
        },
        "flow": _flow_dict(flow),
        "reference": {
            "area": float(ref.area),
            "length": float(ref.length),
            "moment_point": [float(v) for v in ref.moment_point],
        },
        "shading": {"mode": shading.mode, "samples": shading.samples},
    }


def setup_from_metadata(metadata: dict) -> Setup:
    """The set-up a database's metadata records; KeyError/TypeError/ValueError if none."""
    mesh = metadata["mesh"]
    spec = mesh["spec"]
    joints = tuple((mesh.get("joints") or {}).items()) if is_urdf(spec) else None
    model, mat, ref = metadata["model"], metadata["materials"], metadata["reference"]
    shading = metadata["shading"]
    solver = dict(metadata.get("solver") or {"method": "panel"})
    return Setup(
        body=BodySpec(spec, float(mesh["scale"]), joints=joints),
        model=model["name"],
        options=ModelOptions(model["incident_temperature"], bool(model["adbsat_compat"])),
        surface=SurfaceProperties(**mat["default"]),
        overrides=tuple(mat["overrides"]),
        reference=Reference(ref["area"], ref["length"], tuple(ref["moment_point"])),
        shading=ShadingPolicy(shading["mode"], int(shading["samples"]), exact_offline=1),
        solver=SolverSpec(**solver),
        labels=(("moment_point", "reference moment_point"),),
    )


def model_from_metadata(metadata: dict, path=None):
    """``(model, flow)`` of a database's metadata; DatabaseError naming ``path``."""
    where = path or "database"
    try:
        mesh_meta = metadata["mesh"]
        spec = mesh_meta["spec"]
        if spec is None:
            raise DatabaseError(
                f"{where}: the mesh was built in code (no mesh spec recorded), so it cannot be "
                "reloaded"
            )
        setup = setup_from_metadata(metadata)
        with errors_as(DatabaseError, MeshError, f"{where}: cannot reload the mesh {spec!r}: "):
            model = build_model(setup)
        if model.mesh.fingerprint() != mesh_meta["fingerprint"]:
            raise DatabaseError(
                f"{where}: the mesh {spec!r} has changed since the database was built "
                f"(fingerprint {model.mesh.fingerprint()}, recorded {mesh_meta['fingerprint']})",
            )
        f = metadata["flow"]
        gas = {k: f.get(k) for k in ("number_densities", "mean_mass_amu", "density")}
        flow = FreeStream(speed=f["speed"], temperature=f["temperature"], **gas)
    except DatabaseError:
        raise
    except (KeyError, TypeError, ValueError) as exc:
        raise DatabaseError(
            f"{where}: metadata does not describe a set-up: {type(exc).__name__}: {exc}"
        ) from None
    return model, flow
