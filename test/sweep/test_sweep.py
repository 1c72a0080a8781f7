"""Sweeps on local workers and real dask.distributed: a 4-axis sweep on two worker processes
equals a serial loop over the same points, bit for bit; one worker gives the same store; a sweep
stopped part-way, or whose process is killed, takes up where it stopped and gives the same
store; an articulated body's joint axis equals the posed bodies'."""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.example_satellite import example_satellite
from adbsat_ros.geometry.example_urdf import example_finned_urdf
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.shading.shader import make_shader
from adbsat_ros.sweep.engine import run_sweep
from adbsat_ros.sweep.spec import parse_spec

RESULTS = ("Cf_G", "Cm_G", "Cf_w", "Cm_B", "CD", "CL", "CY", "area_projected")
FOUR_AXES = {
    "mesh": "example",
    "model": "sentman",
    "shading": "raycast",
    "fixed": {"temperature": 900, "mean_mass_amu": 16},
    "axes": {"aoa": "0:30:60", "aos": [0, 25], "speed": [7000, 7800], "alpha": [0.8, 1.0]},
    "chunk_points": 4,
}


def load(path) -> xr.Dataset:
    return xr.open_zarr(path, consolidated=False).load()


def assert_same_store(a: xr.Dataset, b: xr.Dataset) -> None:
    for name in RESULTS:
        np.testing.assert_array_equal(a[name].values, b[name].values)
    assert a.attrs["spec_fingerprint"] == b.attrs["spec_fingerprint"]


@pytest.fixture(scope="module")
def four_axis(tmp_path_factory):
    """The 4-axis sweep on two local worker processes."""
    out = tmp_path_factory.mktemp("sweep") / "four.zarr"
    spec = parse_spec(FOUR_AXES, yaml.safe_dump(FOUR_AXES))
    report = run_sweep(spec, out, workers=2)
    assert report.workers == 2 and report.computed == report.chunks == 6
    return spec, load(out)


def test_a_four_axis_sweep_equals_a_serial_loop(four_axis):
    spec, ds = four_axis
    mesh = example_satellite()
    method = PanelMethod(mesh, "sentman", shading="none")
    shader = make_shader(mesh)
    assert not np.isnan(ds["CD"].values).any() and ds["chunk_done"].values.all()
    for i, aoa in enumerate(spec.axes["aoa"]):
        for j, aos in enumerate(spec.axes["aos"]):
            a, b = math.radians(aoa), math.radians(aos)
            lighting = shader.lighting_angles(a, b)
            for k, speed in enumerate(spec.axes["speed"]):
                flow = FreeStream(speed, 900.0, mean_mass_amu=16.0)
                for m, alpha in enumerate(spec.axes["alpha"]):
                    surface = method.surface_with(alpha=alpha)
                    r = method.coefficients(flow, a, b, lighting=lighting, surface=surface)
                    point = dict(aoa=i, aos=j, speed=k, alpha=m)
                    np.testing.assert_array_equal(ds["Cf_G"][point].values, r.Cf_G)
                    np.testing.assert_array_equal(ds["Cm_B"][point].values, r.Cm_B)
                    assert ds["CD"][point].item() == r.drag
                    assert ds["area_projected"][point].item() == r.area_projected
    assert ds["aoa"].attrs["units"] == "deg" and ds["speed"].attrs["units"] == "m/s"
    assert ds.attrs["reference_area_m2"] == method.reference.area
    assert yaml.safe_load(ds.attrs["spec_yaml"]) == FOUR_AXES


def test_one_worker_gives_the_same_store(four_axis, tmp_path):
    spec, ds = four_axis
    run_sweep(spec, tmp_path / "one.zarr", workers=1)
    assert_same_store(load(tmp_path / "one.zarr"), ds)


class StopAfter:
    """A stop event that is set once ``count`` chunks have been written."""

    def __init__(self, store_path, count):
        self.path, self.count = store_path, count

    def is_set(self):
        done = xr.open_zarr(self.path, consolidated=False)["chunk_done"].values
        return int(done.sum()) >= self.count


def test_a_stopped_sweep_takes_up_where_it_stopped(four_axis, tmp_path):
    spec, ds = four_axis
    out = tmp_path / "stopped.zarr"
    first = run_sweep(spec, out, workers=2, stop=StopAfter(out, 2))
    assert first.stopped and 2 <= first.computed < first.chunks
    done = load(out)["chunk_done"].values
    assert done.sum() == first.computed < done.size
    second = run_sweep(spec, out, workers=2)
    assert second.already_done == first.computed
    assert second.computed == second.chunks - first.computed
    assert_same_store(load(out), ds)
    other = parse_spec({**FOUR_AXES, "model": "cook"}, "")
    with pytest.raises(ValueError, match="holds another spec's sweep"):
        run_sweep(other, out, workers=1)


