"""Aerodynamic databases: closed forms at every grid point, file round trips, worker independence,
validation of bad files, and rebuilding the set-up from the metadata."""

import csv
import json
import math

import numpy as np
import pytest
import trimesh
from closed_forms import reemission_temperature, sentman_sphere_cd, unit_sphere_mesh

from adbsat_ros import (
    FreeStream,
    MaterialTable,
    PanelMethod,
    Reference,
    SurfaceProperties,
    panels_from_arrays,
)
from adbsat_ros.database.build import build_database
from adbsat_ros.database.format import (
    FORMAT_VERSION,
    REQUIRED_METADATA,
    SCALAR_FIELDS,
    VECTOR_FIELDS,
    AeroDatabase,
    DatabaseError,
    load_database,
)
from adbsat_ros.database.metadata import model_from_metadata
from adbsat_ros.geometry.loading import resolve_mesh
from adbsat_ros.processes import usable_cpus
from adbsat_ros.shading.shader import make_shader

FLOW = FreeStream(7500.0, 900.0, mean_mass_amu=16.0)
SLOW = FreeStream(1500.0, 1200.0, mean_mass_amu=28.0)


def plate_method(model="newton"):
    return PanelMethod(two_sided_plate(), model, reference=Reference(area=1.5**2, length=1.0))


def two_sided_plate(size=1.5):
    """Zero-thickness square plate in the y-z plane, faces +x and -x, centred on the origin."""
    h = size / 2
    v = np.array([[0, -h, -h], [0, h, -h], [0, h, h], [0, -h, h]], dtype=float)
    f = np.array([[0, 1, 2], [0, 2, 3], [0, 2, 1], [0, 3, 2]])
    return panels_from_arrays(v, f, fix_normals=False)


@pytest.fixture(scope="module")
def example_db():
    """Example satellite, Sentman, ray-cast shading, a coarse full-sphere grid, one worker."""
    method = PanelMethod(
        resolve_mesh("example"),
        "sentman",
        MaterialTable.from_texts(
            SurfaceProperties(alpha=0.9), ["solar_array:alpha=0.8,wall_temperature=350"]
        ),
    )
    return build_database(
        method,
        FLOW,
        np.arange(-180, 181, 45.0),
        np.arange(-90, 91, 45.0),
        shading="raycast",
        workers=1,
        progress=False,
        mesh_spec="example",
    )


# ------------------------------------------------------------------------------ closed forms
def test_newton_plate_database_matches_closed_form_everywhere():
    """Two-sided Newtonian plate (normal x): c = |cos a cos b| on the front face, so
    Cf_G = (-2 c cos(a) cos(b), 0, 0), C_D = 2 c^3 per plate area, no moment about its centre,
    projected area A c; CL = sin(a) Cf_x and CY = -cos(a) sin(b) Cf_x from the rows of the
    body-to-wind matrix (B x = G x)."""
    A = 1.5**2
    method = PanelMethod(two_sided_plate(), "newton", reference=Reference(area=A, length=1.0))
    aoa, aos = np.arange(-180, 181, 30.0), np.arange(-90, 91, 30.0)
    db = build_database(
        method, FLOW, aoa, aos, shading="none", workers=1, progress=False, mesh_spec=None
    )
    a, b = np.meshgrid(np.radians(aoa), np.radians(aos), indexing="ij")
    k = np.cos(a) * np.cos(b)
    c = np.abs(k)
    np.testing.assert_allclose(db.Cf_G[..., 0], -2.0 * c * k, atol=1e-14)
    np.testing.assert_allclose(db.Cf_G[..., 1:], 0.0, atol=1e-14)
    np.testing.assert_allclose(db.CD, 2.0 * c**3, atol=1e-14)
    np.testing.assert_allclose(db.Cm_G, 0.0, atol=1e-14)
    np.testing.assert_allclose(db.AreaProj, A * c, atol=1e-14)
    # lift: -Cf_w[2] = F . (sin a, 0, cos a)_B ; side force Cf_w[1] (wind axes from frames)
    sa, ca, sb = np.sin(a), np.cos(a), np.sin(b)
    Fx = db.Cf_G[..., 0]  # B x = G x
    np.testing.assert_allclose(db.CL, -(-sa) * Fx, atol=1e-14)  # third row of L_WB: (-sa, 0, ca)
    np.testing.assert_allclose(db.CY, -ca * sb * Fx, atol=1e-14)  # second row: (-ca sb, cb, -sa sb)
    assert db.metadata["mesh"]["spec"] is None


