"""Figures: aerodynamic databases, per-panel pressure on the mesh, and rosbag time series.

Everything here draws on :class:`matplotlib.figure.Figure` objects with the Agg canvas, never
through pyplot, so it works headless and leaves no global state behind. Each figure has a
``make_*_figure`` function that returns the Figure (for tests and notebooks) and a ``plot_*``
function that writes PNG files (about 8 x 5 in at 100 dpi, small enough to commit).

Conventions (see :mod:`adbsat_ros.geometry.frames`): angles in degrees at this interface; coefficients
as ADBSat names them (``CD``, ``CL``, ``CY`` in wind axes, ``Cm_B`` in ADBSat's body frame B,
x_B = x_G, y_B = -y_G, z_B = -z_G, about the reference moment point); the panel picture is
drawn in the mesh frame G [m].
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import Normalize, to_rgba
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from adbsat_ros.geometry import frames
from adbsat_ros.shading.lighting import PanelLighting

#: Resolution of the written PNGs [dots per inch].
DPI = 100
#: Default size of line-plot figures [in].
FIGSIZE = (8.0, 5.0)
#: At most this many sideslip lines per database panel (evenly spaced if there are more).
MAX_SIDESLIP_LINES = 7
#: Colour map of the pressure coefficient.
PRESSURE_CMAP = "viridis"
#: Face colour of panels (partly) shaded from the flow.
SHADED_COLOUR = (0.45, 0.45, 0.45, 1.0)
PARTLY_SHADED_COLOUR = (0.72, 0.72, 0.72, 1.0)
#: Back faces (facing away from the flow) are drawn in their c_p colour mixed with this much white.
BACK_FACE_WHITE = 0.55
#: The pressure picture's camera is turned this far [deg] from looking straight down the flow.
VIEW_TURN_DEG = 35.0
#: ... and kept within this elevation [deg] above or below the x_G-y_G plane.
MAX_VIEW_ELEVATION_DEG = 55.0


def _new_figure(figsize=FIGSIZE) -> Figure:
    fig = Figure(figsize=figsize, dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _save(fig: Figure, path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=DPI, format="png")
    return path


# =============================================================================== database
def select_sideslip_lines(aos_deg, max_lines: int = MAX_SIDESLIP_LINES) -> np.ndarray:
    """Indices of the sideslip angles to draw as lines.

    All of them if there are at most ``max_lines``; otherwise ``max_lines`` evenly spaced ones
    from first to last, with 0 deg swapped in for its nearest pick if the grid has it.

    Parameters
    ----------
    aos_deg : array_like, shape (nb,)
        Sideslip angles of the database [deg], increasing.
    max_lines : int
        Largest number of lines wanted (>= 2).

    Returns
    -------
    ndarray of int
        Increasing indices into ``aos_deg``.
    """
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


def _meta(metadata: dict, *keys, default=None):
    value = metadata
    for key in keys:
        if not isinstance(value, dict) or key not in value:
            return default
        value = value[key]
    return value


def database_title(metadata: dict) -> str:
    """One line naming the mesh, model, speed ratio and shading mode of a database."""
    mesh = _meta(metadata, "mesh", "spec", default=None) or _meta(metadata, "mesh", "source", default="?")
    mesh = Path(str(mesh)).name if str(mesh) != "example" else "example satellite"
    n_panels = _meta(metadata, "mesh", "n_panels")
    model = _meta(metadata, "model", "name", default="?")
    s = _meta(metadata, "flow", "speed_ratio")
    shading = _meta(metadata, "shading", "mode", default="?")
    parts = [f"{mesh}" + (f" ({n_panels} panels)" if n_panels is not None else ""), f"{model}"]
    if s is not None:
        parts.append(f"speed ratio s = {float(s):.2f}")
    parts.append(f"shading: {shading}")
    return ", ".join(parts)


def _sideslip_lines(ax, aoa, values, aos, picks):
    """One line per picked sideslip: colour by |beta|, dashed for negative beta (so that
    +beta and -beta share a colour and a symmetric body shows as overlapping pairs)."""
    from matplotlib import colormaps

    cmap = colormaps["plasma"]
    span = max(float(np.max(np.abs(aos[picks]))), 1e-12)
    for j in picks:
        colour = cmap(0.82 * abs(aos[j]) / span)
        ax.plot(aoa, values[:, j], color=colour, lw=1.3, ls=(0, (4, 2)) if aos[j] < 0 else "-", label=f"{aos[j]:g}")


def _angle_axis(ax, aoa):
    lo, hi = float(np.min(aoa)), float(np.max(aoa))
    ax.set_xlim(lo, hi)
    span = hi - lo
    step = next((s for s in (5, 10, 15, 30, 45, 90) if span / s <= 10), 90)
    if span > 0:
        ax.set_xticks(np.arange(math.ceil(lo / step) * step, hi + 1e-9, step))
    ax.grid(True, lw=0.4, alpha=0.6)
    ax.axhline(0.0, color="0.3", lw=0.6)


def _legend_title(aos, picks) -> str:
    title = "sideslip β [deg]"
    if picks.size < aos.size:
        title += f"\n({picks.size} of {aos.size} shown)"
    return title + "\ndashed: β < 0"


def _database_figure(db, series, ylabels, heading, max_lines) -> Figure:
    aoa = np.asarray(db.aoa_deg, dtype=float)
    aos = np.asarray(db.aos_deg, dtype=float)
    picks = select_sideslip_lines(aos, max_lines)
    fig = _new_figure((8.0, 6.5))
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
    fig.legend(handles, labels, loc="outside right center", title=_legend_title(aos, picks), fontsize=8,
               title_fontsize=8)
    fig.suptitle(f"{heading}\n{database_title(getattr(db, 'metadata', {}) or {})}", fontsize=10)
    return fig


def make_force_coefficient_figure(db, max_lines: int = MAX_SIDESLIP_LINES) -> Figure:
    """C_D, C_L and C_Y against angle of attack, one line per sideslip angle.

    Parameters
    ----------
    db : AeroDatabase
        Anything with ``aoa_deg`` (na,), ``aos_deg`` (nb,) [deg], ``CD``, ``CL``, ``CY`` (na, nb)
        and ``metadata`` (dict, see :mod:`adbsat_ros.database.build`).
    max_lines : int
        Most sideslip lines per panel (:func:`select_sideslip_lines`).
    """
    return _database_figure(
        db,
        (db.CD, db.CL, db.CY),
        ("drag $C_D$", "lift $C_L$", "side force $C_Y$"),
        "Force coefficients (wind axes)",
        max_lines,
    )


def make_moment_coefficient_figure(db, max_lines: int = MAX_SIDESLIP_LINES) -> Figure:
    """The three components of Cm_B against angle of attack, one line per sideslip angle.

    Cm_B is the moment coefficient in ADBSat's body frame B (x_B = x_G, y_B = -y_G, z_B = -z_G)
    about the database's reference moment point, normalised by A_ref L_ref.
    """
    cm = np.asarray(db.Cm_B, dtype=float)
    if cm.ndim != 3 or cm.shape[-1] != 3:
        raise ValueError(f"Cm_B: expected shape (na, nb, 3), got {cm.shape}")
    point = _meta(getattr(db, "metadata", {}) or {}, "reference", "moment_point")
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
    """Write the coefficient plots of a database as PNGs.

    Writes ``{prefix}database_coefficients.png`` (C_D, C_L, C_Y) and
    ``{prefix}database_moments.png`` (Cm_B x, y, z) into ``out_dir`` (created if needed).

    Returns
    -------
    list of Path
        The files written.
    """
    out_dir = Path(out_dir)
    return [
        _save(make_force_coefficient_figure(db, max_lines), out_dir / f"{prefix}database_coefficients.png"),
        _save(make_moment_coefficient_figure(db, max_lines), out_dir / f"{prefix}database_moments.png"),
    ]


# =============================================================================== panel pressure
def _resolve_lighting(lighting, mesh, u) -> PanelLighting:
    if lighting is None:
        return PanelLighting.all_lit(mesh.n_panels)
    if isinstance(lighting, PanelLighting):
        result = lighting
    elif hasattr(lighting, "lighting"):  # a Shader
        result = lighting.lighting(u)
    else:
        raise TypeError(f"lighting must be a PanelLighting, a Shader or None, got {type(lighting).__name__}")
    if np.shape(result.lit_fraction) != (mesh.n_panels,):
        raise ValueError(
            f"lighting has {np.size(result.lit_fraction)} panels, the mesh has {mesh.n_panels}"
        )
    return result


def panel_colours(cp, cos_delta, lit_fraction, cmap=PRESSURE_CMAP):
    """Face colours of the pressure picture and the colour scale.

    Panels fully reached by the flow (lit fraction 1) take the colour of their c_p on a scale
    from the smallest to the largest c_p among them; those facing away from the flow
    (cos delta < 0) are mixed with white. Panels with lit fraction < 1 are grey: dark if fully
    shaded, light if partly.

    Parameters
    ----------
    cp, cos_delta, lit_fraction : ndarray, shape (N,)
        Per-panel pressure coefficient, incidence cosine and lit fraction.
    cmap : str or Colormap

    Returns
    -------
    colours : ndarray, shape (N, 4)
        RGBA per panel.
    norm : matplotlib.colors.Normalize
        The c_p scale (vmin, vmax = min, max c_p of the lit panels).
    groups : dict of str to ndarray of bool
        ``lit``, ``back`` (lit and facing away), ``shaded`` (lit fraction < 1),
        ``fully_shaded`` (lit fraction 0), ``partly_shaded``.
    """
    from matplotlib import colormaps

    cmap = colormaps[cmap] if isinstance(cmap, str) else cmap
    cp = np.asarray(cp, dtype=float)
    f = np.asarray(lit_fraction, dtype=float)
    shaded = f < 1.0
    lit = ~shaded
    back = lit & (np.asarray(cos_delta, dtype=float) < 0.0)
    if lit.any():
        lo, hi = float(cp[lit].min()), float(cp[lit].max())
    else:
        lo, hi = 0.0, 1.0
    norm = Normalize(lo, hi) if hi > lo else Normalize(lo - 0.5, hi + 0.5)
    colours = cmap(norm(cp))
    colours[back, :3] = (1.0 - BACK_FACE_WHITE) * colours[back, :3] + BACK_FACE_WHITE
    fully = f <= 0.0
    colours[fully] = SHADED_COLOUR
    colours[shaded & ~fully] = PARTLY_SHADED_COLOUR
    groups = {
        "lit": lit,
        "back": back,
        "shaded": shaded,
        "fully_shaded": fully,
        "partly_shaded": shaded & ~fully,
    }
    return colours, norm, groups


def default_view(u_G, normals=None, areas=None, shaded=None) -> tuple[float, float]:
    """Camera elevation and azimuth [deg] for the pressure picture.

    The camera looks roughly along the flow from upstream (position -u), turned by ``VIEW_TURN_DEG``
    towards the mean normal of the shaded panels if there are any (so the shadows face the
    camera), otherwise towards +z_G and -y_G ("from upstream, the side and above").
    """
    u = np.asarray(u_G, dtype=float)
    u = u / np.linalg.norm(u)
    turn = np.array([0.0, -0.6, 0.8])
    if shaded is not None and np.any(shaded):
        mean_normal = (normals[shaded] * areas[shaded, None]).sum(axis=0)
        if np.linalg.norm(mean_normal - (mean_normal @ u) * u) > 1e-9:
            turn = mean_normal
    turn = turn - (turn @ u) * u
    if np.linalg.norm(turn) < 1e-9:  # flow along the preferred turn: any perpendicular
        turn = np.cross(u, [1.0, 0.0, 0.0] if abs(u[0]) < 0.9 else [0.0, 1.0, 0.0])
    turn /= np.linalg.norm(turn)
    camera = -u + math.tan(math.radians(VIEW_TURN_DEG)) * turn
    camera /= np.linalg.norm(camera)
    elev = math.degrees(math.asin(max(-1.0, min(1.0, camera[2]))))
    elev = max(-MAX_VIEW_ELEVATION_DEG, min(MAX_VIEW_ELEVATION_DEG, elev))  # steeper views look confusing
    azim = math.degrees(math.atan2(camera[1], camera[0]))
    return elev, azim


def make_panel_pressure_figure(
    method, flow, aoa_deg: float, aos_deg: float, lighting=None, *, view=None, title=None
) -> Figure:
    """A 3-D picture of the mesh coloured by per-panel pressure coefficient at one attitude.

    Parameters
    ----------
    method : PanelMethod
        Mesh, model and materials.
    flow : FreeStream
    aoa_deg, aos_deg : float
        Angle of attack and sideslip [deg] (frames module).
    lighting : PanelLighting or Shader or None
        Shading for this attitude, or a shader to compute it with; None: nothing shaded.
    view : (elev, azim) in degrees, optional
        Camera; default :func:`default_view`.
    title : str, optional
        First title line (default: mesh, model, speed ratio, attitude).

    Returns
    -------
    Figure
        One 3-D axes (``fig.axes[0]``) whose first collection is the panels' Poly3DCollection;
        that collection carries the c_p norm and colour map of the colour bar. The legend names
        the number of panels with lit fraction < 1 and of back faces.
    """
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    aoa_deg, aos_deg = float(aoa_deg), float(aos_deg)
    if not (math.isfinite(aoa_deg) and math.isfinite(aos_deg)):
        raise ValueError(f"aoa_deg and aos_deg must be finite, got {aoa_deg!r}, {aos_deg!r}")
    mesh = method.mesh
    aoa, aos = math.radians(aoa_deg), math.radians(aos_deg)
    u = frames.flow_direction(aoa, aos)
    light = _resolve_lighting(lighting, mesh, u)
    result = method.coefficients(flow, aoa, aos, lighting=light)
    colours, norm, groups = panel_colours(result.cp, result.cos_delta, light.lit_fraction)

    fig = _new_figure((8.0, 6.0))
    ax = fig.add_subplot(projection="3d")
    edge = colours.copy()
    edge[:, :3] *= 0.85  # faint mesh lines; also hides anti-aliasing seams between triangles
    panels = Poly3DCollection(mesh.vertices, facecolors=colours, edgecolors=edge, linewidths=0.25)
    panels.set_cmap(PRESSURE_CMAP)
    panels.set_norm(norm)
    ax.add_collection3d(panels)

    # The flow arrow ends just upstream of the mesh's bounding sphere, pointing at its centre.
    lo, hi = mesh.bounds
    centre = 0.5 * (lo + hi)
    radius = 0.5 * float(np.linalg.norm(hi - lo)) or 1.0
    arrow_len = 0.6 * radius
    tip = centre - u * 0.75 * radius
    start = tip - u * arrow_len
    ax.quiver(*start, *(u * arrow_len), color="crimson", lw=2.5, arrow_length_ratio=0.3)
    ax.text(*(start - 0.08 * radius * u), "flow", color="crimson", fontsize=9, ha="center")
    # Equal scaling: a box around the mesh and the arrow, with the aspect of the data.
    pts = np.vstack([lo, hi, start, tip])
    pmin, pmax = pts.min(axis=0), pts.max(axis=0)
    pad = 0.04 * float(np.max(pmax - pmin))
    pmin, pmax = pmin - pad, pmax + pad
    ax.set_xlim(pmin[0], pmax[0])
    ax.set_ylim(pmin[1], pmax[1])
    ax.set_zlim(pmin[2], pmax[2])
    ax.set_box_aspect(tuple(pmax - pmin), zoom=1.1)
    ax.set_xlabel("$x_G$ [m]")
    ax.set_ylabel("$y_G$ [m]")
    ax.set_zlabel("$z_G$ [m]")
    ax.tick_params(labelsize=7)
    elev, azim = view if view is not None else default_view(u, mesh.normals, mesh.areas, groups["shaded"])
    ax.view_init(elev=elev, azim=azim)

    n_shaded = int(groups["shaded"].sum())
    handles = [
        Patch(
            facecolor=SHADED_COLOUR,
            label=f"shaded from the flow (lit fraction < 1): {n_shaded} panels\n"
            f"  dark: {int(groups['fully_shaded'].sum())} fully, "
            f"light: {int(groups['partly_shaded'].sum())} partly",
        ),
        Patch(
            facecolor=(1 - BACK_FACE_WHITE) * np.array(to_rgba("tab:purple")[:3]) + BACK_FACE_WHITE,
            label=f"pale: back faces (facing away from the flow): {int(groups['back'].sum())} panels",
        ),
        Line2D([], [], color="crimson", lw=2.5, label="gas flow direction"),
    ]
    fig.legend(handles=handles, loc="outside lower center", ncols=2, fontsize=8)
    cbar = fig.colorbar(panels, ax=ax, shrink=0.65, pad=0.08)
    cbar.set_label("pressure coefficient $c_p$ (panels reached by the flow)")
    if title is None:
        title = f"{Path(str(mesh.source)).name}, {method.model}, speed ratio s = {flow.speed_ratio:.2f}"
        if lighting is not None:
            title += f", shading: {getattr(lighting, 'mode', 'given')}"
    fig.suptitle(
        f"{title}\nα = {aoa_deg:g}°, β = {aos_deg:g}°: "
        f"C_D = {result.drag:.3f}, projected area {result.area_projected:.3f} m²",
        fontsize=10,
    )
    return fig


def plot_panel_pressure(method, flow, aoa_deg, aos_deg, lighting, out_path, **options) -> Path:
    """Write :func:`make_panel_pressure_figure` to ``out_path`` (PNG); returns the path."""
    return _save(make_panel_pressure_figure(method, flow, aoa_deg, aos_deg, lighting, **options), out_path)


def legend_panel_counts(fig: Figure) -> dict:
    """The panel counts stated in a pressure picture's legend (``shaded``, ``back``)."""
    text = "\n".join(t.get_text() for legend in fig.legends for t in legend.get_texts())
    out = {}
    for key, pattern in (("shaded", r"lit fraction < 1\): (\d+) panels"), ("back", r"back faces.*?: (\d+) panels")):
        match = re.search(pattern, text)
        if match:
            out[key] = int(match.group(1))
    return out


