"""The axes beyond attitude and gas: the atmosphere's UTC, a species' number density, design
variants of the mesh, and test particles with their standard errors; each point checked
against the solver called directly with the inputs built here."""

from __future__ import annotations

import datetime as dt
import math

import numpy as np
import pytest
import xarray as xr

from adbsat_ros.database.build import attitude_seed
from adbsat_ros.environment.atmosphere import SpaceWeather
from adbsat_ros.environment.circular_orbit import flight_conditions_circular_orbit
from adbsat_ros.geometry.example_satellite import example_satellite
from adbsat_ros.geometry.loading import resolve_mesh
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.constants import species_mass_kg
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.physics.tpmc.method import TestParticleMethod
from adbsat_ros.sweep.engine import run_sweep
from adbsat_ros.sweep.spec import parse_spec

EPOCH = dt.datetime(2026, 3, 20, 6)


def swept(tmp_path, data, workers=1, name="s.zarr"):
    spec = parse_spec(data, "")
    run_sweep(spec, tmp_path / name, workers=workers)
    return spec, xr.open_zarr(tmp_path / name, consolidated=False).load()


def air(hours: float):
    """NRLMSISE-00's free stream at 300 km over (0, 0) at EPOCH + hours, F10.7 150, Ap 4."""
    conditions = flight_conditions_circular_orbit(
        EPOCH + dt.timedelta(hours=hours), 300e3, 0.0, 0.0, SpaceWeather(150.0, 150.0, 4.0)
    )
    return conditions.free_stream()


def test_a_time_axis_is_the_atmosphere_hours_after_the_epoch(tmp_path):
    data = {
        "mesh": "example",
        "shading": "none",
        "time": EPOCH.isoformat(),
        "fixed": {"altitude": 300},
        "axes": {"aoa": [0, 45], "time": "0:6:18"},
    }
    spec, ds = swept(tmp_path, data)
    expected = [np.datetime64(EPOCH + dt.timedelta(hours=h)) for h in (0, 6, 12, 18)]
    np.testing.assert_array_equal(ds["time"].values, np.array(expected, dtype="datetime64[ns]"))
    method = PanelMethod(example_satellite(), "sentman", shading="none")
    for k, hours in enumerate(spec.axes["time"]):
        flow = air(hours)
        assert ds["density"][{"aoa": 1, "aos": 0, "time": k}].item() == flow.mass_density
        r = method.coefficients(flow, math.radians(45.0), 0.0)
        np.testing.assert_array_equal(ds["Cf_G"][{"aoa": 1, "aos": 0, "time": k}].values, r.Cf_G)
    densities = ds["density"].values[0, 0]
    assert densities.max() > 1.2 * densities.min()  # (the day side is denser: it varies)


def test_a_species_scale_multiplies_its_number_density(tmp_path):
    data = {
        "mesh": "example",
        "shading": "none",
        "time": EPOCH.isoformat(),
        "fixed": {"altitude": 300},
        "axes": {"aoa": [30], "scale.O": [0.5, 1.0, 2.0]},
    }
    _, ds = swept(tmp_path, data)
    flow = air(0.0)
    method = PanelMethod(example_satellite(), "sentman", shading="none")
    n_o = flow.number_densities["O"]
    for k, factor in enumerate((0.5, 1.0, 2.0)):
        point = {"aoa": 0, "aos": 0, "scale.O": k}
        rho = flow.mass_density + (factor - 1.0) * n_o * species_mass_kg("O")
        assert ds["density"][point].item() == pytest.approx(rho, rel=1e-13)
        densities = {**flow.number_densities, "O": factor * n_o}
        gas = FreeStream(flow.speed, flow.temperature, densities, density=rho)
        r = method.coefficients(gas, math.radians(30.0), 0.0)
        np.testing.assert_allclose(ds["Cf_G"][point].values, r.Cf_G, rtol=1e-14, atol=0)
    unscaled = method.coefficients(flow, math.radians(30.0), 0.0)
    one = {"aoa": 0, "aos": 0, "scale.O": 1}
    np.testing.assert_array_equal(ds["Cf_G"][one].values, unscaled.Cf_G)
    assert ds["density"][one].item() == flow.mass_density
    # more atomic oxygen: a lighter gas, a lower speed ratio s = V sqrt(m / 2kT), more drag
    cd = ds["CD"].values[0, 0]
    assert cd[0] < cd[1] < cd[2]


def test_mesh_variants_are_each_meshs_own_panel_method(tmp_path):
    data = {
        "shading": "raycast",
        "reference": {"area": 1.5, "length": 2.0},
        "axes": {"aoa": [0, 60], "aos": [0, 20], "mesh": ["example", "grooved-cylinder"]},
    }
    _, ds = swept(tmp_path, data)
    assert ds.attrs["mesh_variants"] == ["example", "grooved-cylinder"]
    assert ds["mesh"].attrs["meshes"] == ["example", "grooved-cylinder"]
    flow = FreeStream(7700.0, 900.0, mean_mass_amu=16.0)
    reference = Reference(area=1.5, length=2.0)
    for k, name in enumerate(("example", "grooved-cylinder")):
        mesh = resolve_mesh(name)
        assert ds.attrs["mesh_fingerprints"][k] == mesh.fingerprint()
        method = PanelMethod(mesh, "sentman", reference=reference)  # (ray-cast shading)
        for i, aoa in enumerate((0.0, 60.0)):
            for j, aos in enumerate((0.0, 20.0)):
                r = method.coefficients(flow, math.radians(aoa), math.radians(aos))
                point = {"aoa": i, "aos": j, "mesh": k}
                np.testing.assert_allclose(ds["Cf_G"][point].values, r.Cf_G, rtol=1e-13, atol=1e-15)
                assert ds["area_projected"][point].item() == pytest.approx(
                    r.area_projected, rel=1e-12
                )
    assert not np.allclose(ds["CD"].values[..., 0], ds["CD"].values[..., 1])