def test_sentman_sphere_database_matches_closed_form_everywhere():
    """Icosphere (area 4 pi, convex: ray-cast shading has nothing to do): C_D = Sentman's sphere
    at every grid point, the force along the flow, no lift, side force or moment about the
    centre."""
    alpha, Tw = 0.9, 300.0
    method = PanelMethod(
        unit_sphere_mesh(5),
        "sentman",
        SurfaceProperties(alpha=alpha, wall_temperature=Tw),
        reference=Reference(area=math.pi, length=2.0),
    )
    aoa, aos = np.arange(-180, 181, 60.0), np.arange(-90, 91, 45.0)
    db = build_database(
        method, SLOW, aoa, aos, shading="raycast", workers=1, progress=False, mesh_spec=None
    )
    expected = sentman_sphere_cd(
        SLOW.speed_ratio, reemission_temperature(SLOW, alpha, Tw) / SLOW.temperature
    )
    np.testing.assert_allclose(db.CD, expected, rtol=1e-4)
    np.testing.assert_allclose(
        db.Cf_G, db.CD[..., None] * db.flow_directions(), atol=2e-5 * expected
    )
    assert np.abs(db.CL).max() < 2e-5 * expected and np.abs(db.CY).max() < 2e-5 * expected
    assert np.abs(db.Cm_G).max() < 2e-6 * expected
    np.testing.assert_allclose(db.AreaProj, math.pi, rtol=1e-4)


def test_frames_are_consistent(example_db):
    """Stored Cf_w, Cf_f, Cm_B are the rotations of Cf_G, Cm_G, and CD/CL/CY come from Cf_w."""
    from adbsat_ros.geometry import frames

    db = example_db
    a, b = np.meshgrid(np.radians(db.aoa_deg), np.radians(db.aos_deg), indexing="ij")
    L = frames.mesh_to_wind(a, b)
    np.testing.assert_allclose(db.Cf_w, np.einsum("...ij,...j->...i", L, db.Cf_G), atol=1e-14)
    np.testing.assert_allclose(db.Cf_f, db.Cf_G @ (frames.L_FB @ frames.L_GB).T, atol=1e-15)
    np.testing.assert_allclose(db.Cm_B, db.Cm_G @ frames.L_GB.T, atol=1e-15)
    np.testing.assert_array_equal(db.CD, -db.Cf_w[..., 0])
    np.testing.assert_array_equal(db.CL, -db.Cf_w[..., 2])
    np.testing.assert_array_equal(db.CY, db.Cf_w[..., 1])


# ------------------------------------------------------------------------------ workers, progress
def test_worker_count_does_not_change_results(example_db):
    """Two worker processes, odd chunking, give the same numbers bit for bit as one process."""
    model, flow = model_from_metadata(example_db.metadata)
    method = model.method
    calls = []
    db2 = build_database(
        method,
        flow,
        example_db.aoa_deg,
        example_db.aos_deg,
        shading="raycast",
        workers=2,
        progress=lambda done, total: calls.append((done, total)),
        mesh_spec="example",
    )
    for name in SCALAR_FIELDS + VECTOR_FIELDS:
        np.testing.assert_array_equal(getattr(db2, name), getattr(example_db, name), err_msg=name)
    assert calls[-1] == (example_db.n_attitudes, example_db.n_attitudes)
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)
    assert db2.metadata["interpolation_error"] == example_db.metadata["interpolation_error"]


