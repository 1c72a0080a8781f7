"""The mesh coloured by panel pressure coefficient at one attitude [deg], with the flow arrow;
drawn in the mesh frame G [m] (:mod:`adbsat_ros.geometry.frames`).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from matplotlib import colormaps
from matplotlib.colors import Normalize, to_rgba
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from matplotlib.ticker import MaxNLocator
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

from adbsat_ros.geometry import frames
from adbsat_ros.plotting.figures import new_figure, save_png

#: Colour map of the pressure coefficient.
PRESSURE_CMAP = "viridis"
#: Face colours of panels fully and partly shaded from the flow.
SHADED_COLOUR = (0.45, 0.45, 0.45, 1.0)
PARTLY_SHADED_COLOUR = (0.72, 0.72, 0.72, 1.0)
#: Back faces (facing away from the flow) are drawn in their c_p colour mixed with this much white.
BACK_FACE_WHITE = 0.55
#: The pressure picture's camera is turned this far [deg] from looking straight down the flow,
VIEW_TURN_DEG = 35.0
#: and kept within this elevation [deg] above or below the x_G-y_G plane,
MAX_VIEW_ELEVATION_DEG = 55.0
#: and at least this far [deg] from it, and this far in azimuth from every axis, so that the box is
#: not seen edge-on nor an axis end-on (its ticks stacked).
MIN_VIEW_ELEVATION_DEG = 20.0
MIN_VIEW_AZIMUTH_DEG = 25.0
#: Each side of the drawn box is at least this fraction of its longest (a flat body is not drawn
#: in a flat box); the axes keep the data's aspect.
MIN_BOX_FRACTION = 0.4


def panel_colours(cp, cos_delta, lit_fraction, cmap=PRESSURE_CMAP):
    """Face colours (N, 4), the c_p scale and the panel groups (boolean masks) of the picture.

    Fully lit panels coloured by c_p (mixed with white if cos delta < 0), shaded ones grey.
    """
    cmap = colormaps[cmap] if isinstance(cmap, str) else cmap
    cp = np.asarray(cp, dtype=float)
    f = np.asarray(lit_fraction, dtype=float)
    shaded = f < 1.0
    lit = ~shaded
    back = lit & (np.asarray(cos_delta, dtype=float) < 0.0)
    lo, hi = (float(cp[lit].min()), float(cp[lit].max())) if lit.any() else (0.0, 1.0)
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
    """Camera (elevation, azimuth) [deg]: upstream of ``u_G``, turned by :data:`VIEW_TURN_DEG`
    towards the shaded panels (else +z_G, -y_G), within :data:`MAX_VIEW_ELEVATION_DEG`.
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
    elev = math.copysign(min(max(abs(elev), MIN_VIEW_ELEVATION_DEG), MAX_VIEW_ELEVATION_DEG), elev)
    azim = math.degrees(math.atan2(camera[1], camera[0]))
    off = azim - 90.0 * round(azim / 90.0)
    azim += math.copysign(max(abs(off), MIN_VIEW_AZIMUTH_DEG), off) - off
    return elev, azim