def test_test_particles_give_standard_errors_and_the_same_numbers_on_any_workers(tmp_path):
    """A convex cylinder: every molecule hits once, so test particles converge to the panel
    method; each point is the solver's run with the point's own seed, whatever the workers."""
    data = {
        "mesh": "cylinder",
        "shading": "none",
        "solver": {"method": "tpmc", "particles": 40000, "seed": 7},
        "axes": {"aoa": [0, 50], "aos": [0, 30], "alpha": [0.6, 1.0]},
        "chunk_points": 2,
    }
    spec, one = swept(tmp_path, data, workers=1, name="one.zarr")
    _, two = swept(tmp_path, data, workers=2, name="two.zarr")
    for name in ("Cf_G", "Cm_G", "Cf_G_error", "Cm_G_error", "CD"):
        np.testing.assert_array_equal(one[name].values, two[name].values)
    mesh = resolve_mesh("cylinder")
    panel = PanelMethod(mesh, "sentman", shading="none")
    flow = FreeStream(7700.0, 900.0, mean_mass_amu=16.0)
    for index in ((1, 1, 0), (0, 1, 1)):
        aoa, aos, alpha = (float(spec.axes[n][i]) for n, i in zip(spec.axes, index))
        point = dict(zip(spec.axes, index))
        a, b = math.radians(aoa), math.radians(aos)
        surface = panel.surface_with(alpha=alpha)
        exact = panel.coefficients(flow, a, b, surface=surface)
        error = one["Cf_G_error"][point].values
        assert np.all(error > 0) and np.all(error < 0.05 * np.abs(exact.Cf_G).max())
        assert np.all(np.abs(one["Cf_G"][point].values - exact.Cf_G) <= 4.5 * error + 1e-12)
        if alpha == 1.0:  # (the materials' own alpha: the solver as the database builds it)
            solver = TestParticleMethod(mesh, "sentman", reference=panel.reference)
            r = solver.coefficients(
                flow,
                a,
                b,
                particles=40000,
                seed=attitude_seed(7, int(np.ravel_multi_index(index, spec.shape))),
            )
            np.testing.assert_array_equal(one["Cf_G"][point].values, r.Cf_G)


def test_each_point_records_its_gas_and_its_moment_in_wind_axes(tmp_path):
    """The gas's mean molecular mass and speed ratio are the free stream's; Cm_w is Cm_G
    turned to wind axes by the rotation that turns Cf_G into Cf_w (lengths kept)."""
    from adbsat_ros.geometry import frames
    from adbsat_ros.physics.constants import AMU

    data = {
        "mesh": "example",
        "shading": "none",
        "time": EPOCH.isoformat(),
        "fixed": {"altitude": 300},
        "axes": {"aoa": [-30, 40], "aos": [-20, 10]},
    }
    _, ds = swept(tmp_path, data)
    flow = air(0.0)
    assert np.all(ds["gas_mean_mass"].values == flow.mean_mass / AMU)
    assert np.all(ds["speed_ratio"].values == flow.speed_ratio)
    for i, aoa in enumerate((-30.0, 40.0)):
        for j, aos in enumerate((-20.0, 10.0)):
            point = {"aoa": i, "aos": j}
            turn = frames.body_to_wind(math.radians(aoa), math.radians(aos)) @ frames.L_GB
            cm_g, cf_g = ds["Cm_G"][point].values, ds["Cf_G"][point].values
            np.testing.assert_allclose(ds["Cm_w"][point].values, turn @ cm_g, atol=1e-15)
            np.testing.assert_allclose(ds["Cf_w"][point].values, turn @ cf_g, atol=1e-15)
            cm_w = ds["Cm_w"][point].values
            assert np.linalg.norm(cm_w) == pytest.approx(np.linalg.norm(cm_g), rel=1e-13)


def test_historical_space_weather_and_msis2_give_each_time_its_own_indices(tmp_path):
    from adbsat_ros.environment.space_weather import HistoricalWeather
    from adbsat_ros.sweep.axes import SpecError

    epoch = dt.datetime(2015, 3, 16, 12)
    data = {
        "mesh": "example",
        "shading": "none",
        "time": epoch.isoformat(),
        "space_weather": "historical",
        "atmosphere_model": "msis2.0",
        "fixed": {"altitude": 400},
        "axes": {"time": "0:12:24"},
    }
    spec, ds = swept(tmp_path, data)
    record = HistoricalWeather()
    for k, hours in enumerate(spec.axes["time"]):
        when = epoch + dt.timedelta(hours=hours)
        flow = flight_conditions_circular_orbit(
            when, 400e3, 0.0, 0.0, record, atmosphere_model="msis2.0"
        ).free_stream()
        assert ds["density"][{"aoa": 0, "aos": 0, "time": k}].item() == flow.mass_density
    assert len(set(ds["density"].values.ravel().tolist())) == 3
    for change, text in (
        ({"fixed": {"altitude": 400, "f107": 120}}, "historical takes f107 from the record"),
        ({"time": "2090-01-01T00:00:00"}, "2090-01-01T00:00:00 is outside the space-weather"),
        ({"atmosphere_model": "msis3"}, "atmosphere_model: 'msis3' is not one of"),
    ):
        with pytest.raises(SpecError, match=text):
            parse_spec({**data, **change}, "")
