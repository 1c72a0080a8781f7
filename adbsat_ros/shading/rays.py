"""Ray casting against a mesh: one interface (:class:`RayScene`), two backends.

``"embree"`` (float32, :mod:`~.rays_embree`) and ``"numpy"`` (float64 Moeller-Trumbore, the
reference, :mod:`~.rays_numpy`) agree except within float32 rounding (~1e-7 of the mesh size) of
an edge; shared edges count as inside both triangles. Units: metres, mesh frame G.
"""

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

        ``origins`` (R, 3) [m] and the unit ``direction`` (3,) in G; ``occluder`` (N,) bool, the
        panels that can block (default all; panels parallel to ``direction`` must be left out).
        """
        ...

    def first_face(self, origins, direction, occluder=None) -> np.ndarray:
        """The first occluding panel (R,) int64 each ray meets (as :meth:`any_hit`), -1 for
        none exactly where :meth:`any_hit` is False."""
        ...

    def first_hit(self, origins, directions) -> tuple:
        """``(face, t)``, (R,) each: the first panel each ray origins[r] + t directions[r], t > 0,
        meets (-1 and inf for none); directions (R, 3) of any non-zero length, G."""
        ...


def resolve_backend(backend: str) -> str:
    """The backend ``"embree"`` or ``"numpy"`` that ``backend`` names (``"auto"``: Embree if
    :data:`has_embree`).

    Raises ValueError for an unknown name, RuntimeError for ``"embree"`` without embreex.
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
    """A ray scene of the panels of ``mesh`` (face i is panel i) with ``backend``; ``indexed``:
    its merged vertices (V, 3) and faces (N, 3), if made before."""
    if resolve_backend(backend) == "embree":
        return EmbreeScene(mesh, indexed)
    return NumpyScene(mesh)
