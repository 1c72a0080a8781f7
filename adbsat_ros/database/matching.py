"""A database matched to the node's set-up, as the estimator's source of coefficients; moments
carried to the node's point, C_M(c) = C_M(p) + (p - c) x C_F / L_ref. docs/physics.md, section 9.
"""

from __future__ import annotations

import math

import numpy as np

from adbsat_ros.bounds import errors_as
from adbsat_ros.database.format import DatabaseError
from adbsat_ros.database.lookup import CoefficientLookup
from adbsat_ros.database.metadata import model_values, surface_values
from adbsat_ros.geometry import frames
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.physics.surface import MaterialTable, SurfaceProperties

#: Relative tolerance on the reference area and length when matching a database.
REFERENCE_RTOL = 1e-9


def database_mismatches(metadata: dict, method: PanelMethod) -> list:
    """How a database's set-up differs from ``method``'s: one line per mismatch."""
    out = []
    mesh = metadata.get("mesh", {})
    if mesh.get("fingerprint") != method.mesh.fingerprint():
        out.append(
            f"mesh: the database was made for {mesh.get('source', '?')} "
            f"({mesh.get('n_panels', '?')} panels, fingerprint {mesh.get('fingerprint')}), "
            f"the node has {method.mesh.source} "
            f"({method.mesh.n_panels} panels, fingerprint {method.mesh.fingerprint()})"
        )
    model = metadata.get("model", {})
    for key, ours in model_values(method).items():
        if model.get(key) != ours:
            label = "gsi_model" if key == "name" else key
            out.append(f"{label}: database {model.get(key)!r}, node {ours!r}")
    try:
        materials = metadata["materials"]
        theirs = MaterialTable.from_texts(
            SurfaceProperties(**materials["default"]), materials["overrides"]
        )
    except (KeyError, TypeError, ValueError) as exc:
        out.append(f"materials: the database's materials cannot be read ({exc})")
    else:
        names = sorted(set(method.mesh.material_names))
        for name in names:
            a = surface_values(theirs.properties(name))
            b = surface_values(method.materials.properties(name))
            diff = [f"{k} database {a[k]:g}, node {b[k]:g}" for k in a if a[k] != b[k]]
            if diff:
                out.append(f"surface of material {name!r}: " + "; ".join(diff))
    ref = metadata.get("reference", {})
    for key, ours in (("area", method.reference.area), ("length", method.reference.length)):
        theirs_value = ref.get(key)
        if not isinstance(theirs_value, (int, float)) or not math.isclose(
            float(theirs_value), ours, rel_tol=REFERENCE_RTOL
        ):
            out.append(f"reference {key}: database {theirs_value!r}, node {ours!r}")
    return out


class DatabaseCoefficients:
    """Body-frame coefficients from the database ``path`` matching ``method``, about its point c.

    ``error_bound``: e_M + |p - c| e_F / L_ref. ValueError: unreadable, or mismatches.
    """

    def __init__(self, path: str, method: PanelMethod):
        with errors_as(ValueError, (DatabaseError, OSError), "parameter database_path: "):
            self.lookup = CoefficientLookup.load(path)
        metadata = self.lookup.database.metadata
        problems = database_mismatches(metadata, method)
        if problems:
            raise ValueError(
                f"parameter database_path: {path} was not made for this node's set-up: "
                + "; ".join(problems)
            )
        self.path = path
        self.reference_length = method.reference.length
        point = np.asarray(metadata["reference"]["moment_point"], dtype=float)
        self._offset = point - np.asarray(method.reference.moment_point, dtype=float)  # p - c [m]
        self.speed_ratio = float(metadata.get("flow", {}).get("speed_ratio", float("nan")))
        stated = self.lookup.error_bound
        force_error = float(stated.get("force_coefficient", float("nan")))
        moment_error = float(stated.get("moment_coefficient", float("nan")))
        self.error_bound = {
            "force_coefficient": force_error,
            "moment_coefficient": moment_error
            + float(np.linalg.norm(self._offset)) * force_error / self.reference_length,
        }

    def body_coefficients(self, u_body):
        """C_F and C_M (about c) for the unit flow ``u_body`` (body frame)."""
        aoa, aos = frames.angles_of_flow(u_body)
        Cf, Cm = self.lookup.body_coefficients(math.degrees(aoa), math.degrees(aos))
        return Cf, Cm + frames.cross(self._offset, Cf) / self.reference_length