def test_the_default_workers_give_the_same_database_here_or_split(example_db, monkeypatch):
    """By default the chunks run here (a small build), or here until workers pay and on them
    after (forced): the same numbers bit for bit."""
    from adbsat_ros import tasks

    model, flow = model_from_metadata(example_db.metadata)
    for split in (False, True):
        monkeypatch.setattr(tasks, "worth_workers", lambda left, start, count: split)
        report = tasks.TaskReport()
        db = build_database(
            model.method,
            flow,
            example_db.aoa_deg,
            example_db.aos_deg,
            shading="raycast",
            progress=False,
            mesh_spec="example",
            report=report,
        )
        for name in SCALAR_FIELDS + VECTOR_FIELDS:
            np.testing.assert_array_equal(getattr(db, name), getattr(example_db, name))
        assert report.here == (1 if split else report.computed)
        assert report.workers == (min(2, usable_cpus()) if split else 1)


def test_a_running_scheduler_gives_the_same_database(example_db, tmp_path):
    """The attitudes computed by the workers of a running Dask scheduler (here a LocalCluster
    of two processes), by the API and by ``database --scheduler``: the same numbers bit for
    bit as one process."""
    from distributed import Client, LocalCluster

    from adbsat_ros.cli import main
    from adbsat_ros.database.format import load_database

    model, flow = model_from_metadata(example_db.metadata)
    method = model.method
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=":0")
    with cluster, Client(cluster) as client:
        client.wait_for_workers(2)
        db2 = build_database(
            method,
            flow,
            example_db.aoa_deg,
            example_db.aos_deg,
            shading="raycast",
            progress=False,
            mesh_spec="example",
            scheduler=cluster.scheduler_address,
        )
        out = tmp_path / "remote.npz"
        argv = ["database", "example", "--speed", "7500", "--temperature", "900"]
        argv += ["--mean-mass", "16", "--aoa", "-180:45:180", "--aos", "-90:45:90"]
        argv += ["--scheduler", cluster.scheduler_address, "--out", str(out)]
        assert main(argv) == 0
    for name in SCALAR_FIELDS + VECTOR_FIELDS:
        np.testing.assert_array_equal(getattr(db2, name), getattr(example_db, name), err_msg=name)
    here = tmp_path / "here.npz"
    assert main([*argv[:-4], "--workers", "1", "--out", str(here)]) == 0
    remote, local = load_database(out), load_database(here)
    for name in SCALAR_FIELDS + VECTOR_FIELDS:
        np.testing.assert_array_equal(getattr(remote, name), getattr(local, name), err_msg=name)


def test_progress_tqdm_instance_is_updated():
    import io

    from tqdm import tqdm

    method = plate_method()
    with tqdm(total=6, file=io.StringIO()) as bar:
        build_database(
            method,
            FLOW,
            [0, 10, 20],
            [0, 5],
            shading="none",
            workers=1,
            progress=bar,
            mesh_spec=None,
        )
        assert bar.n == 6


# ------------------------------------------------------------------------------ files
def test_npz_round_trip(example_db, tmp_path):
    path = example_db.save(tmp_path / "db.npz")
    back = load_database(path)
    for name in ("aoa_deg", "aos_deg") + SCALAR_FIELDS + VECTOR_FIELDS:
        np.testing.assert_array_equal(getattr(back, name), getattr(example_db, name), err_msg=name)
    assert back.metadata == example_db.metadata
    assert back.path == str(path)
    assert set(REQUIRED_METADATA) <= set(back.metadata)
    assert back.metadata["format_version"] == FORMAT_VERSION


