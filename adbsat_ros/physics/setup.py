"""One configured aerodynamic body as a value, :class:`Setup` (body, materials, reference,
model, shading policy, solver), checked once and built by
:func:`adbsat_ros.physics.model.build_model`. Each dialect has one translator to it (command
line, node parameters, database metadata, sweep spec; docs/architecture.md), and errors name
an input as that dialect does (:attr:`Setup.labels`).
"""

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

    Attributes
    ----------
    mesh : str
        A mesh file, a bundled body (``example``, ``cylinder`` ...) or a URDF (a ``.urdf``
        file, ``example-articulated``, ``example-finned``).
    scale : float
        Factor from file units to metres (mesh files only).
    accept_size : bool
        Take a mesh that is under 1 mm or over 200 m across.
    urdf : str
        A URDF's text (the node's ``robot_description``), taken instead of ``mesh``.
    joints : tuple of (str, float) or None
        A URDF posed once at these joint positions (the others at 0) and evaluated as a rigid
        body; None: a URDF's joints move (an articulated body).
    joint_degrees : bool
        ``joints`` of revolute and continuous joints are in degrees (else radians); prismatic
        ones in metres.
    """

    mesh: str = EXAMPLE_MESH_NAME
    scale: float = 1.0
    accept_size: bool = False
    urdf: str = ""
    joints: tuple | None = None
    joint_degrees: bool = False


@dataclass(frozen=True)
class ShadingPolicy:
    """How the panels are shaded: the mode, rays per panel, and the node's shading cache (a
    rigid body's flow-direction cells; an articulated body's grid of joint configurations, or
    its exact shading). ``exact_offline`` > 0: an offline job's cache instead, in exact mode
    (the flow directions and joint positions themselves, no cells), keeping that many
    lightings (:attr:`~adbsat_ros.physics.model.Model.cache`)."""

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
    """The solver: ``panel``, ``tpmc`` (test particles: ``particles``, ``tolerance``,
    ``seed`` of each run) or ``both``."""

    method: str = "panel"
    particles: int | None = None
    tolerance: float | None = None
    seed: int = 0


@dataclass(frozen=True)
class Setup:
    """A configured aerodynamic body, checked when made (ValueError naming the input).

    ``model`` is the canonical name; ``surface`` the default of every material and
    ``overrides`` per-material ``NAME:key=value[,key=value]``; ``reference`` area and length
    (None: from the mesh) and moment point (centre of mass); ``labels`` (str, str) pairs: how
    the dialect names ``materials``, ``moment_point``, ``joints``, ``samples`` and ``solver``
    in error messages (default those words; ``""``: no prefix).
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
        """The set-up with ``alpha`` as alpha and alpha_n of the default surface and of every
        material (an accommodation model's value at the flight conditions)."""
        a = float(alpha)
        return replace(
            self,
            surface=replace(self.surface, alpha=a, alpha_n=a),
            overrides=tuple(f"{text},alpha={a!r},alpha_n={a!r}" for text in self.overrides),
        )
