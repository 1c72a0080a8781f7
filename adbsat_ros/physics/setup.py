"""One configured aerodynamic body as a value, :class:`Setup`, checked once and built by
:func:`adbsat_ros.physics.model.build_model`. Each dialect (command line, node parameters,
database metadata, sweep spec; docs/architecture.md) has one translator to it."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from adbsat_ros.geometry.example_satellite import EXAMPLE_MESH_NAME
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.gsi_models import ModelOptions, canonical_model_name
from adbsat_ros.physics.surface import MaterialTable, SurfaceProperties
from adbsat_ros.shading.shader import DEFAULT_SAMPLES
from adbsat_ros.shading.shader import MODES as SHADING_MODES

#: Solvers of a set-up: the panel method, test particles, or each (the command line's ``both``).
SOLVERS = ("panel", "tpmc", "both")


@dataclass(frozen=True)
class BodySpec:
    """Where the body's panels come from.

    mesh: a mesh file, a bundled body or a URDF; scale: file units to metres (mesh files only);
    urdf: a URDF's text instead of ``mesh``; joints: a URDF posed once there (None: joints move);
    joint_degrees: revolute joints in degrees (else radians; prismatic in metres).
    """

    mesh: str = EXAMPLE_MESH_NAME
    scale: float = 1.0
    accept_size: bool = False
    urdf: str = ""
    joints: tuple | None = None
    joint_degrees: bool = False


@dataclass(frozen=True)
class ShadingPolicy:
    """How the panels are shaded: mode, rays per panel and the node's shading cache.

    ``exact_offline`` > 0: an offline job's exact-mode cache keeping that many lightings.
    """

    mode: str = "raycast"
    samples: int = DEFAULT_SAMPLES
    cache_resolution_deg: float = 0.25
    cache_size: int = 20000
    interpolation: bool = True
    joint_resolution_deg: float = 0.25
    joint_resolution_m: float = 0.001
    joint_interpolation: bool = False
    joint_cache_size: int = 64
    joint_exact: bool = False
    exact_offline: int = 0


@dataclass(frozen=True)
class SolverSpec:
    """The solver: ``panel``, ``tpmc`` (``particles``, ``tolerance``, ``seed``) or ``both``."""

    method: str = "panel"
    particles: int | None = None
    tolerance: float | None = None
    seed: int = 0


@dataclass(frozen=True)
class Setup:
    """A configured aerodynamic body, checked when made (ValueError naming the input).

    ``overrides``: per-material ``NAME:key=value`` texts; ``reference``: area, length (None: from
    the mesh), moment point; ``labels``: how the dialect names inputs in errors.
    """

    body: BodySpec = field(default_factory=BodySpec)
    model: str = "sentman"
    options: ModelOptions = field(default_factory=ModelOptions)
    surface: SurfaceProperties = field(default_factory=SurfaceProperties)
    overrides: tuple = ()
    reference: Reference = field(default_factory=Reference)
    shading: ShadingPolicy = field(default_factory=ShadingPolicy)
    solver: SolverSpec = field(default_factory=SolverSpec)
    labels: tuple = ()

    def __post_init__(self):
        object.__setattr__(self, "model", canonical_model_name(self.model))
        object.__setattr__(self, "overrides", tuple(self.overrides))
        scale = self.body.scale
        if isinstance(scale, bool) or not (math.isfinite(float(scale)) and scale > 0.0):
            raise ValueError(f"{self.label('scale')} must be a finite number > 0, got {scale!r}")
        if self.shading.mode not in SHADING_MODES:
            raise ValueError(
                f"{self.label('shading')}: {self.shading.mode!r} is not one of "
                f"{', '.join(SHADING_MODES)}"
            )
        if self.shading.mode != "none" and self.shading.samples < 1:
            raise ValueError(f"{self.label('samples')} must be >= 1, got {self.shading.samples}")
        offline = self.shading.exact_offline
        if isinstance(offline, bool) or not isinstance(offline, int) or offline < 0:
            raise ValueError(f"exact_offline must be a whole number >= 0, got {offline!r}")
        if self.solver.method not in SOLVERS:
            raise ValueError(f"{self.label('solver')}: {self.solver.method!r} is not a solver")
        if self.solver.method != "panel":
            from adbsat_ros.physics.tpmc.method import run_settings

            s = self.solver
            self.prefixed("solver", run_settings, s.particles, s.tolerance, s.seed)
        self.materials()

    def label(self, name: str) -> str:
        """How the set-up's dialect names the input ``name`` (:attr:`labels`)."""
        return dict(self.labels).get(name, name)

    def prefixed(self, name: str, call, *args):
        """``call(*args)``, a ValueError from it prefixed with the label of ``name``."""
        try:
            return call(*args)
        except ValueError as exc:
            label = self.label(name)
            raise ValueError(f"{label}: {exc}" if label else str(exc)) from None

    def materials(self) -> MaterialTable:
        """The default surface with the overrides (ValueError naming ``materials``)."""
        return self.prefixed("materials", MaterialTable.from_texts, self.surface, self.overrides)

    def with_accommodation(self, alpha: float) -> "Setup":
        """The set-up with ``alpha`` as alpha and alpha_n of every material."""
        a = float(alpha)
        return replace(
            self,
            surface=replace(self.surface, alpha=a, alpha_n=a),
            overrides=tuple(f"{text},alpha={a!r},alpha_n={a!r}" for text in self.overrides),
        )
