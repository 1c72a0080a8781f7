"""Matplotlib figures without a display (the Agg canvas): one resolution, saved as PNG."""

from __future__ import annotations

from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

#: Resolution of the written PNGs [dots per inch].
DPI = 100
#: Default size of line-plot figures [in].
FIGSIZE = (8.0, 5.0)


def new_figure(figsize=FIGSIZE) -> Figure:
    """A Figure of ``figsize`` [in] with constrained layout on its own Agg canvas (no pyplot)."""
    fig = Figure(figsize=figsize, dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def save_figures(figures, out_dir, prefix: str = "") -> list[Path]:
    """Write figures (name to Figure) as PNGs ``{prefix}{name}.png`` in ``out_dir``; the paths."""
    return [save_png(fig, Path(out_dir, f"{prefix}{name}.png")) for name, fig in figures.items()]


def save_png(fig: Figure, path) -> Path:
    """Write ``fig`` as a PNG at :data:`DPI` to ``path`` (folders created); returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=DPI, format="png")
    return path
