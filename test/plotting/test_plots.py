"""Figures (adbsat_ros.plotting.coefficients) and the `adbsat-ros plot` command.

The figures are checked through their Figure objects (which lines, which numbers, which colour
scale) against quantities computed independently with the panel method and the shader, and
through the written PNGs (read back: right size, not blank).

Scene for the pressure picture ("cube + plate", as in test_shading): a 1 m cube centred at
x = +2 m in front of a 3 x 3 x 0.1 m plate at the origin; at aoa = 10 deg the cube throws a
shadow on the plate's front face.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from matplotlib.image import imread
from meshes import grid_box, write_obj

from adbsat_ros import FreeStream, PanelMethod
from adbsat_ros.cli import main
from adbsat_ros.cli.plot import default_angle
from adbsat_ros.database.build import build_database
from adbsat_ros.database.format import load_database
from adbsat_ros.geometry import frames
from adbsat_ros.geometry.example_satellite import combine
from adbsat_ros.geometry.loading import resolve_mesh
from adbsat_ros.physics.model import build_model
from adbsat_ros.physics.setup import Setup, ShadingPolicy
from adbsat_ros.plotting import coefficients, figures, panels, time_series
from adbsat_ros.shading.shader import make_shader

FLOW = FreeStream(7726.0, 934.0, mean_mass_amu=17.9)


def legend_panel_counts(fig) -> dict:
    """The ``shaded`` and ``back`` panel counts read back from a picture's legend."""
    text = "\n".join(t.get_text() for legend in fig.legends for t in legend.get_texts())
    out = {}
    for key, pattern in (
        ("shaded", r"lit fraction < 1\): (\d+) panels"),
        ("back", r"back faces.*?: (\d+) panels"),
    ):
        match = re.search(pattern, text)
        if match:
            out[key] = int(match.group(1))
    return out


def cube_plate():
    return combine(
        [
            grid_box((2.0, 0.0, 0.0), (1.0, 1.0, 1.0), (2, 2, 2)),
            grid_box((0.0, 0.0, 0.0), (0.1, 3.0, 3.0), (1, 12, 12)),
        ],
        source="cube+plate",
    )


def data_lines(ax):
    """The labelled lines of an axes (reference lines such as axhline carry '_' labels)."""
    return [line for line in ax.get_lines() if not line.get_label().startswith("_")]


def assert_png(path, size_in):
    """A readable PNG of the expected pixel size with non-uniform content."""
    image = imread(path)
    assert image.shape[:2] == (round(size_in[1] * figures.DPI), round(size_in[0] * figures.DPI))
    assert float(image[..., :3].var()) > 1e-3  # not blank
    assert path.stat().st_size < 400_000  # small enough to commit


# ------------------------------------------------------------------------------ databases
@pytest.fixture(scope="module")
def mesh_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("mesh") / "cube_plate.obj"
    write_obj(cube_plate(), path)
    return path


@pytest.fixture(scope="module")
def database_file(mesh_file, tmp_path_factory):
    mesh = resolve_mesh(str(mesh_file))
    db = build_database(
        PanelMethod(mesh, "sentman"),
        FLOW,
        np.arange(-30.0, 31.0, 10.0),
        np.arange(-90.0, 91.0, 15.0),  # 13 sideslips: more than the 7 lines drawn
        shading="raycast",
        workers=1,
        progress=False,
        mesh_spec=str(mesh_file),
    )
    path = tmp_path_factory.mktemp("db") / "cube_plate.npz"
    db.save(path)
    return path


def test_sideslip_line_selection():
    assert coefficients.select_sideslip_lines(np.arange(-30.0, 31.0, 10.0)).tolist() == list(
        range(7)
    )
    assert coefficients.select_sideslip_lines([5.0]).tolist() == [0]
    for grid in (
        np.arange(-90.0, 91.0, 15.0),
        np.arange(-80.0, 91.0, 10.0),
        np.arange(-90.0, 91.0, 1.0),
    ):
        picks = coefficients.select_sideslip_lines(grid, 7)
        assert picks.size == 7 and np.all(np.diff(picks) > 0)
        assert picks[0] == 0 and picks[-1] == grid.size - 1  # the ends
        assert 0.0 in grid[picks]  # zero sideslip whenever the grid has it
        gaps = np.diff(grid[picks])
        assert gaps.max() <= 2.0 * gaps.min()  # roughly even
    with pytest.raises(ValueError, match="max_lines"):
        coefficients.select_sideslip_lines(np.arange(10.0), 1)


