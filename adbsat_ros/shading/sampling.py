"""Where rays start on a panel: Roberts' R2 sequence, shifted per panel (SplitMix64 of the index).
Triangle coordinates (a, b): the point P1 + a (P2 - P1) + b (P3 - P1) (metres, mesh frame G)."""

from __future__ import annotations

import numpy as np

# R2 sequence (Roberts 2018): alpha = (1/g, 1/g^2), g the plastic number.
_PLASTIC = 1.32471795724474602596
_R2_ALPHA = np.array([1.0 / _PLASTIC, 1.0 / _PLASTIC**2])

#: Triangle coordinates (a, b) of the corner detection samples (1e-3 inside each corner).
CORNERS = np.array([[1e-3, 1e-3], [1.0 - 2e-3, 1e-3], [1e-3, 1.0 - 2e-3]])


def _splitmix64(x: np.ndarray) -> np.ndarray:
    """SplitMix64 hash of uint64 values (vectorised, wrapping arithmetic)."""
    z = x.astype(np.uint64) + np.uint64(0x9E3779B97F4A7C15)
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


def panel_shifts(panel_index) -> np.ndarray:
    """Fixed pseudo-random shift in [0, 1)^2 of each panel's sample pattern, shape (K, 2)."""
    i = np.asarray(panel_index, dtype=np.uint64)
    h1 = _splitmix64(2 * i)
    h2 = _splitmix64(2 * i + np.uint64(1))
    return (np.stack([h1, h2], axis=-1) >> np.uint64(11)).astype(float) * (1.0 / float(1 << 53))


def sample_coordinates(panel_index, start: int, count: int):
    """Triangle coordinates ``a, b`` (K, count) of points start .. start+count-1 of each panel."""
    shifts = panel_shifts(panel_index)
    k = np.arange(start, start + count, dtype=float)
    base = k[:, None] * _R2_ALPHA[None, :]
    base -= np.floor(base)
    x = shifts[:, None, :] + base[None, :, :]
    x -= x >= 1.0
    a, b = x[..., 0], x[..., 1]
    fold = (a + b) > 1.0
    return np.where(fold, 1.0 - a, a), np.where(fold, 1.0 - b, b)


def sample_points(vertices: np.ndarray, a: np.ndarray, b: np.ndarray, lift=None) -> np.ndarray:
    """Points P1 + a (P2 - P1) + b (P3 - P1) + lift on triangles, (K, S, 3) [m]."""
    v0 = vertices[:, 0, :]
    e1 = vertices[:, 1, :] - v0
    e2 = vertices[:, 2, :] - v0
    if lift is not None:
        v0 = v0 + lift
    return v0[:, None] + a[..., None] * e1[:, None] + b[..., None] * e2[:, None]
