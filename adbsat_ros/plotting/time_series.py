"""Force, torque [N, N m, body frame], density and C_D against time, one line per model; density
and drag with the space weather in force."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from adbsat_ros.plotting.figures import new_figure, save_figures

#: The series every run holds, with their number of dimensions: (N, 3) or (N,).
TIME_SERIES_KEYS = {"force": 2, "torque": 2, "density": 1, "drag_coefficient": 1}


def _check_runs(time_s, runs) -> tuple[np.ndarray, dict]:
    """The times and runs as float arrays, or ValueError naming the run and series at fault."""
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


def _time_axis(lines):
    """The factor from seconds to s, min or h (whichever suits the lines' span) and the label."""
    xs = [x for run in lines.values() for series in run.values() for x, _ in series]
    finite = [x[np.isfinite(x)] for x in xs]
    finite = [x for x in finite if x.size]
    span = float(max(x.max() for x in finite) - min(x.min() for x in finite)) if finite else 0.0
    if span > 3 * 3600:
        return 1 / 3600.0, "time since first message [h]"
    if span > 600:
        return 1 / 60.0, "time since first message [min]"
    return 1.0, "time since first message [s]"


def _run_style(values: np.ndarray) -> dict:
    """Line style of one series: a marker only on isolated samples (NaN on both sides)."""
    ok = np.isfinite(values)
    before = np.concatenate([[False], ok[:-1]])
    after = np.concatenate([ok[1:], [False]])
    isolated = ok & ~before & ~after
    return {"lw": 1.1, "marker": ".", "ms": 5, "markevery": isolated if isolated.any() else []}


#: A component whose largest magnitude is below this fraction of the largest component's is drawn
#: on that component's scale (and said so), not magnified to look like a signal.
SMALL_FRACTION = 0.05
#: A density axis is logarithmic only where the values span at least this ratio.
LOG_RATIO = 10.0


def _peak(series) -> float:
    """The largest finite magnitude of (t, values) lines (0 if none)."""
    finite = [np.abs(v[np.isfinite(v)]) for _, v in series]
    return max((float(v.max()) for v in finite if v.size), default=0.0)


def _share_small_components(axes, peaks) -> None:
    """Draw each component below :data:`SMALL_FRACTION` of the largest at the largest's scale:
    its panel spans as much as the largest's (if its own values span less), about its values."""
    largest = max(peaks)
    if not largest > 0.0:
        return
    low, high = axes[int(np.argmax(peaks))].get_ylim()
    for ax, peak in zip(axes, peaks):
        if peak < SMALL_FRACTION * largest:
            own = ax.get_ylim()
            if own[1] - own[0] < high - low:
                mid = 0.5 * (own[0] + own[1])
                ax.set_ylim(mid - 0.5 * (high - low), mid + 0.5 * (high - low))
            note = "zero to rounding" if peak < 1e-9 * largest else f"at most {peak:.2g}"
            ax.text(0.01, 0.95, f"{note}: below {SMALL_FRACTION:.0%} of the largest component, "
                    "drawn at its scale", transform=ax.transAxes, fontsize=7, va="top")  # fmt: skip


def _log_if_wide(ax, lines) -> None:
    """A log axis where the positive values span :data:`LOG_RATIO`, else linear with an offset."""
    values = np.concatenate([v[np.isfinite(v) & (v > 0)] for _, v in lines])
    if values.size and values.max() >= LOG_RATIO * values.min():
        ax.set_yscale("log")
    else:
        ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 4), useOffset=True)


def make_time_series_figures(time_s, runs) -> dict:
    """Figures ``force``, ``torque``, ``density`` and ``drag_coefficient`` of one or more runs.

    ``time_s`` (N,) [s] since the first message; ``runs``: label -> {'force': (N, 3) [N], 'torque':
    (N, 3) [N m], 'density': (N,) [kg/m^3], 'drag_coefficient': (N,)}, NaN where no sample.
    """
    t, runs = _check_runs(time_s, runs)
    lines = {}
    for label, data in runs.items():
        lines[label] = {
            key: [(t, data[key][:, i]) for i in range(3)] if ndim == 2 else [(t, data[key])]
            for key, ndim in TIME_SERIES_KEYS.items()
        }
    return make_line_figures(lines)