def test_csv_agrees_with_npz(example_db, tmp_path):
    """The CSV, read with the csv module, holds the npz values exactly, one row per attitude."""
    example_db.save_csv(tmp_path / "db.csv")
    back = load_database(example_db.save(tmp_path / "db.npz"))
    with open(tmp_path / "db.csv", encoding="utf-8") as stream:
        lines = stream.read().splitlines()
    header = [line[2:] for line in lines if line.startswith("# ")]
    meta = dict(line.split(": ", 1) for line in header[1:])
    assert int(meta["format_version"]) == FORMAT_VERSION
    assert (
        meta["shading"].startswith("raycast")
        and "fingerprint " + back.metadata["mesh"]["fingerprint"] in meta["mesh"]
    )
    rows = list(csv.DictReader(line for line in lines if not line.startswith("#")))
    assert len(rows) == back.n_attitudes
    na, nb = back.shape
    for k, row in enumerate(rows):
        i, j = divmod(k, nb)
        assert float(row["aoa_deg"]) == back.aoa_deg[i] and float(row["aos_deg"]) == back.aos_deg[j]
        for name, column in (
            ("CD", "drag_coefficient"),
            ("CL", "lift_coefficient"),
            ("CY", "side_force_coefficient"),
            ("AreaProj", "projected_area_m2"),
        ):
            assert float(row[column]) == getattr(back, name)[i, j]
        for name, prefix in zip(VECTOR_FIELDS, ("cf_w_", "cf_f_", "cm_b_", "cf_", "cm_")):
            assert [float(row[prefix + x]) for x in "xyz"] == getattr(back, name)[i, j].tolist()
        assert (
            float(row["reference_area_m2"]) == back.reference_area
            and float(row["reference_length_m"]) == back.reference_length
        )


def test_save_refuses_other_suffixes(example_db, tmp_path):
    with pytest.raises(ValueError, match=r"\.npz"):
        example_db.save(tmp_path / "db.dat")


def _corrupt(example_db, path, **changes):
    """Write example_db to path with some arrays replaced (None: left out)."""
    arrays = {
        "aoa_deg": example_db.aoa_deg,
        "aos_deg": example_db.aos_deg,
        "metadata": np.array(json.dumps(example_db.metadata)),
    }
    arrays.update({n: getattr(example_db, n) for n in SCALAR_FIELDS + VECTOR_FIELDS})
    for key, value in changes.items():
        if value is None:
            arrays.pop(key)
        else:
            arrays[key] = value
    np.savez(path, **arrays)
    return path


def _metadata_with(example_db, **changes):
    meta = dict(example_db.metadata, **changes)
    return np.array(json.dumps(meta))


@pytest.mark.parametrize(
    "case,needle",
    [
        ("missing_file", "no such file"),
        ("text_file", "not a readable database"),
        ("no_CD", "missing arrays CD"),
        ("bad_json", "not valid JSON"),
        ("version", "format_version 99"),
        ("no_interp", "interpolation_error"),
        ("shape", "Cf_G has shape"),
        ("nan", "CL has non-finite"),
        ("order", "aoa_deg is not strictly increasing"),
        ("strings", "CD is not numeric"),
    ],
)
def test_bad_files_raise_database_error_naming_the_file(example_db, tmp_path, case, needle):
    path = tmp_path / f"{case}.npz"
    if case == "text_file":
        path.write_text("not a zip file")
    elif case == "no_CD":
        _corrupt(example_db, path, CD=None)
    elif case == "bad_json":
        _corrupt(example_db, path, metadata=np.array("{not json"))
    elif case == "version":
        _corrupt(example_db, path, metadata=_metadata_with(example_db, format_version=99))
    elif case == "no_interp":
        meta = dict(example_db.metadata)
        meta.pop("interpolation_error")
        _corrupt(example_db, path, metadata=np.array(json.dumps(meta)))
    elif case == "shape":
        _corrupt(example_db, path, Cf_G=example_db.Cf_G[:, :-1])
    elif case == "nan":
        bad = example_db.CL.copy()
        bad[1, 2] = np.nan
        _corrupt(example_db, path, CL=bad)
    elif case == "order":
        _corrupt(example_db, path, aoa_deg=example_db.aoa_deg[::-1].copy())
    elif case == "strings":
        _corrupt(example_db, path, CD=np.full(example_db.shape, "x"))
    with pytest.raises(DatabaseError) as info:
        load_database(path)
    assert str(path) in str(info.value) and needle in str(info.value)


