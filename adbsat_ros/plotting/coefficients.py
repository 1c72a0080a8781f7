"""Figures of an aerodynamic database against angle of attack [deg], one line per sideslip.

ADBSat's names: ``CD``, ``CL``, ``CY`` (wind axes), ``Cm_B`` (body frame B about the moment point).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from matplotlib import colormaps
from matplotlib.figure import Figure

from adbsat_ros.plotting.figures import new_figure, save_figures

#: At most this many sideslip lines per database panel (evenly spaced if there are more).
MAX_SIDESLIP_LINES = 7


def select_sideslip_lines(aos_deg, max_lines: int = MAX_SIDESLIP_LINES) -> np.ndarray:
    """Indices of at most ``max_lines`` (>= 2) evenly spaced sideslips, 0 deg kept."""
    aos = np.asarray(aos_deg, dtype=float)
    n = aos.size
    if max_lines < 2:
        raise ValueError(f"max_lines must be >= 2, got {max_lines}")
    if n <= max_lines:
        return np.arange(n)
    picks = np.unique(np.round(np.linspace(0, n - 1, max_lines)).astype(int))
    zero = np.flatnonzero(aos == 0.0)
    if zero.size and zero[0] not in picks:
        inner = picks[1:-1]  # keep the ends
        if inner.size:
            nearest = inner[np.argmin(np.abs(aos[inner]))]
            picks = np.unique(np.where(picks == nearest, zero[0], picks))
    return picks


def _metadata_value(metadata: dict, *keys, default=None):
    """``metadata[k0][k1]...``, or ``default`` where a key is missing."""
    value = metadata
    for key in keys:
        if not isinstance(value, dict) or key not in value:
            return default
        value = value[key]
    return value


def database_title(metadata: dict) -> str:
    """The mesh, model, speed ratio and shading (or test particles) of a database, in one line."""
    mesh = _metadata_value(metadata, "mesh", "spec", default=None) or _metadata_value(
        metadata, "mesh", "source", default="?"
    )
    mesh = Path(str(mesh)).name if str(mesh) != "example" else "example satellite"
    n_panels = _metadata_value(metadata, "mesh", "n_panels")
    model = _metadata_value(metadata, "model", "name", default="?")
    s = _metadata_value(metadata, "flow", "speed_ratio")
    shading = _metadata_value(metadata, "shading", "mode", default="?")
    parts = [f"{mesh}" + (f" ({n_panels} panels)" if n_panels is not None else ""), f"{model}"]
    if s is not None:
        parts.append(f"speed ratio s = {float(s):.2f}")
    if _metadata_value(metadata, "solver", "method") == "tpmc":
        particles = _metadata_value(metadata, "solver", "particles")
        parts.append("test particles" + (f": {particles:,} per attitude" if particles else ""))
    else:
        parts.append(f"shading: {shading}")
    return ", ".join(parts)


def _sideslip_lines(ax, aoa, values, aos, picks):
    """One line per picked sideslip, coloured by |beta|, dashed for negative beta."""
    cmap = colormaps["plasma"]
    span = max(float(np.max(np.abs(aos[picks]))), 1e-12)
    for j in picks:
        colour = cmap(0.82 * abs(aos[j]) / span)
        ax.plot(
            aoa,
            values[:, j],
            color=colour,
            lw=1.3,
            ls=(0, (4, 2)) if aos[j] < 0 else "-",
            label=f"{aos[j]:g}",
        )


def _angle_axis(ax, aoa):
    """The angle-of-attack axis: the grid's range, ticks every 5 to 90 deg, a zero line."""
    lo, hi = float(np.min(aoa)), float(np.max(aoa))
    ax.set_xlim(lo, hi)
    span = hi - lo
    step = next((s for s in (5, 10, 15, 30, 45, 90) if span / s <= 10), 90)
    if span > 0:
        ax.set_xticks(np.arange(math.ceil(lo / step) * step, hi + 1e-9, step))
    ax.grid(True, lw=0.4, alpha=0.6)
    ax.axhline(0.0, color="0.3", lw=0.6)


def _legend_title(aos, picks) -> str:
    """Title of the sideslip legend, saying how many lines are shown if not all."""
    title = "sideslip β [deg]"
    if picks.size < aos.size:
        title += f"\n({picks.size} of {aos.size} shown)"
    return title + "\ndashed: β < 0"


def _database_figure(db, series, ylabels, heading, max_lines) -> Figure:
    """Stacked panels, one per array of ``series`` (shape (na, nb)), against angle of attack."""
    aoa = np.asarray(db.aoa_deg, dtype=float)
    aos = np.asarray(db.aos_deg, dtype=float)
    picks = select_sideslip_lines(aos, max_lines)
    fig = new_figure((8.0, 6.5))
    axes = fig.subplots(len(series), 1, sharex=True)
    for ax, values, label in zip(axes, series, ylabels):
        values = np.asarray(values, dtype=float)
        if values.shape != (aoa.size, aos.size):
            raise ValueError(f"{label}: expected shape {(aoa.size, aos.size)}, got {values.shape}")
        _sideslip_lines(ax, aoa, values, aos, picks)
        _angle_axis(ax, aoa)
        ax.set_ylabel(label)
    axes[-1].set_xlabel("angle of attack α [deg]")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(
        handles,
        labels,
        loc="outside right center",
        title=_legend_title(aos, picks),
        fontsize=8,
        title_fontsize=8,
    )
    fig.suptitle(f"{heading}\n{database_title(getattr(db, 'metadata', {}) or {})}", fontsize=10)
    return fig


def make_force_coefficient_figure(db, max_lines: int = MAX_SIDESLIP_LINES) -> Figure:
    """C_D, C_L and C_Y against angle of attack, one line per sideslip angle.

    ``db``: ``aoa_deg`` (na,), ``aos_deg`` (nb,) [deg], ``CD``, ``CL``, ``CY`` (na, nb).
    """
    return _database_figure(
        db,
        (db.CD, db.CL, db.CY),
        ("drag $C_D$", "lift $C_L$", "side force $C_Y$"),
        "Force coefficients (wind axes)",
        max_lines,
    )


def make_moment_coefficient_figure(db, max_lines: int = MAX_SIDESLIP_LINES) -> Figure:
    """The three components of Cm_B (na, nb, 3) against angle of attack."""
    cm = np.asarray(db.Cm_B, dtype=float)
    if cm.ndim != 3 or cm.shape[-1] != 3:
        raise ValueError(f"Cm_B: expected shape (na, nb, 3), got {cm.shape}")
    point = _metadata_value(getattr(db, "metadata", {}) or {}, "reference", "moment_point")
    heading = "Moment coefficients $C_{m,B}$ (ADBSat body axes: x fwd, y = -y$_G$, z = -z$_G$)"
    if point is not None:
        heading += " about (" + ", ".join(f"{float(v):g}" for v in point) + ") m"
    return _database_figure(
        db,
        (cm[..., 0], cm[..., 1], cm[..., 2]),
        ("roll $C_{m,x}$", "pitch $C_{m,y}$", "yaw $C_{m,z}$"),
        heading,
        max_lines,
    )


def plot_database(db, out_dir, prefix: str = "", max_lines: int = MAX_SIDESLIP_LINES) -> list[Path]:
    """Write ``{prefix}database_coefficients.png`` and ``..._moments.png``; the paths."""
    figures = {
        "database_coefficients": make_force_coefficient_figure(db, max_lines),
        "database_moments": make_moment_coefficient_figure(db, max_lines),
    }
    return save_figures(figures, out_dir, prefix)
