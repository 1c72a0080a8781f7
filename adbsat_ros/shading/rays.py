"""Ray casting against a mesh: one interface, two backends.

A *ray scene* answers, for rays of one direction (shading), whether each meets an occluding
panel at t > 0 and which first, and for rays of their own directions (test particles), which
panel each meets first and how far. ``"embree"``: Embree through embreex, float32
(:mod:`adbsat_ros.shading.rays_embree`); ``"numpy"``: Moeller-Trumbore in float64, the reference
and fallback (:mod:`adbsat_ros.shading.rays_numpy`). Shared edges count as inside both triangles;
the two agree except within float32 rounding (~1e-7 of the mesh size) of an edge.
``has_embree`` says whether embreex imports; ``"auto"`` picks Embree then. Units: metres, G.
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
        """Whether each ray origins[r] + t direction, t > 0, meets an occluding panel.

        Parameters
        ----------
        origins : ndarray, shape (R, 3)
            Ray origins [m], mesh frame G.
        direction : ndarray, shape (3,)
            Common unit ray direction (G).
        occluder : ndarray of bool, shape (N,), optional
            Panels that can block a ray (default all); panels parallel to ``direction`` must
            be left out.

        Returns
        -------
        ndarray of bool, shape (R,)
        """
        ...

    def first_face(self, origins, direction, occluder=None) -> np.ndarray:
        """The first occluding panel each ray origins[r] + t direction, t > 0, meets.

        Parameters
        ----------
        origins, direction, occluder
            As :meth:`any_hit`.

        Returns
        -------
        ndarray of int64, shape (R,)
            Panel index, -1 exactly where :meth:`any_hit` says the ray is not blocked.
        """
        ...

    def first_hit(self, origins, directions) -> tuple:
        """The first panel each ray origins[r] + t directions[r], t > 0, meets.

        Parameters
        ----------
        origins, directions : ndarray, shape (R, 3)
            Ray origins [m] and directions (G; any non-zero length, e.g. velocities).

        Returns
        -------
        face : ndarray of int64, shape (R,)
            Panel index, -1 where the ray meets none.
        t : ndarray, shape (R,)
            The hit is at origins + t directions (t the distance [m] for unit directions; inf
            where none).
        """
        ...


def resolve_backend(backend: str) -> str:
    """The backend that ``backend`` names: ``"embree"`` or ``"numpy"``.

    Parameters
    ----------
    backend : {"auto", "embree", "numpy"}
        ``"auto"`` is ``"embree"`` if :data:`has_embree`, else ``"numpy"``.

    Raises
    ------
    ValueError
        For an unknown name, listing :data:`BACKENDS`.
    RuntimeError
        For ``"embree"`` when embreex is not available, saying why.
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
    """A ray scene of the panels of ``mesh`` with the given backend.

    Parameters
    ----------
    mesh : PanelMesh
        Panels [m], mesh frame G; face i of the scene is panel i.
    backend : {"auto", "embree", "numpy"}
        See :func:`resolve_backend`.
    indexed : (ndarray, ndarray), optional
        The panels as merged vertices (V, 3) and faces (N, 3), made before.

    Returns
    -------
    RayScene
        An :class:`EmbreeScene` or a :class:`NumpyScene`.
    """
    if resolve_backend(backend) == "embree":
        return EmbreeScene(mesh, indexed)
    return NumpyScene(mesh)