def test_database_figures_draw_the_database(database_file):
    db = load_database(database_file)
    picks = coefficients.select_sideslip_lines(db.aos_deg)
    fig = coefficients.make_force_coefficient_figure(db)
    assert len(fig.legends) == 1 and "7 of 13 shown" in fig.legends[0].get_title().get_text()
    for ax, values in zip(fig.axes, (db.CD, db.CL, db.CY)):
        lines = data_lines(ax)
        assert len(lines) == picks.size
        for line, j in zip(lines, picks):  # each line is the column of its labelled sideslip
            assert float(line.get_label()) == db.aos_deg[j]
            np.testing.assert_array_equal(line.get_xdata(), db.aoa_deg)
            np.testing.assert_array_equal(line.get_ydata(), values[:, j])
            assert (line.get_linestyle() == "-") == (db.aos_deg[j] >= 0)  # dashed for beta < 0
    title = fig.get_suptitle()
    for word in ("cube_plate.obj", "sentman", f"s = {FLOW.speed_ratio:.2f}", "raycast"):
        assert word in title
    fig = coefficients.make_moment_coefficient_figure(db, max_lines=20)
    for i, ax in enumerate(fig.axes):
        lines = data_lines(ax)
        assert len(lines) == db.aos_deg.size
        np.testing.assert_array_equal(lines[3].get_ydata(), db.Cm_B[:, 3, i])


def test_plot_database_writes_pngs(database_file, tmp_path):
    paths = coefficients.plot_database(load_database(database_file), tmp_path / "out", prefix="x_")
    assert [p.name for p in paths] == ["x_database_coefficients.png", "x_database_moments.png"]
    for p in paths:
        assert_png(p, (8.0, 6.5))


# ------------------------------------------------------------------------------ pressure picture
@pytest.fixture(scope="module")
def scene():
    """The cube on a plate, its models shaded by ray casting and not shaded, and a shader."""
    mesh = cube_plate()
    shaded, plain = (
        build_model(Setup(shading=ShadingPolicy(mode, exact_offline=1)), mesh)
        for mode in ("raycast", "none")
    )
    return mesh, shaded, plain, make_shader(mesh)


@pytest.mark.parametrize("aoa_deg, aos_deg", [(10.0, 0.0), (0.0, 20.0)])
def test_pressure_picture_marks_shadows_and_scales_cp(scene, aoa_deg, aos_deg, tmp_path):
    mesh, model, plain, shader = scene
    u = frames.flow_direction(math.radians(aoa_deg), math.radians(aos_deg))
    lit_fraction = shader.lighting(u).lit_fraction
    angles = (math.radians(aoa_deg), math.radians(aos_deg))
    result = plain.evaluate(FLOW, angles=angles)  # unshaded cp
    shaded = lit_fraction < 1.0
    assert 0 < shaded.sum() < mesh.n_panels  # the cube shades part of the plate
    fig = panels.make_panel_pressure_figure(model, FLOW, aoa_deg, aos_deg)
    assert "shading: raycast" in fig._suptitle.get_text()
    counts = legend_panel_counts(fig)
    assert counts["shaded"] == int(shaded.sum())
    assert counts["back"] == int(((result.cos_delta < 0) & ~shaded).sum())
    legend = "\n".join(t.get_text() for t in fig.legends[0].get_texts())
    assert f"{int((lit_fraction <= 0).sum())} fully" in legend
    fig.canvas.draw()
    collection = fig.axes[0].collections[0]
    assert len(collection.get_paths()) == mesh.n_panels
    assert collection.norm.vmin == pytest.approx(result.cp[~shaded].min(), rel=1e-12)
    assert collection.norm.vmax == pytest.approx(result.cp[~shaded].max(), rel=1e-12)
    unshaded = panels.make_panel_pressure_figure(plain, FLOW, aoa_deg, aos_deg)
    assert legend_panel_counts(unshaded)["shaded"] == 0
    assert "shading" not in unshaded._suptitle.get_text()
    norm = unshaded.axes[0].collections[0].norm
    assert (norm.vmin, norm.vmax) == (result.cp.min(), result.cp.max())
    assert_png(
        panels.plot_panel_pressure(model, FLOW, aoa_deg, aos_deg, tmp_path / "p.png"),
        (8.0, 6.0),
    )


