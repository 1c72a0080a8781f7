"""A sweep as a lookup: exact at the grid points, bilinear in attitude as a database, linear in
the other axes, close to the panel method between them; queries outside refused by name."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr

from adbsat_ros.database.lookup import CoefficientLookup
from adbsat_ros.geometry.example_satellite import example_satellite
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.sweep.engine import run_sweep
from adbsat_ros.sweep.lookup import SweepLookup
from adbsat_ros.sweep.spec import parse_spec

SPEC = {
    "mesh": "example",
    "shading": "none",
    "axes": {"aoa": "-180:30:180", "aos": "-90:30:90", "speed": [7000, 7400, 7800]},
    "chunk_points": 512,
}


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    out = tmp_path_factory.mktemp("lookup") / "s.zarr"
    run_sweep(parse_spec(SPEC, ""), out, workers=1)
    return out


@pytest.fixture(scope="module")
def sweep(store):
    return xr.open_zarr(store, consolidated=False).load(), SweepLookup.open(store)


def test_at_the_grid_points_it_is_the_sweep(sweep):
    ds, lookup = sweep
    for i, j, k in ((2, 3, 0), (5, 1, 2), (12, 6, 1)):
        aoa, aos = ds["aoa"].values[i], ds["aos"].values[j]
        r = lookup.coefficients(aoa, aos, speed=ds["speed"].values[k])
        point = {"aoa": i, "aos": j, "speed": k}
        np.testing.assert_allclose(r.Cf_G, ds["Cf_G"][point].values, rtol=0, atol=1e-15)
        np.testing.assert_allclose(r.Cm_G, ds["Cm_G"][point].values, rtol=0, atol=1e-15)
        assert r.CD == pytest.approx(ds["CD"][point].item(), abs=1e-13)
        assert r.CL == pytest.approx(ds["CL"][point].item(), abs=1e-13)
        assert r.CY == pytest.approx(ds["CY"][point].item(), abs=1e-13)


def test_between_speeds_it_is_linear_and_close_to_the_panel_method(sweep):
    ds, lookup = sweep
    aoa, aos = 30.0, 30.0  # a grid attitude: only the speed is interpolated
    low = lookup.body_coefficients(aoa, aos, speed=7000.0)[0]
    high = lookup.body_coefficients(aoa, aos, speed=7400.0)[0]
    middle = lookup.body_coefficients(aoa, aos, speed=7100.0)[0]
    np.testing.assert_allclose(middle, 0.75 * low + 0.25 * high, rtol=1e-14, atol=1e-16)
    method = PanelMethod(example_satellite(), "sentman", shading="none")
    exact = method.coefficients(
        FreeStream(7100.0, 900.0, mean_mass_amu=16.0), math.radians(aoa), math.radians(aos)
    )
    assert np.linalg.norm(middle - exact.Cf_G) < 1e-3 * np.linalg.norm(exact.Cf_G)


def test_queries_outside_the_sweep_are_refused_by_name(sweep):
    _, lookup = sweep
    with pytest.raises(
        ValueError, match=r"speed 8000.0 is outside the sweep's range \[7000, 7800\]"
    ):
        lookup.coefficients(0.0, 0.0, speed=8000.0)
    with pytest.raises(ValueError, match="missing \\['speed'\\]"):
        lookup.coefficients(0.0, 0.0)
    with pytest.raises(ValueError, match="unknown \\['alpha'\\]"):
        lookup.coefficients(0.0, 0.0, speed=7000.0, alpha=0.9)


def test_a_coefficient_lookup_reads_the_store_at_a_speed(store, sweep):
    """CoefficientLookup of the store at one speed: bilinear in attitude and linear in speed,
    as the sweep's own lookup, with the stated error of the blended grid."""
    _, lookup = sweep
    at_speed = CoefficientLookup.load(store, speed=7250.0)
    assert at_speed.error_bound["force_coefficient"] > 0.0
    for aoa, aos in ((12.5, -7.0), (-140.0, 44.0), (90.0, 0.0)):
        cf, cm = at_speed.body_coefficients(aoa, aos)
        cf_sweep, cm_sweep = lookup.body_coefficients(aoa, aos, speed=7250.0)
        np.testing.assert_allclose(cf, cf_sweep, rtol=1e-13, atol=1e-15)
        np.testing.assert_allclose(cm, cm_sweep, rtol=1e-13, atol=1e-15)
    with pytest.raises(ValueError, match=r"speed 6000.0 is outside the sweep's range"):
        CoefficientLookup.load(store, speed=6000.0)
    with pytest.raises(ValueError, match=r"missing \['speed'\]"):
        CoefficientLookup.load(store)


def test_a_database_file_takes_no_axis_values(tmp_path):
    from adbsat_ros.database.build import build_database

    method = PanelMethod(example_satellite(), "sentman", shading="none")
    flow = FreeStream(7400.0, 900.0, mean_mass_amu=16.0)
    path = tmp_path / "d.npz"
    build_database(method, flow, [-10, 0, 10], [0, 5], shading="none", workers=1).save(path)
    assert CoefficientLookup.load(path).body_coefficients(5.0, 2.0)[0].shape == (3,)
    with pytest.raises(ValueError, match="has no axes besides aoa and aos"):
        CoefficientLookup.load(path, speed=7400.0)


def test_at_a_grid_speed_the_stores_database_is_the_database_builds(store):
    """The attitude grid read from the store at a grid speed is the database ``database``
    builds for that gas: every array, Cf_f in ADBSat's flight axes included."""
    from adbsat_ros.database.build import build_database

    read = CoefficientLookup.load(store, speed=7400.0).database
    method = PanelMethod(example_satellite(), "sentman", shading="none")
    flow = FreeStream(7400.0, 900.0, mean_mass_amu=16.0)
    built = build_database(
        method, flow, read.aoa_deg, read.aos_deg, shading="none", workers=1, progress=False
    )
    for name in ("Cf_G", "Cm_G", "Cf_w", "Cf_f", "Cm_B", "CD", "CL", "CY", "AreaProj"):
        np.testing.assert_allclose(
            getattr(read, name), getattr(built, name), rtol=1e-13, atol=1e-15, err_msg=name
        )
