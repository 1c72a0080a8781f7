"""Surface (material) properties that the gas-surface and radiation models read, by material."""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import Mapping

import numpy as np

from adbsat_ros.validation import finite

#: Names of the per-material parameters, in the order of :class:`SurfaceProperties`.
SURFACE_PARAMETERS = (
    "alpha",
    "alpha_n",
    "sigma_n",
    "sigma_t",
    "wall_temperature",
    "specular_reflectivity",
    "diffuse_reflectivity",
)


@dataclass(frozen=True)
class SurfaceProperties:
    """Gas-surface and optical properties of one material.

    alpha: energy accommodation [-] in [0, 1] (sentman, cook, dria; maxwell's diffuse fraction).
    alpha_n: normal energy accommodation of CLL [-] in [0, 1].
    sigma_n: normal momentum accommodation [-] (schaaf, storch) in [0, 2).
    sigma_t: tangential momentum accommodation [-] (schaaf, storch, cll) in [0, 1].
    wall_temperature: T_w [K] > 0.
    specular_reflectivity, diffuse_reflectivity: photon fractions [-], sum <= 1 (solar pressure).
    """

    alpha: float = 1.0
    alpha_n: float = 1.0
    sigma_n: float = 1.0
    sigma_t: float = 1.0
    wall_temperature: float = 300.0
    specular_reflectivity: float = 0.0
    diffuse_reflectivity: float = 0.0

    def __post_init__(self):
        for f in fields(self):
            object.__setattr__(self, f.name, finite(f.name, getattr(self, f.name)))
        for name in (
            "alpha",
            "alpha_n",
            "sigma_t",
            "specular_reflectivity",
            "diffuse_reflectivity",
        ):
            value = getattr(self, name)
            if not 0.0 <= value <= 1.0:
                raise ValueError(f"{name} must be in [0, 1], got {value!r}")
        if not 0.0 <= self.sigma_n < 2.0:
            raise ValueError(f"sigma_n must be in [0, 2), got {self.sigma_n!r}")
        if self.wall_temperature <= 0.0:
            raise ValueError(f"wall_temperature must be > 0 K, got {self.wall_temperature!r}")
        if self.specular_reflectivity + self.diffuse_reflectivity > 1.0 + 1e-12:
            raise ValueError(
                "specular_reflectivity + diffuse_reflectivity must be <= 1, got "
                f"{self.specular_reflectivity} + {self.diffuse_reflectivity}"
            )


class PanelSurface:
    """Per-panel :class:`SurfaceProperties` fields: each a float (uniform) or an (N,) array."""

    __slots__ = SURFACE_PARAMETERS

    def __init__(self, **values):
        for name in SURFACE_PARAMETERS:
            setattr(self, name, values[name])


class MaterialTable:
    """Surface properties by material name, with a default for unnamed materials.

    materials: per-material overrides; a dict is applied on top of ``default``.
    """

    def __init__(self, default: SurfaceProperties | None = None, materials: Mapping | None = None):
        self.default = default or SurfaceProperties()
        self.materials = {}
        for name, props in (materials or {}).items():
            if isinstance(props, Mapping):
                unknown = set(props) - set(SURFACE_PARAMETERS)
                if unknown:
                    raise ValueError(
                        f"material {name!r}: unknown parameters {sorted(unknown)}; "
                        f"allowed: {', '.join(SURFACE_PARAMETERS)}"
                    )
                props = replace(self.default, **props)  # (validated)
            elif not isinstance(props, SurfaceProperties):
                raise TypeError(f"material {name!r}: expected SurfaceProperties or a dict")
            self.materials[str(name)] = props

    @classmethod
    def of(cls, materials) -> "MaterialTable":
        """``materials`` as a table: None for the default, SurfaceProperties for every panel."""
        if materials is None:
            return cls()
        if isinstance(materials, SurfaceProperties):
            return cls(materials)
        return materials

    @classmethod
    def from_texts(cls, default: SurfaceProperties, override_texts) -> "MaterialTable":
        """A table from defaults and ``NAME:key=value[,key=value]`` texts; ValueError naming the bad
        item."""
        return cls(default, dict(parse_material_override(text) for text in override_texts))

    def properties(self, name: str) -> SurfaceProperties:
        """Properties of material ``name`` (the default if it has no entry)."""
        return self.materials.get(name, self.default)

    def check_names(self, mesh_material_names) -> list:
        """Names given in the table that the mesh does not have (probably typos)."""
        return sorted(set(self.materials) - set(mesh_material_names))

    def expand(self, material_names, material_index) -> PanelSurface:
        """Per-panel parameters for a mesh; ValueError naming a material it lacks."""
        unknown = self.check_names(material_names)
        if unknown:
            raise ValueError(
                f"material {', '.join(map(repr, unknown))} is not in the mesh; its materials are "
                f"{', '.join(material_names)}"
            )
        props = [self.properties(n) for n in material_names]
        used = np.flatnonzero(np.bincount(material_index))  # (np.unique imports numpy.ma)
        values = {}
        for name in SURFACE_PARAMETERS:
            per_material = np.array([getattr(p, name) for p in props])
            if np.all(per_material[used] == per_material[used[0]]):
                values[name] = float(per_material[used[0]])
            else:
                values[name] = np.ascontiguousarray(per_material[material_index])
        return PanelSurface(**values)


def parse_material_override(text: str):
    """Parse ``NAME:key=value[,key=value]`` into ``(name, {key: value})``.

    ValueError: a bad item or a key not in :data:`SURFACE_PARAMETERS` (names the material).
    """
    name, sep, rest = str(text).partition(":")
    name = name.strip()
    if not sep or not name:
        raise ValueError(f"expected NAME:KEY=VALUE[,KEY=VALUE], got {text!r}")
    values = {}
    for item in rest.split(","):
        key, sep, value = item.partition("=")
        key = key.strip().replace("-", "_")
        if not sep or key not in SURFACE_PARAMETERS:
            raise ValueError(
                f"material {name}: unknown parameter {key!r}; "
                f"allowed: {', '.join(SURFACE_PARAMETERS)}"
            )
        try:
            values[key] = float(value)
        except ValueError:
            raise ValueError(f"material {name}: {key} must be a number, got {value!r}") from None
    return name, values