def test_panel_colours():
    cp = np.array([2.0, 1.0, 0.1, 5.0, 0.5, -0.3])
    cos_delta = np.array([1.0, 0.5, -0.5, 1.0, 0.7, 0.2])
    lit = np.array([1.0, 1.0, 1.0, 0.0, 0.4, 1.0])
    colours, norm, groups = panels.panel_colours(cp, cos_delta, lit)
    assert (norm.vmin, norm.vmax) == (-0.3, 2.0)  # lit panels only: the shaded 5.0 is left out
    assert groups["shaded"].tolist() == [False, False, False, True, True, False]
    assert groups["back"].tolist() == [False, False, True, False, False, False]
    np.testing.assert_array_equal(colours[3], panels.SHADED_COLOUR)
    np.testing.assert_array_equal(colours[4], panels.PARTLY_SHADED_COLOUR)
    plain, _, _ = panels.panel_colours(cp, np.abs(cos_delta), lit)
    assert np.all(colours[2, :3] > plain[2, :3])  # back face paler than the same cp facing the flow
    np.testing.assert_array_equal(colours[[0, 1, 5]], plain[[0, 1, 5]])


def test_default_view_looks_from_upstream_at_the_shadows(scene):
    mesh, _, _, shader = scene
    for aoa, aos in ((10.0, 0.0), (0.0, 20.0), (-60.0, 45.0), (180.0, 0.0), (90.0, 0.0)):
        u = frames.flow_direction(math.radians(aoa), math.radians(aos))
        shaded = shader.lighting(u).lit_fraction < 1
        elev, azim = panels.default_view(u, mesh.normals, mesh.areas, shaded)
        e, a = math.radians(elev), math.radians(azim)
        camera = np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])
        assert panels.MIN_VIEW_ELEVATION_DEG <= abs(elev) <= panels.MAX_VIEW_ELEVATION_DEG + 1e-9
        assert abs(azim - 90 * round(azim / 90)) >= panels.MIN_VIEW_AZIMUTH_DEG - 1e-9  # no axis
        assert camera @ -u > 0.5  # upstream, within ~60 deg of the flow axis
        if shaded.any():  # the shaded panels face the camera on average
            assert (mesh.normals[shaded] * mesh.areas[shaded, None]).sum(axis=0) @ camera > 0


def test_pressure_picture_rejects_non_finite_angles(scene):
    _, model, _, _ = scene
    with pytest.raises(ValueError, match="finite"):
        panels.make_panel_pressure_figure(model, FLOW, float("nan"), 0.0)


# ------------------------------------------------------------------------------ time series
def synthetic_runs(n=300):
    t = np.linspace(0.0, 5400.0, n)  # 90 minutes: the time axis is in minutes
    orbit = 2 * np.pi * t / 5400.0
    runs = {}
    for label, scale in (("sentman", 1.0), ("dria", 0.93), ("cll", 1.05)):
        rho = 3e-12 * np.exp(0.8 * np.cos(orbit))
        force = -scale * np.column_stack(
            [1e-6 * rho / 3e-12, 1e-8 * np.sin(orbit), 2e-8 * np.cos(orbit)]
        )
        runs[label] = {
            "force": force,
            "torque": 0.1 * force[:, [1, 2, 0]],
            "density": rho,
            "drag_coefficient": scale * (2.2 + 0.05 * np.sin(3 * orbit)),
        }
    if n >= 200:
        runs["cll"]["density"][100:140] = np.nan  # a gap: no samples
        runs["cll"]["force"][100:140] = np.nan
        runs["cll"]["density"][120] = runs["dria"]["density"][120]  # one isolated sample in the gap
    return t, runs