def make_panel_pressure_figure(
    model, flow, aoa_deg: float, aos_deg: float, *, view=None, title=None, result=None, mesh=None
) -> Figure:
    """A 3-D picture of ``model``'s mesh coloured by panel pressure coefficient at one attitude.

    ``aoa_deg``, ``aos_deg`` [deg]; ``view``: (elev, azim) [deg]; ``result``: coefficients already
    computed (default ``model.evaluate``); ``mesh``: the panels drawn (default ``model.mesh``).
    The legend states the shaded and back-face panel counts.
    """
    aoa_deg, aos_deg = float(aoa_deg), float(aos_deg)
    if not (math.isfinite(aoa_deg) and math.isfinite(aos_deg)):
        raise ValueError(f"aoa_deg and aos_deg must be finite, got {aoa_deg!r}, {aos_deg!r}")
    mesh = model.mesh if mesh is None else mesh
    aoa, aos = math.radians(aoa_deg), math.radians(aos_deg)
    u = frames.flow_direction(aoa, aos)
    shading = None
    if result is None:
        result = model.evaluate(flow, angles=(aoa, aos))
        shading = model.setup.shading.mode
    colours, norm, groups = panel_colours(result.cp, result.cos_delta, result.lit_fraction)

    fig = new_figure((8.0, 6.0))
    ax = fig.add_subplot(projection="3d")
    edge = colours.copy()
    edge[:, :3] *= 0.85  # faint mesh lines; also hides anti-aliasing seams between triangles
    panels = Poly3DCollection(mesh.vertices, facecolors=colours, edgecolors=edge, linewidths=0.25)
    panels.set_cmap(PRESSURE_CMAP)
    panels.set_norm(norm)
    ax.add_collection3d(panels)

    # The flow arrow ends at the mesh's box, pointing at its centre, from outside it.
    lo, hi = mesh.bounds
    centre = 0.5 * (lo + hi)
    half = 0.5 * (hi - lo)
    radius = float(np.linalg.norm(half)) or 1.0
    tip = centre - u * (float(np.abs(u) @ half) + 0.05 * radius)
    start = tip - u * 0.45 * radius
    ax.quiver(*start, *(tip - start), color="crimson", lw=2.5, arrow_length_ratio=0.3)
    ax.text(*(start - 0.08 * radius * u), "flow", color="crimson", fontsize=9, ha="center")
    # Equal scaling: a box around the mesh and the arrow, no side shorter than MIN_BOX_FRACTION
    # of the longest, with the aspect of the data.
    pts = np.vstack([lo, hi, start, tip])
    mid, size = 0.5 * (pts.min(axis=0) + pts.max(axis=0)), np.ptp(pts, axis=0)
    size = np.maximum(size, MIN_BOX_FRACTION * size.max()) * 1.06
    for axis, low, high in zip("xyz", mid - size / 2, mid + size / 2):
        getattr(ax, f"set_{axis}lim")(low, high)
        getattr(ax, f"set_{axis}label")(f"${axis}_G$ [m]", fontsize=8, labelpad=-2)
        getattr(ax, f"{axis}axis").set_major_locator(MaxNLocator(4))
    ax.set_box_aspect(tuple(size), zoom=0.95)
    ax.tick_params(labelsize=7, pad=0)
    elev, azim = (
        view if view is not None else default_view(u, mesh.normals, mesh.areas, groups["shaded"])
    )
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
            label="pale: back faces (facing away from the flow): "
            f"{int(groups['back'].sum())} panels",
        ),
        Line2D([], [], color="crimson", lw=2.5, label="gas flow direction"),
    ]
    fig.legend(handles=handles, loc="outside lower center", ncols=2, fontsize=8)
    cbar = fig.colorbar(panels, ax=ax, shrink=0.65, pad=0.08)
    cbar.set_label("pressure coefficient $c_p$ (panels reached by the flow)")
    if title is None:
        title = (
            f"{Path(str(mesh.source)).name}, {model.method.model}, speed ratio s = "
            f"{flow.speed_ratio:.2f}"
        )
        if hasattr(result, "particles"):
            title += f", test particles: {result.particles:,}"
        elif shading not in (None, "none"):
            title += f", shading: {shading}"
    fig.suptitle(
        f"{title}\nα = {round(aoa_deg, 1) + 0.0:g}°, β = {round(aos_deg, 1) + 0.0:g}°: "
        f"C_D = {result.drag:.3f}, projected area {result.area_projected:.3f} m²",
        fontsize=10,
    )
    return fig


def plot_panel_pressure(model, flow, aoa_deg, aos_deg, out_path, **options) -> Path:
    """Write :func:`make_panel_pressure_figure` to ``out_path`` (PNG); the path."""
    return save_png(make_panel_pressure_figure(model, flow, aoa_deg, aos_deg, **options), out_path)