# ------------------------------------------------------------------------------ metadata
def test_metadata_rebuilds_the_exact_setup(example_db):
    """model_from_metadata reloads the mesh, materials (with the override), model, shading and
    flow: a fresh evaluation at a grid attitude reproduces the stored numbers exactly, and so
    does the kernel shaded by ray casting at that direction."""
    meta = example_db.metadata
    assert meta["mesh"]["spec"] == "example" and meta["mesh"]["n_panels"] == 4192
    assert meta["materials"]["default"]["alpha"] == 0.9
    model, flow = model_from_metadata(meta)
    method = model.method
    assert method.materials.properties("solar_array").wall_temperature == 350.0
    assert method.materials.properties("solar_array").alpha == 0.8
    assert model.setup.shading.mode == "raycast"
    i, j = 3, 1
    a, b = math.radians(example_db.aoa_deg[i]), math.radians(example_db.aos_deg[j])
    from adbsat_ros.geometry import frames

    r = model.evaluate(flow, angles=(a, b))
    np.testing.assert_array_equal(r.Cf_G, example_db.Cf_G[i, j])
    np.testing.assert_array_equal(r.Cm_G, example_db.Cm_G[i, j])
    shader = make_shader(method.mesh, mode="raycast")
    r = method.coefficients(flow, a, b, lighting=shader.lighting(frames.flow_direction(a, b)))
    np.testing.assert_array_equal(r.Cf_G, example_db.Cf_G[i, j])
    np.testing.assert_array_equal(r.Cm_G, example_db.Cm_G[i, j])


def test_metadata_refuses_changed_or_unknown_meshes(example_db, tmp_path):
    box = trimesh.creation.box(extents=(1.0, 0.5, 0.5))
    path = tmp_path / "box.stl"
    box.export(path)
    from adbsat_ros import load_mesh

    method = PanelMethod(load_mesh(path), "sentman")
    db = build_database(
        method, FLOW, [0, 90], [0], shading="none", workers=1, progress=False, mesh_spec=str(path)
    )
    assert model_from_metadata(db.metadata)[0].mesh.fingerprint() == method.mesh.fingerprint()
    box.apply_scale(1.1)
    box.export(path)
    with pytest.raises(DatabaseError, match="has changed"):
        model_from_metadata(db.metadata, path="db.npz")
    with pytest.raises(DatabaseError, match="built in code"):
        model_from_metadata(dict(db.metadata, mesh=dict(db.metadata["mesh"], spec=None)))
    with pytest.raises(ValueError, match="does not load the method's mesh"):
        build_database(
            plate_method(),
            FLOW,
            [0],
            [0],
            shading="none",
            workers=1,
            progress=False,
            mesh_spec=str(path),
        )


@pytest.mark.parametrize(
    "kwargs,needle",
    [
        ({"aoa_deg": [0, 10, 10]}, "given twice"),
        ({"aos_deg": [0, 95]}, r"\[-90, 90\]"),
        ({"aoa_deg": [0, np.nan]}, "finite"),
        ({"workers": 0}, "workers"),
        ({"shading": "fancy"}, "shading"),
        ({"samples": 0}, "samples"),
    ],
)
def test_bad_build_arguments(kwargs, needle):
    args = {
        "aoa_deg": [0, 10],
        "aos_deg": [0],
        "shading": "none",
        "workers": 1,
        "progress": False,
        "mesh_spec": None,
    }
    args.update(kwargs)
    with pytest.raises(ValueError, match=needle):
        build_database(plate_method(), FLOW, **args)