def test_time_series_figures(tmp_path):
    t, runs = synthetic_runs()
    made = time_series.make_time_series_figures(t, runs)
    assert list(made) == ["force", "torque", "density", "drag_coefficient"]
    for key in ("force", "torque"):
        axes = made[key].axes
        assert len(axes) == 3
        for i, ax in enumerate(axes):
            lines = data_lines(ax)
            assert [line.get_label() for line in lines] == list(runs)
            np.testing.assert_array_equal(lines[0].get_ydata(), runs["sentman"][key][:, i])
        assert "[min]" in axes[-1].get_xlabel()
        np.testing.assert_allclose(data_lines(axes[0])[0].get_xdata(), t / 60.0)
    # the y and z forces (at most 3 % of x) are drawn at the x force's scale, about their values,
    # and said so
    force_axes = made["force"].axes
    spans = [np.ptp(ax.get_ylim()) for ax in force_axes]
    assert spans[1] == pytest.approx(spans[0], rel=1e-12) and spans[2] == pytest.approx(spans[0])
    for i in (1, 2):
        low, high = force_axes[i].get_ylim()
        values = runs["cll"]["force"][:, i]
        assert low < np.nanmin(values) and np.nanmax(values) < high
    assert [len(ax.texts) for ax in force_axes] == [0, 1, 1]
    assert "below 5% of the largest component" in force_axes[1].texts[0].get_text()
    assert [len(ax.texts) for ax in made["torque"].axes] == [1, 1, 0]
    # a density within a factor e^1.6 on a linear axis; spanning more than 10, a log one
    ax = made["density"].axes[0]
    assert ax.get_yscale() == "linear" and len(data_lines(ax)) == len(runs)
    wide = {k: dict(v, density=v["density"] ** 2 / 3e-12) for k, v in runs.items()}
    assert time_series.make_time_series_figures(t, wide)["density"].axes[0].get_yscale() == "log"
    gap_line = data_lines(ax)[2]
    assert np.isnan(gap_line.get_ydata()[110])  # the gap is kept, not filled
    assert np.flatnonzero(gap_line.get_markevery()).tolist() == [120]  # the lone sample is marked
    assert list(data_lines(ax)[0].get_markevery()) == []  # continuous runs carry no markers
    assert len(data_lines(made["drag_coefficient"].axes[0])) == len(runs)

    paths = time_series.plot_time_series(t, runs, tmp_path, prefix="bag_")
    assert [p.name for p in paths] == [
        "bag_force.png",
        "bag_torque.png",
        "bag_density.png",
        "bag_drag_coefficient.png",
    ]
    for p in paths:
        assert_png(p, figures.FIGSIZE)
    # one run: no legend needed, still one line per panel
    single = time_series.make_time_series_figures(
        t[:10], {"only": {k: v[:10] for k, v in runs["dria"].items()}}
    )
    assert all(len(data_lines(ax)) == 1 for ax in single["force"].axes)
    assert "[s]" in single["force"].axes[-1].get_xlabel()


def test_time_series_input_errors():
    t, runs = synthetic_runs(20)
    bad = {"a": dict(runs["sentman"], density=np.ones(19))}
    with pytest.raises(ValueError, match=r"run 'a': 'density' has shape \(19,\), expected \(20,\)"):
        time_series.make_time_series_figures(t, bad)
    missing = {"b": {k: v for k, v in runs["sentman"].items() if k != "torque"}}
    with pytest.raises(ValueError, match="run 'b': missing 'torque'"):
        time_series.make_time_series_figures(t, missing)
    with pytest.raises(ValueError, match="runs is empty"):
        time_series.make_time_series_figures(t, {})


# ------------------------------------------------------------------------------ command line
def run_plot(capsys, *argv):
    code = main(["plot", *map(str, argv)])
    out, err = capsys.readouterr()
    return code, out, err


def test_cli_writes_all_figures(database_file, tmp_path, capsys):
    code, out, err = run_plot(
        capsys, database_file, "--out-dir", tmp_path / "figs", "--aoa", "10", "--aos", "0"
    )
    assert code == 0, err
    names = ("database_coefficients.png", "database_moments.png", "panel_pressure.png")
    paths = [tmp_path / "figs" / name for name in names]
    assert out.split() == [str(p) for p in paths]
    for p, size in zip(paths, [(8.0, 6.5), (8.0, 6.5), (8.0, 6.0)]):
        assert_png(p, size)


def test_cli_default_output_folder_and_angles(database_file, tmp_path, capsys):
    copy = tmp_path / "mine.npz"
    copy.write_bytes(database_file.read_bytes())
    code, out, err = run_plot(capsys, copy, "--no-mesh")
    assert code == 0, err
    names = ("database_coefficients.png", "database_moments.png")
    assert out.split() == [str(tmp_path / "mine_plots" / n) for n in names]
    assert default_angle(np.array([-30.0, 0.0, 30.0])) == 0.0
    assert default_angle(np.array([10.0, 20.0])) == 10.0