# =============================================================================== time series
TIME_SERIES_KEYS = {"force": 2, "torque": 2, "density": 1, "drag_coefficient": 1}


def _check_runs(time_s, runs) -> tuple[np.ndarray, dict]:
    t = np.asarray(time_s, dtype=float)
    if t.ndim != 1 or t.size == 0:
        raise ValueError(f"time_s must be a non-empty 1-D array, got shape {t.shape}")
    if not runs:
        raise ValueError("runs is empty: give at least one run (label -> data)")
    checked = {}
    for label, data in runs.items():
        entry = {}
        for key, ndim in TIME_SERIES_KEYS.items():
            if key not in data:
                raise ValueError(f"run {label!r}: missing {key!r}")
            value = np.asarray(data[key], dtype=float)
            want = (t.size, 3) if ndim == 2 else (t.size,)
            if value.shape != want:
                raise ValueError(f"run {label!r}: {key!r} has shape {value.shape}, expected {want}")
            entry[key] = value
        checked[str(label)] = entry
    return t, checked


def _time_axis(t: np.ndarray):
    span = float(np.nanmax(t) - np.nanmin(t)) if np.isfinite(t).any() else 0.0
    if span > 3 * 3600:
        return t / 3600.0, "time since first message [h]"
    if span > 600:
        return t / 60.0, "time since first message [min]"
    return t, "time since first message [s]"