def test_angles_are_sorted():
    db = build_database(
        plate_method(),
        FLOW,
        [30, -30, 0],
        [10, 0],
        shading="none",
        workers=1,
        progress=False,
        mesh_spec=None,
    )
    assert db.aoa_deg.tolist() == [-30, 0, 30] and db.aos_deg.tolist() == [0, 10]
    assert isinstance(db, AeroDatabase) and db.shape == (3, 2)


def test_a_test_particle_database_is_each_attitudes_own_run_for_any_worker_count():
    """--method tpmc: attitude i is the test-particle run with its own seed (attitude_seed), the
    same for 1 and 2 workers; the stated error adds three of the largest standard errors, and
    the lookup (the node's database source) reads it unchanged."""
    from adbsat_ros.database.build import attitude_seed
    from adbsat_ros.database.lookup import CoefficientLookup
    from adbsat_ros.physics.tpmc.method import TestParticleMethod

    mesh = resolve_mesh("cylinder")
    method = PanelMethod(mesh, "sentman")
    run = dict(solver="tpmc", particles=70_000, seed=9, mesh_spec="cylinder")
    dbs = [
        build_database(method, FLOW, [0, 20, 40], [0, 15], workers=w, progress=False, **run)
        for w in (1, 2)
    ]
    for name in VECTOR_FIELDS + SCALAR_FIELDS:
        np.testing.assert_array_equal(getattr(dbs[0], name), getattr(dbs[1], name))
    db = dbs[0]
    assert db.metadata["solver"] == {
        "method": "tpmc",
        "particles": 70_000,
        "tolerance": None,
        "seed": 9,
    }
    solver = TestParticleMethod(mesh, "sentman")
    index = 1 * 2 + 1  # aoa 20, aos 15 in the grid's row-major order
    direct = solver.coefficients(
        FLOW, math.radians(20), math.radians(15), particles=70_000, seed=attitude_seed(9, index)
    )
    np.testing.assert_array_equal(db.Cf_G[1, 1], direct.Cf_G)
    np.testing.assert_array_equal(db.Cm_G[1, 1], direct.Cm_G)
    error = db.metadata["interpolation_error"]
    assert error["statistical_force_coefficient"] >= 3.0 * np.linalg.norm(direct.Cf_G_error)
    lookup = CoefficientLookup(db)
    cf, _ = lookup.body_coefficients(20.0, 15.0)
    np.testing.assert_allclose(cf, direct.Cf_G, rtol=1e-12)  # (mesh frame G)
    assert (
        lookup.error_bound["statistical_force_coefficient"]
        == error["statistical_force_coefficient"]
    )


def test_a_stopped_build_keeps_the_attitudes_done_and_is_no_database(tmp_path):
    import threading

    stop = threading.Event()
    stop.set()  # set before: the build ends after its first chunk
    method = PanelMethod(resolve_mesh("cylinder"), "sentman")
    db = build_database(
        method, FLOW, [0, 10, 20, 30], [0, 10], workers=1, progress=False, stop=stop
    )
    partial = db.metadata["partial"]
    assert 0 < partial["attitudes_done"] < partial["attitudes"] == 8
    done = np.isfinite(db.CD)
    assert done.sum() == partial["attitudes_done"]
    full = build_database(method, FLOW, [0, 10, 20, 30], [0, 10], workers=1, progress=False)
    np.testing.assert_array_equal(db.Cf_G[done], full.Cf_G[done])
    with pytest.raises(ValueError, match="the build was stopped; a partial grid is not a database"):
        db.save(tmp_path / "p.npz")
    rows = [
        line
        for line in open(db.save_csv(tmp_path / "p.csv"), encoding="utf-8")
        if not line.startswith("#")
    ]
    assert len(rows) == 1 + partial["attitudes_done"]