def make_line_figures(lines) -> dict:
    """The figures of :func:`make_time_series_figures` from (t, values) lines per series."""
    if not lines:
        raise ValueError("runs is empty: give at least one run (label -> data)")
    scale, t_label = _time_axis(lines)
    several = len(lines) > 1
    figures = {}
    for key, quantity, unit in (("force", "force", "N"), ("torque", "torque", "N m")):
        fig = new_figure()
        axes = fig.subplots(3, 1, sharex=True)
        for i, (ax, comp) in enumerate(zip(axes, "xyz")):
            for label, run in lines.items():
                t, values = run[key][i]
                ax.plot(t * scale, values, label=label, **_run_style(values))
            ax.set_ylabel(f"{comp} [{unit}]")
            ax.grid(True, lw=0.4, alpha=0.6)
            ax.ticklabel_format(axis="y", style="sci", scilimits=(-3, 4))
        _share_small_components(axes, [_peak(r[key][i] for r in lines.values()) for i in range(3)])
        axes[-1].set_xlabel(t_label)
        fig.suptitle(f"Aerodynamic {quantity}, body frame", fontsize=10)
        if several:
            fig.legend(
                *axes[0].get_legend_handles_labels(),
                loc="outside right center",
                fontsize=8,
                title="run",
            )
        figures[key] = fig
    for key, ylabel, heading in (
        ("density", "density [kg/m³]", "Free-stream mass density"),
        ("drag_coefficient", "drag coefficient $C_D$", "Drag coefficient"),
    ):
        fig = new_figure()
        ax = fig.add_subplot()
        for label, run in lines.items():
            ((t, values),) = run[key]
            ax.plot(t * scale, values, label=label, **_run_style(values))
        if key == "density":
            _log_if_wide(ax, [r[key][0] for r in lines.values()])
        ax.set_xlabel(t_label)
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", lw=0.4, alpha=0.6)
        ax.set_title(heading, fontsize=10)
        if several:
            ax.legend(fontsize=8, title="run")
        figures[key] = fig
    return figures


def make_space_weather_figure(lines):
    """The replay of a flight: density, drag [N], F10.7 and Ap against time, one line per model;
    ``lines``: label -> {'density', 'drag', 'f107', 'ap'}: [(t, values)]."""
    scale, t_label = _time_axis(lines)
    fig = new_figure()
    axes = fig.subplots(4, 1, sharex=True)
    rows = (("density", "density [kg/m³]"), ("drag", "drag [N]"), ("f107", "F10.7 [sfu]"),
            ("ap", "Ap"))  # fmt: skip
    for ax, (key, ylabel) in zip(axes, rows):
        for label, run in lines.items():
            ((t, values),) = run[key]
            ax.plot(t * scale, values, label=label, **_run_style(values))
        ax.set_ylabel(ylabel, fontsize=8)
        ax.grid(True, lw=0.4, alpha=0.6)
    _log_if_wide(axes[0], [r["density"][0] for r in lines.values()])
    axes[-1].set_xlabel(t_label)
    fig.suptitle("Density and drag with the space weather in force", fontsize=10)
    if len(lines) > 1:
        fig.legend(*axes[0].get_legend_handles_labels(), loc="outside right center", fontsize=8)
    return fig


def plot_time_series(time_s, runs, out_dir, prefix: str = "") -> list[Path]:
    """Write :func:`make_time_series_figures` as ``{prefix}force.png`` etc.; the paths."""
    return save_figures(make_time_series_figures(time_s, runs), out_dir, prefix)