def test_a_killed_sweep_resumes_to_the_same_store(four_axis, tmp_path):
    """The command line killed with SIGKILL after its first chunks: the same command again
    finishes the store, equal to an uninterrupted run."""
    spec, ds = four_axis
    data = {**FOUR_AXES, "chunk_points": 1}  # 24 chunks: time to kill it in the middle
    path = tmp_path / "spec.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    out = tmp_path / "killed.zarr"
    argv = [sys.executable, "-m", "adbsat_ros.cli", "sweep", str(path), "--out", str(out)]
    process = subprocess.Popen([*argv, "--workers", "1"], stdout=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        done_path = out / "chunk_done"
        if done_path.exists():
            try:
                done = int(xr.open_zarr(out, consolidated=False)["chunk_done"].values.sum())
            except Exception:  # (the store being written)
                done = 0
            if done >= 3:
                break
        time.sleep(0.05)
    process.send_signal(signal.SIGKILL)
    process.wait(timeout=30)
    partial = xr.open_zarr(out, consolidated=False)["chunk_done"].values
    assert 3 <= partial.sum() < len(partial)
    finished = subprocess.run([*argv, "--workers", "2"], capture_output=True, text=True)
    assert finished.returncode == 0, finished.stderr
    assert f"{int(partial.sum())} already in" in finished.stdout
    again = load(out)
    for name in RESULTS:  # (the chunking differs from the fixture's; the numbers do not)
        np.testing.assert_array_equal(again[name].values, ds[name].values)


def test_a_joint_axis_sweeps_the_posed_bodies(tmp_path):
    data = {
        "mesh": "example-finned",
        "shading": "raycast",
        "axes": {"aoa": [0, 15], "aos": [5], "joint.fin_py_hinge": [-10, 0, 20]},
    }
    body = ArticulatedBody.from_urdf(example_finned_urdf())
    spec = parse_spec(data, "", body.joints)
    run_sweep(spec, tmp_path / "fins.zarr", workers=2)
    ds = load(tmp_path / "fins.zarr")
    assert ds["joint.fin_py_hinge"].attrs["units"] == "deg"
    reference = Reference().resolved(body.mesh())
    flow = FreeStream(7700.0, 900.0, mean_mass_amu=16.0)
    for i, aoa in enumerate(spec.axes["aoa"]):
        for k, deflection in enumerate(spec.axes["joint.fin_py_hinge"]):
            mesh = body.mesh({"fin_py_hinge": math.radians(deflection)})
            a, b = math.radians(aoa), math.radians(5.0)
            lighting = make_shader(mesh).lighting_angles(a, b)
            r = PanelMethod(mesh, "sentman", reference=reference).coefficients(
                flow, a, b, lighting=lighting
            )
            point = {"aoa": i, "aos": 0, "joint.fin_py_hinge": k}
            np.testing.assert_allclose(ds["Cf_G"][point].values, r.Cf_G, rtol=0, atol=1e-13)
            np.testing.assert_allclose(ds["Cm_G"][point].values, r.Cm_G, rtol=0, atol=1e-13)
    pitch = ds["Cm_G"].sel(component=1) if "component" in ds.coords else ds["Cm_G"][..., 1]
    assert np.ptp(pitch.values[0, 0, :]) > 1e-4  # the fin's deflection pitches the body


def _dask_cli(*args) -> list:
    return [str(Path(sys.executable).with_name("dask")), *args]


@pytest.fixture
def external_cluster(tmp_path):
    """A scheduler and two workers started as separate processes on 127.0.0.1 (as `dask
    scheduler` and `dask worker` start them on a cluster's nodes); the workers' process ids."""
    info = tmp_path / "scheduler.json"
    quiet = {"stdout": subprocess.DEVNULL, "stderr": subprocess.DEVNULL}
    processes = []
    try:  # (every process is killed, even when starting the others fails)
        processes.append(
            subprocess.Popen(
                _dask_cli(
                    "scheduler",
                    "--host",
                    "127.0.0.1",
                    "--port",
                    "0",
                    "--no-dashboard",
                    "--scheduler-file",
                    str(info),
                ),
                **quiet,
            )
        )
        deadline = time.monotonic() + 60
        while not info.exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        address = json.loads(info.read_text())["address"]
        for k in range(2):
            processes.append(
                subprocess.Popen(
                    _dask_cli(
                        "worker",
                        address,
                        "--nthreads",
                        "1",
                        "--no-nanny",
                        "--no-dashboard",
                        "--name",
                        f"w{k}",
                        "--host",
                        "127.0.0.1",
                    ),
                    **quiet,
                )
            )
        from distributed import Client

        with Client(address) as client:
            client.wait_for_workers(2, timeout=60)
        yield address, [p.pid for p in processes[1:]]
    finally:
        for p in processes:
            p.kill()
            p.wait(timeout=30)


def test_a_sweep_on_a_running_scheduler_with_a_worker_killed_gives_the_same_store(
    four_axis, external_cluster, tmp_path
):
    """Against a scheduler and two workers of their own processes; one worker is killed with
    SIGKILL once the first chunks are in: its chunks go to the other, the store is the same."""
    spec, ds = four_axis
    address, workers = external_cluster
    fine = parse_spec({**FOUR_AXES, "chunk_points": 1}, "")  # 24 chunks
    out = tmp_path / "remote.zarr"

    class KillAfter:
        """Kills the first worker once three chunks are written (checked as chunks finish)."""

        killed = False

        def is_set(self):
            done = int(xr.open_zarr(out, consolidated=False)["chunk_done"].values.sum())
            if done >= 3 and not self.killed:
                os.kill(workers[0], signal.SIGKILL)
                self.killed = True
            return False

    stopper = KillAfter()
    report = run_sweep(fine, out, scheduler=address, stop=stopper)
    assert stopper.killed and report.workers == 2
    assert report.computed == report.chunks == 24
    again = load(out)
    for name in RESULTS:
        np.testing.assert_array_equal(again[name].values, ds[name].values)


def test_an_atmosphere_sweep_is_nrlmsise_at_each_altitude_and_flux(tmp_path):
    """Altitude and F10.7 axes: each point's gas is NRLMSISE-00's at a circular orbit's speed
    (flight_conditions_circular_orbit at the spec's time), the same numbers as computed here;
    the density it was computed in is recorded, and falls with altitude, rises with F10.7."""
    import datetime as dt

    from adbsat_ros.environment.atmosphere import SpaceWeather
    from adbsat_ros.environment.circular_orbit import flight_conditions_circular_orbit

    data = {
        "mesh": "example",
        "shading": "none",
        "time": "2026-06-21T12:00:00",
        "fixed": {"ap": 15},
        "axes": {"aoa": [0, 40], "altitude": [250, 450], "f107": [80, 220]},
    }
    spec = parse_spec(data, "")
    run_sweep(spec, tmp_path / "air.zarr", workers=1)
    ds = load(tmp_path / "air.zarr")
    method = PanelMethod(example_satellite(), "sentman", shading="none")
    for i, aoa in enumerate(spec.axes["aoa"]):
        for k, altitude in enumerate(spec.axes["altitude"]):
            for m, f107 in enumerate(spec.axes["f107"]):
                conditions = flight_conditions_circular_orbit(
                    dt.datetime(2026, 6, 21, 12),
                    1e3 * altitude,
                    0.0,
                    0.0,
                    SpaceWeather(f107, 150.0, 15.0),
                )
                flow = conditions.free_stream()
                r = method.coefficients(flow, math.radians(aoa), 0.0)
                point = {"aoa": i, "aos": 0, "altitude": k, "f107": m}
                np.testing.assert_array_equal(ds["Cf_G"][point].values, r.Cf_G)
                assert ds["density"][point].item() == flow.mass_density
                assert ds["gas_speed"][point].item() == flow.speed
    density = ds["density"].values[0, 0]
    assert density[0, 0] > 10 * density[1, 0] and density[1, 1] > density[1, 0]


def test_a_chunk_write_cut_by_a_kill_is_the_stores_own_file():
    """zarr writes a chunk through ``<index>.<hex>.partial``; a kill can leave one, and the
    resumed sweep takes it as its own; anything else under ``c/`` stays foreign."""
    from adbsat_ros.sweep.store import _zarr_file

    assert _zarr_file(("chunk_done", "c", "4." + "0a" * 16 + ".partial"))
    assert _zarr_file(("Cf_w", "c", "4", "0"))
    assert not _zarr_file(("chunk_done", "c", "notes.partial"))
    assert not _zarr_file(("chunk_done", "c", "4", "x." + "0a" * 16 + ".partial"))
