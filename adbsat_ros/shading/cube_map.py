"""Cells of the sphere of flow directions: an equi-angular cube map (the shading cache's keys).
A direction (G, any length) maps to its face and two angles in [-45, 45] deg, each cut into n
steps (docs/shading.md, "Cache")."""

from __future__ import annotations

import math

import numpy as np

_QUARTER = 0.25 * math.pi


def cells_per_edge(resolution_deg: float) -> int:
    """The smallest odd n >= 90 / resolution_deg (odd: the six axis directions are cell centres)."""
    resolution_deg = float(resolution_deg)
    if not (math.isfinite(resolution_deg) and 0.0 < resolution_deg <= 90.0):
        raise ValueError(f"resolution_deg must be in (0, 90], got {resolution_deg!r}")
    n = max(1, math.ceil(90.0 / resolution_deg - 1e-9))
    return n if n % 2 == 1 else n + 1


def direction_keys(u, n: int) -> np.ndarray:
    """Cube-map cell keys (int64) of non-zero directions ``u`` (G): face * n^2 + i * n + j."""
    u = np.asarray(u, dtype=float)
    single = u.ndim == 1
    u = np.atleast_2d(u)
    rows = np.arange(len(u))
    k = np.argmax(np.abs(u), axis=1)
    uk = u[rows, k]
    face = 2 * k + (uk < 0)
    ak = np.abs(uk)
    a = np.arctan2(u[rows, (k + 1) % 3], ak)
    b = np.arctan2(u[rows, (k + 2) % 3], ak)
    h = 0.5 * math.pi / n
    i = np.clip(np.floor((a + _QUARTER) / h), 0, n - 1).astype(np.int64)
    j = np.clip(np.floor((b + _QUARTER) / h), 0, n - 1).astype(np.int64)
    key = face.astype(np.int64) * n * n + i * n + j
    return key[0] if single else key


def face_axes(x: float, y: float, z: float) -> tuple:
    """``(face, |u_k|, u_a, u_b)`` of one direction: k the first axis of largest |u_k|."""
    ax, ay, az = abs(x), abs(y), abs(z)
    if ax >= ay and ax >= az:
        return (x < 0.0), ax, y, z
    if ay >= az:
        return 2 + (y < 0.0), ay, z, x
    return 4 + (z < 0.0), az, x, y


def direction_key(x: float, y: float, z: float, n: int) -> int:
    """:func:`direction_keys` of one direction given as three floats (no numpy; tested equal)."""
    face, ak, a1, a2 = face_axes(x, y, z)
    h = 0.5 * math.pi / n
    i = min(max(math.floor((math.atan2(a1, ak) + _QUARTER) / h), 0), n - 1)
    j = min(max(math.floor((math.atan2(a2, ak) + _QUARTER) / h), 0), n - 1)
    return face * n * n + i * n + j


def key_centres(keys, n: int) -> np.ndarray:
    """Unit directions (3,) or (M, 3) at the centres of cube-map cells ``keys`` (``n`` steps)."""
    keys = np.asarray(keys, dtype=np.int64)
    single = keys.ndim == 0
    keys = np.atleast_1d(keys)
    if np.any((keys < 0) | (keys >= 6 * n * n)):
        raise ValueError("cube-map key out of range")
    face, rest = np.divmod(keys, n * n)
    i, j = np.divmod(rest, n)
    k = face // 2
    sign = np.where(face % 2 == 1, -1.0, 1.0)
    h = 0.5 * math.pi / n
    a = -_QUARTER + (i + 0.5) * h
    b = -_QUARTER + (j + 0.5) * h
    out = np.zeros((len(keys), 3))
    rows = np.arange(len(keys))
    out[rows, k] = sign
    out[rows, (k + 1) % 3] = np.tan(a)
    out[rows, (k + 2) % 3] = np.tan(b)
    out /= np.linalg.norm(out, axis=1, keepdims=True)
    return out[0] if single else out