def test_cli_errors(database_file, mesh_file, tmp_path, capsys):
    code, _, err = run_plot(capsys, tmp_path / "absent.npz")
    assert code == 2 and "no such file" in err and "absent.npz" in err

    junk = tmp_path / "junk.npz"
    junk.write_text("not a zip file")
    code, _, err = run_plot(capsys, junk)
    assert (
        code == 2 and "junk.npz" in err and "database" in err and len(err.strip().splitlines()) == 1
    )

    for option, value in (("--aoa", "ten"), ("--aos", "nan")):
        with pytest.raises(SystemExit) as exc:
            main(["plot", str(database_file), option, value])
        assert exc.value.code == 2
        assert re.search(
            rf"{option} must be a finite angle in degrees, got '{value}'", capsys.readouterr().err
        )
    code, _, err = run_plot(capsys, database_file, "--aos", "120")
    assert code == 2 and "--aos must be in [-90, 90]" in err


def test_cli_refuses_a_changed_mesh(tmp_path, capsys):
    mesh_path = tmp_path / "sat.obj"
    write_obj(cube_plate(), mesh_path)
    db = build_database(
        PanelMethod(resolve_mesh(str(mesh_path)), "newton"),
        FLOW,
        [0.0, 10.0],
        [0.0],
        shading="none",
        workers=1,
        progress=False,
        mesh_spec=str(mesh_path),
    )
    db.save(tmp_path / "sat.npz")
    write_obj(
        combine([grid_box((0.0, 0.0, 0.0), (1.0, 1.0, 1.0), (1, 1, 1))], source="other"), mesh_path
    )
    code, _, err = run_plot(capsys, tmp_path / "sat.npz", "--out-dir", tmp_path / "o")
    assert code == 2 and "changed since the database was built" in err and "--no-mesh" in err
    assert not (tmp_path / "o" / "panel_pressure.png").exists()
    code, out, err = run_plot(
        capsys, tmp_path / "sat.npz", "--out-dir", tmp_path / "o", "--no-mesh"
    )
    assert code == 0 and len(out.split()) == 2


def test_a_test_particle_database_draws_the_test_particles_pressures(tmp_path, capsys):
    """`plot` of a database made by test particles draws their per-panel pressures (every
    reflection) at the picture's attitude, from a run of the database's own settings."""
    from adbsat_ros.database.metadata import model_from_metadata

    mesh = resolve_mesh("intake-box")
    method = PanelMethod(mesh, "sentman")
    db = build_database(
        method,
        FLOW,
        [0, 10, 20],
        [0],
        solver="tpmc",
        particles=20_000,
        seed=3,
        mesh_spec="intake-box",
        workers=1,
        progress=False,
    )
    path = db.save(tmp_path / "tp.npz")
    rebuilt, flow = model_from_metadata(load_database(path).metadata)
    result = rebuilt.evaluate(flow, angles=(0.0, 0.0))
    assert result.particles == 20_000 and result.seed == 3
    fig = panels.make_panel_pressure_figure(rebuilt, flow, 0.0, 0.0)
    norm = fig.axes[0].collections[0].norm
    assert (norm.vmin, norm.vmax) == (result.cp.min(), result.cp.max())
    panel_cp = rebuilt.evaluate(flow, angles=(0.0, 0.0), solver="panel").cp
    assert not np.allclose(result.cp, panel_cp, atol=0.05)  # the intake's walls differ
    assert "test particles" in fig._suptitle.get_text()
    assert main(["plot", str(path), "--out-dir", str(tmp_path / "plots")]) == 0
    assert "panel_pressure.png" in capsys.readouterr().out


def test_pressure_picture_rounds_its_angles_and_fits_its_box(scene):
    _, model, _, _ = scene
    fig = panels.make_panel_pressure_figure(model, FLOW, 4.38739e-15, -2.93956)
    assert "α = 0°, β = -2.9°" in fig.get_suptitle()
    ax = fig.axes[0]
    spans = [np.ptp(limits) for limits in (ax.get_xlim(), ax.get_ylim(), ax.get_zlim())]
    assert min(spans) >= panels.MIN_BOX_FRACTION * max(spans) * (1 - 1e-9)
    lo, hi = model.mesh.bounds
    for (low, high), a, b in zip((ax.get_xlim(), ax.get_ylim(), ax.get_zlim()), lo, hi):
        assert low < a and b < high  # the whole mesh inside the box
    assert abs(ax.elev) >= panels.MIN_VIEW_ELEVATION_DEG