def _run_style(values: np.ndarray) -> dict:
    """Line style of one series: a marker only on isolated samples (NaN on both sides), which
    a line alone would not show."""
    ok = np.isfinite(values)
    before = np.concatenate([[False], ok[:-1]])
    after = np.concatenate([ok[1:], [False]])
    isolated = ok & ~before & ~after
    return {"lw": 1.1, "marker": ".", "ms": 5, "markevery": isolated if isolated.any() else []}


def make_time_series_figures(time_s, runs) -> dict:
    """Time-series figures of one or more runs (e.g. models compared on one rosbag).

    Parameters
    ----------
    time_s : array_like, shape (N,)
        Seconds since the first message.
    runs : dict of str to dict
        Label -> ``{'force': (N, 3) [N] body frame, 'torque': (N, 3) [N m] body frame,
        'density': (N,) [kg/m^3], 'drag_coefficient': (N,)}``; NaN where a run has no sample.

    Returns
    -------
    dict of str to Figure
        ``force``, ``torque`` (three stacked panels x, y, z), ``density`` (log y) and
        ``drag_coefficient``; one line per run in every panel.
    """
    t, runs = _check_runs(time_s, runs)
    t_plot, t_label = _time_axis(t)
    several = len(runs) > 1
    figures = {}
    for key, quantity, unit in (("force", "force", "N"), ("torque", "torque", "N m")):
        fig = _new_figure()
        axes = fig.subplots(3, 1, sharex=True)
        for i, (ax, comp) in enumerate(zip(axes, "xyz")):
            for label, data in runs.items():
                ax.plot(t_plot, data[key][:, i], label=label, **_run_style(data[key][:, i]))
            ax.set_ylabel(f"{comp} [{unit}]")
            ax.grid(True, lw=0.4, alpha=0.6)
            ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 4))
        axes[-1].set_xlabel(t_label)
        fig.suptitle(f"Aerodynamic {quantity}, body frame", fontsize=10)
        if several:
            fig.legend(*axes[0].get_legend_handles_labels(), loc="outside right center", fontsize=8, title="run")
        figures[key] = fig
    for key, ylabel, heading in (
        ("density", "density [kg/m³]", "Free-stream mass density"),
        ("drag_coefficient", "drag coefficient $C_D$", "Drag coefficient"),
    ):
        fig = _new_figure()
        ax = fig.add_subplot()
        positive = False
        for label, data in runs.items():
            values = data[key]
            positive |= bool(np.any(values > 0))
            ax.plot(t_plot, values, label=label, **_run_style(values))
        if key == "density" and positive:
            ax.set_yscale("log")
        ax.set_xlabel(t_label)
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", lw=0.4, alpha=0.6)
        ax.set_title(heading, fontsize=10)
        if several:
            ax.legend(fontsize=8, title="run")
        figures[key] = fig
    return figures


def plot_time_series(time_s, runs, out_dir, prefix: str = "") -> list[Path]:
    """Write :func:`make_time_series_figures` as ``{prefix}force.png``, ``{prefix}torque.png``,
    ``{prefix}density.png`` and ``{prefix}drag_coefficient.png`` in ``out_dir``; returns the paths."""
    out_dir = Path(out_dir)
    return [_save(fig, out_dir / f"{prefix}{name}.png") for name, fig in make_time_series_figures(time_s, runs).items()]
