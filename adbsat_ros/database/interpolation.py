"""Bilinear interpolation on an (aoa, aos) grid, and a database's stated interpolation error: the
grid coarsened by 2 interpolated at the nodes it omits, the largest error unscaled (near shadow
edges the first-order 1/2 does not hold). docs/databases.md.
"""

from __future__ import annotations

import bisect

import numpy as np

from adbsat_ros.database.format import AeroDatabase

#: Factor from the coarse-grid error to the stated error of the full grid.
ERROR_SCALING = 1.0
#: How the error was estimated, as recorded in ``metadata["interpolation_error"]["method"]``.
ERROR_METHOD = (
    "coarsen-by-2: bilinear interpolant of every other node vs exact values at the omitted nodes, "
    "max Euclidean vector error, not scaled down"
)


def _locate(nodes: np.ndarray, x: np.ndarray):
    """Cell index i (nodes[i] <= x <= nodes[i+1]) and fraction t in [0, 1] for each x."""
    if nodes.size == 1:
        return np.zeros(np.shape(x), dtype=np.intp), np.zeros(np.shape(x))
    i = np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, nodes.size - 2)
    t = (x - nodes[i]) / (nodes[i + 1] - nodes[i])
    return i, t


def cell(nodes: list, x: float) -> tuple:
    """``(i, i + 1, t)``: :func:`_locate` of one ``x`` in ``nodes``, a list of floats."""
    n = len(nodes)
    if n == 1:
        return 0, 0, 0.0
    i = min(max(bisect.bisect_right(nodes, x) - 1, 0), n - 2)
    return i, i + 1, (x - nodes[i]) / (nodes[i + 1] - nodes[i])


def bilinear_one(a_nodes: list, b_nodes: list, rows: list, qa: float, qb: float) -> list:
    """:func:`bilinear` at one point on Python floats (``rows``: ``values.tolist()``)."""
    i, i1, t = cell(a_nodes, qa)
    j, j1, s = cell(b_nodes, qb)
    v00, v01, v10, v11 = rows[i][j], rows[i][j1], rows[i1][j], rows[i1][j1]
    w00, w01, w10, w11 = (1.0 - t) * (1.0 - s), (1.0 - t) * s, t * (1.0 - s), t * s
    return [w00 * p + w01 * q + w10 * r + w11 * z for p, q, r, z in zip(v00, v01, v10, v11)]


def bilinear(a_nodes, b_nodes, values, qa, qb) -> np.ndarray:
    """Bilinear interpolation (M, k) of ``values`` (na, nb, k) inside the grid; no range checks."""
    qa, qb = np.broadcast_arrays(np.asarray(qa, float), np.asarray(qb, float))
    ia, ta = _locate(a_nodes, qa)
    ib, tb = _locate(b_nodes, qb)
    ia1 = ia + (1 if a_nodes.size > 1 else 0)
    ib1 = ib + (1 if b_nodes.size > 1 else 0)
    ta, tb = ta[..., None], tb[..., None]
    return (1.0 - ta) * ((1.0 - tb) * values[ia, ib] + tb * values[ia, ib1]) + ta * (
        (1.0 - tb) * values[ia1, ib] + tb * values[ia1, ib1]
    )


def _coarse_indices(n: int) -> np.ndarray:
    return np.unique(np.append(np.arange(0, n, 2), n - 1))


def estimate_interpolation_error(db: AeroDatabase) -> dict:
    """The stated error of a database's grid (bounds on |dCf_G|, |dCm_G|)."""
    na, nb = db.shape
    out = {
        "method": ERROR_METHOD,
        "scaling": ERROR_SCALING,
        "max_force_coefficient": float(np.linalg.norm(db.Cf_G, axis=-1).max()),
        "max_moment_coefficient": float(np.linalg.norm(db.Cm_G, axis=-1).max()),
    }
    ca = _coarse_indices(na) if na >= 3 else np.arange(na)
    cb = _coarse_indices(nb) if nb >= 3 else np.arange(nb)
    omitted = np.ones((na, nb), dtype=bool)
    omitted[np.ix_(ca, cb)] = False
    if not omitted.any():
        out.update(
            force_coefficient=None,
            moment_coefficient=None,
            points=0,
            coarse_force_error=None,
            coarse_moment_error=None,
            method="unavailable: the grid needs at least 3 nodes along an axis to estimate it",
        )
        return out
    values = np.concatenate([db.Cf_G, db.Cm_G], axis=-1)
    ia, ib = np.nonzero(omitted)
    coarse = bilinear(
        db.aoa_deg[ca], db.aos_deg[cb], values[np.ix_(ca, cb)], db.aoa_deg[ia], db.aos_deg[ib]
    )
    diff = coarse - values[ia, ib]
    force = float(np.linalg.norm(diff[:, :3], axis=-1).max())
    moment = float(np.linalg.norm(diff[:, 3:], axis=-1).max())
    out.update(
        force_coefficient=ERROR_SCALING * force,
        moment_coefficient=ERROR_SCALING * moment,
        points=int(ia.size),
        coarse_force_error=force,
        coarse_moment_error=moment,
    )
    return out
