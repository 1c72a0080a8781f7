"""Which part of each panel the flow (or sunlight) reaches: the output of shading. The lit fraction
of every panel (effective area A_i f_i) and, for partly lit panels, the shift of the centre of
pressure to the lit part's centroid, stored sparsely."""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.mesh import PanelMesh


def _read_only(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array


class PanelLighting:
    """Lit fraction and lit-centroid shift of every panel, for one flow direction (read-only).

    lit_fraction: (N,) in [0, 1]; shift_index (K,): panels with a shifted lit centroid;
    shift: lit centroid minus barycentre (K, 3) [m], G.
    ValueError: ``lit_fraction`` not 1-D in [0, 1], or shifts that do not match.
    """

    __slots__ = (
        "n_panels",
        "shaded_index",
        "shaded_fraction",
        "shift_index",
        "shift",
        "shift_fraction",
    )

    def __init__(self, lit_fraction, shift_index=None, shift=None):
        f = np.asarray(lit_fraction, dtype=float)
        if f.ndim != 1 or not np.all((f >= 0.0) & (f <= 1.0)):
            raise ValueError("lit_fraction must be a 1-D array of numbers in [0, 1]")
        index = np.zeros(0, dtype=np.int64) if shift_index is None else shift_index
        index = np.asarray(index, dtype=np.int64).reshape(-1)
        shift = np.zeros((0, 3)) if shift is None else np.asarray(shift, dtype=float)
        if shift.shape != (index.size, 3):
            raise ValueError(
                f"shift must have shape ({index.size}, 3) for {index.size} shift_index entries, "
                f"got {shift.shape}"
            )
        if index.size and (index.min() < 0 or index.max() >= f.size):
            raise ValueError(f"shift_index must be panel indices in [0, {f.size - 1}]")
        self.n_panels = int(f.size)
        shaded = np.flatnonzero(f < 1.0)
        self.shaded_index = _read_only(shaded.astype(np.int32))
        self.shaded_fraction = _read_only(f[shaded])
        self.shift_index = _read_only(index.copy())
        self.shift = _read_only(shift.copy())
        self.shift_fraction = _read_only(f[index])

    @classmethod
    def many(cls, lit_fraction, rows, shift_index, shift) -> list:
        """The lightings of the rows of ``lit_fraction`` (M, N) in [0, 1], with the shifts
        ``shift`` (K, 3) [m] of panels ``shift_index`` (K,) of rows ``rows`` (K,), in order of
        row, then panel (the arrays are kept, made read-only)."""
        f = np.asarray(lit_fraction, dtype=float)
        if not np.all((f >= 0.0) & (f <= 1.0)):
            raise ValueError("lit_fraction must be numbers in [0, 1]")
        row, shaded = np.nonzero(f < 1.0)
        shaded, values, lit = shaded.astype(np.int32), f[row, shaded], f[rows, shift_index]
        for array in (shaded, values, shift_index, shift, lit):
            _read_only(array)  # (before the views are taken: they inherit it)
        ends, stops = (np.searchsorted(x, np.arange(len(f) + 1)).tolist() for x in (row, rows))
        out = []
        for a, b, c, d in zip(ends, ends[1:], stops, stops[1:]):  # (a loop over the rows)
            one = cls.__new__(cls)
            one.n_panels, one.shaded_index, one.shaded_fraction = (
                f.shape[1],
                shaded[a:b],
                values[a:b],
            )
            one.shift_index, one.shift, one.shift_fraction = shift_index[c:d], shift[c:d], lit[c:d]
            out.append(one)
        return out

    @classmethod
    def all_lit(cls, n_panels: int) -> "PanelLighting":
        """Every one of ``n_panels`` panels fully lit (no occlusion)."""
        return cls(np.ones(n_panels))

    def __repr__(self) -> str:
        return (
            f"PanelLighting(n_panels={self.n_panels}, not fully lit={self.shaded_index.size}, "
            f"shifted={self.shift_index.size})"
        )

    @property
    def lit_fraction(self) -> np.ndarray:
        """Lit fraction of every panel, shape (N,), in [0, 1] (a new read-only array)."""
        f = np.ones(self.n_panels)
        f[self.shaded_index] = self.shaded_fraction
        return _read_only(f)

    @property
    def shaded(self) -> np.ndarray:
        """Boolean (N,): panels entirely in shadow."""
        out = np.zeros(self.n_panels, dtype=bool)
        out[self.shaded_index[self.shaded_fraction <= 0.0]] = True
        return out

    @property
    def partly_lit(self) -> np.ndarray:
        """Boolean (N,): panels partly in shadow."""
        out = np.zeros(self.n_panels, dtype=bool)
        out[self.shaded_index[self.shaded_fraction > 0.0]] = True
        return out


class LightingBlend:
    """A weighted mean of lightings (the interpolating cache's answer): f_i = sum_k w_k f_k,i and
    d_i = sum_k w_k f_k,i d_k,i / f_i, so the panel method's result is the mean of the parts'.

    parts: (weight, PanelLighting) pairs of one mesh, weights positive, summing to 1 within 1e-9.
    """

    def __init__(self, parts):
        parts = tuple(parts)
        weights = [w for w, _ in parts]
        if not (weights and all(w > 0.0 for w in weights) and abs(sum(weights) - 1.0) <= 1e-9):
            raise ValueError(f"blend weights must be positive and sum to 1, got {weights}")
        sizes = {lighting.n_panels for _, lighting in parts}
        if len(sizes) != 1:
            raise ValueError(f"blended lightings must have one panel count, got {sorted(sizes)}")
        self.parts = parts
        self.n_panels = sizes.pop()
        self._combined = None

    @classmethod
    def of(cls, parts) -> "PanelLighting | LightingBlend":
        """The blend of ``parts``, or the one lighting itself if there is only one."""
        if len(parts) == 1:
            return parts[0][1]
        return cls(parts)

    def __repr__(self) -> str:
        weights = ", ".join(f"{w:.3f}" for w, _ in self.parts)
        return f"LightingBlend(n_panels={self.n_panels}, weights=({weights}))"

    @property
    def combined(self) -> PanelLighting:
        """The blend as one :class:`PanelLighting` (made once)."""
        if self._combined is None:
            f = np.zeros(self.n_panels)
            for w, lighting in self.parts:
                f += w * lighting.lit_fraction
            index = np.concatenate([lighting.shift_index for _, lighting in self.parts])
            moments = np.concatenate(
                [
                    (w * lighting.shift_fraction)[:, None] * lighting.shift
                    for w, lighting in self.parts
                ]
            )
            index, inverse = np.unique(index, return_inverse=True)
            summed = np.zeros((index.size, 3))
            np.add.at(summed, inverse.reshape(-1), moments)
            lit = f[index][:, None]
            shift = np.divide(summed, lit, out=np.zeros_like(summed), where=lit > 0.0)
            self._combined = PanelLighting(np.clip(f, 0.0, 1.0), index, shift)
        return self._combined

    def __getattr__(self, name):
        """The per-panel views of :attr:`combined`, as :class:`PanelLighting` gives them."""
        if name.startswith("_") or not hasattr(PanelLighting, name):
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        return getattr(self.combined, name)


def panel_range(lighting, start: int, stop: int, rotation=None):
    """The lighting of panels ``start`` to ``stop - 1`` alone (None if all lit), shifts rotated."""
    if lighting is None:
        return None
    if isinstance(lighting, LightingBlend):
        parts = [(w, panel_range(part, start, stop, rotation)) for w, part in lighting.parts]
        if all(part is None for _, part in parts):
            return None
        n = stop - start
        return LightingBlend(
            [(w, PanelLighting.all_lit(n) if part is None else part) for w, part in parts]
        )
    shaded = lighting.shaded_index
    lo, hi = np.searchsorted(shaded, (start, stop))
    if lo == hi:  # (a panel with a shift is partly lit, so among the shaded ones)
        return None
    f = np.ones(stop - start)
    f[shaded[lo:hi] - start] = lighting.shaded_fraction[lo:hi]
    keep = (lighting.shift_index >= start) & (lighting.shift_index < stop)
    shift = lighting.shift[keep]
    if rotation is not None:
        shift = shift @ np.asarray(rotation, dtype=float).T
    return PanelLighting(f, lighting.shift_index[keep] - start, shift)


def lit_projected_area(mesh: PanelMesh, u_G, lighting: PanelLighting | None = None) -> float:
    """Lit projected area sum_i f_i A_i max(cos delta_i, 0) [m^2] for flow direction ``u_G``."""
    u = frames.unit_vector(u_G)
    c = np.maximum(-(mesh.normals @ u), 0.0)
    f = 1.0 if lighting is None else lighting.lit_fraction
    return float((f * mesh.areas * c).sum())
