"""Ray casting against a mesh: one interface (:class:`RayScene`), two backends: ``"embree"``
(float32) and ``"numpy"`` (float64, the reference), equal except within float32 rounding of an
edge; shared edges count as inside both triangles. Units: metres, mesh frame G."""

from __future__ import annotations

from typing import Protocol

import numpy as np

from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.shading.rays_numpy import NumpyScene

try:
    from adbsat_ros.shading.rays_embree import EmbreeScene
except (ImportError, OSError) as exc:  # embreex missing, or its Embree library
    EmbreeScene = None
    #: Why Embree is not available (None if it is).
    EMBREE_ERROR = f"{type(exc).__name__}: {exc}"
else:
    EMBREE_ERROR = None

#: True if the Embree backend can be used.
has_embree = EmbreeScene is not None

#: Valid values of the ``backend`` argument.
BACKENDS = ("auto", "embree", "numpy")


class RayScene(Protocol):
    """What a ray backend's scene provides (:class:`NumpyScene`, :class:`EmbreeScene`)."""

    #: Name of the backend, ``"embree"`` or ``"numpy"``.
    backend: str

    def any_hit(self, origins, direction, occluder=None) -> np.ndarray:
        """Whether each ray origins[r] + t direction, t > 0, meets an occluding panel, (R,) bool.

        origins (R, 3) [m], unit direction (3,), G; occluder (N,) bool, none parallel to the
        direction.
        """
        ...

    def first_face(self, origins, direction, occluder=None) -> np.ndarray:
        """The first occluding panel (R,) each ray meets (as :meth:`any_hit`), -1 for none."""
        ...

    def first_hit(self, origins, directions) -> tuple:
        """``(face, t)`` of the first panel each ray meets (-1, inf: none); directions (R, 3), G."""
        ...


def resolve_backend(backend: str) -> str:
    """``"embree"`` or ``"numpy"`` for ``backend`` (``"auto"``: Embree if :data:`has_embree`).

    ValueError for an unknown name, RuntimeError for ``"embree"`` without embreex.
    """
    name = str(backend).lower()
    if name not in BACKENDS:
        raise ValueError(f"unknown backend {backend!r}; choose one of {', '.join(BACKENDS)}")
    if name == "auto":
        return "embree" if has_embree else "numpy"
    if name == "embree" and not has_embree:
        raise RuntimeError(
            f"backend 'embree' requested but embreex is not available ({EMBREE_ERROR})"
        )
    return name


def ray_scene(mesh: PanelMesh, backend: str = "auto", indexed: tuple | None = None) -> RayScene:
    """A ray scene of the panels of ``mesh`` (face i is panel i) with ``backend``."""
    if resolve_backend(backend) == "embree":
        return EmbreeScene(mesh, indexed)
    return NumpyScene(mesh)
