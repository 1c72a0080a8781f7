"""The `adbsat-ros database` command: files written, summary, agreement with `coeff`, and
one-line errors with exit status 2."""

import json
import subprocess
import sys

import numpy as np
import pytest

from adbsat_ros.cli import main
from adbsat_ros.database.format import load_database
from adbsat_ros.database.lookup import CoefficientLookup
from adbsat_ros.database.metadata import model_from_metadata
from adbsat_ros.processes import usable_cpus

FLOW = ["--speed", "7700", "--temperature", "900", "--mean-mass", "16"]


@pytest.fixture(scope="module")
def mesh_file(tmp_path_factory):
    """An L-shaped pair of boxes (concave: ray-cast shading has work to do), ~100 faces."""
    import trimesh

    a = trimesh.creation.box(extents=(1.0, 0.4, 0.4))
    b = trimesh.creation.box(extents=(0.3, 0.3, 1.0))
    b.apply_translation((-0.35, 0.0, 0.7))
    path = tmp_path_factory.mktemp("mesh") / "ell.stl"
    trimesh.util.concatenate([a, b]).export(path)
    return path


def run(capsys, *argv):
    code = main(["database", *map(str, argv)])
    out, err = capsys.readouterr()
    return code, out, err


def test_end_to_end_and_agreement_with_coeff(capsys, mesh_file, tmp_path):
    out = tmp_path / "ell.npz"
    code, text, _ = run(
        capsys,
        mesh_file,
        *FLOW,
        "--aoa=-180:60:180",
        "--aos=-90:45:90",
        "--gsim",
        "cook",
        "--moment-ref",
        "0.1,0,0.2",
        "--workers",
        "2",
        "--out",
        out,
    )
    assert code == 0
    assert "7 aoa (-180..180 deg) x 5 aos (-90..90 deg) = 35" in text
    assert "stated interpolation error" in text and f"wrote {out}" in text
    csv_path = tmp_path / "ell.csv"
    assert f"wrote {csv_path}" in text and csv_path.exists()
    db = load_database(out)
    meta = db.metadata
    assert meta["mesh"]["spec"] == str(mesh_file) and meta["model"]["name"] == "cook"
    assert meta["shading"] == {"mode": "raycast", "samples": 16}
    assert meta["reference"]["moment_point"] == [0.1, 0.0, 0.2]
    err = CoefficientLookup(db).error_bound
    assert f"|dCf_G| <= {err['force_coefficient']:.3g}" in text
    # the same attitudes through `coeff --json` (an independent loop over attitudes)
    code = main(
        [
            "coeff",
            str(mesh_file),
            *FLOW,
            "--aoa=-180:60:180",
            "--aos=-90:45:90",
            "--gsim",
            "cook",
            "--moment-ref",
            "0.1,0,0.2",
            "--json",
        ]
    )
    rows = json.loads(capsys.readouterr()[0])
    assert code == 0 and len(rows) == db.n_attitudes
    for k, row in enumerate(rows):
        i, j = divmod(k, db.shape[1])
        assert (row["aoa_deg"], row["aos_deg"]) == (db.aoa_deg[i], db.aos_deg[j])
        for name in ("Cf_w", "Cf_f", "Cm_B", "Cf_G", "Cm_G"):
            np.testing.assert_array_equal(row[name], getattr(db, name)[i, j], err_msg=name)
        assert (row["CD"], row["AreaProj"]) == (db.CD[i, j], db.AreaProj[i, j])
    # one worker and an explicit CSV path: the same numbers
    code, _, _ = run(
        capsys,
        mesh_file,
        *FLOW,
        "--aoa=-180:60:180",
        "--aos=-90:45:90",
        "--gsim",
        "cook",
        "--moment-ref",
        "0.1,0,0.2",
        "--workers",
        "1",
        "--out",
        tmp_path / "one.npz",
        "--csv",
        tmp_path / "other.csv",
    )
    assert code == 0 and (tmp_path / "other.csv").exists() and not (tmp_path / "one.csv").exists()
    np.testing.assert_array_equal(load_database(tmp_path / "one.npz").Cf_G, db.Cf_G)


def test_flight_conditions_fold_alpha_into_materials(capsys, mesh_file, tmp_path):
    """--time and a place: the accommodation model's alpha lands in the recorded materials, and the
    numbers equal `coeff` with the same flight conditions."""
    common = [
        str(mesh_file),
        "--shading",
        "none",
        "--time",
        "2015-01-19T00:00:00Z",
        "--altitude",
        "300",
        "--lat",
        "0",
        "--lon",
        "0",
        "--accommodation",
        "langmuir",
        "--aoa",
        "0,30",
        "--aos",
        "10",
    ]
    code, _, err = run(capsys, *common, "--out", tmp_path / "fc.npz")
    assert code == 0, err
    db = load_database(tmp_path / "fc.npz")
    alpha = db.metadata["conditions"]["alpha"]
    assert 0.9 < alpha < 1.0
    assert (
        db.metadata["materials"]["default"]["alpha"]
        == alpha
        == db.metadata["materials"]["default"]["alpha_n"]
    )
    assert main(["coeff", *common, "--json"]) == 0
    rows = json.loads(capsys.readouterr()[0])
    for k, row in enumerate(rows):
        assert row["CD"] == pytest.approx(db.CD[k, 0], rel=1e-13)
        np.testing.assert_allclose(row["Cm_B"], db.Cm_B[k, 0], rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize(
    "argv,needle",
    [
        (["--workers", "0"], "--workers"),
        (["--aoa", "0:0:10"], "--aoa"),
        (["--aoa", "0,10,10"], "--aoa: angle 10 deg is given twice"),
        (["--aos", "0:10:100"], "--aos: angles must lie in [-90, 90]"),
        (["--out", "/nonexistent-dir/db.npz"], "--out: directory /nonexistent-dir does not exist"),
        (["--out", "DIR/db.txt"], "--out: the database file must end in .npz"),
        (["--csv", "/nonexistent-dir/db.csv"], "--csv: directory"),
        (["--samples", "0"], "--samples"),
        (["--gsim", "cll"], "--species"),
    ],
)
def test_bad_values_give_one_line_and_status_2(capsys, mesh_file, tmp_path, argv, needle):
    argv = [a.replace("DIR", str(tmp_path)) for a in argv]
    if "--out" not in argv:
        argv += ["--out", str(tmp_path / "db.npz")]
    try:
        code = main(["database", str(mesh_file), "--aoa", "0", "--aos", "0", *FLOW, *argv])
    except SystemExit as exc:  # argparse's own errors
        code = exc.code
    err = capsys.readouterr()[1]
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0], err
    assert not (tmp_path / "db.npz").exists()


def test_module_entry_point(mesh_file, tmp_path):
    """`python -m adbsat_ros.cli database` runs as a separate process."""
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "adbsat_ros.cli",
            "database",
            str(mesh_file),
            *FLOW,
            "--aoa",
            "0,90",
            "--aos",
            "0",
            "--shading",
            "none",
            "--out",
            str(tmp_path / "p.npz"),
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == ""  # no progress bar when stderr is not a terminal
    assert load_database(tmp_path / "p.npz").shape == (2, 1)


def test_more_workers_than_cpus_are_capped_with_a_warning(capsys, mesh_file, tmp_path):
    out = tmp_path / "capped.npz"
    code, _, err = run(
        capsys, mesh_file, *FLOW, "--aoa=0:30:60", "--aos=0", "--workers", "1000", "--out", out
    )
    cpus = usable_cpus()
    assert code == 0 and out.is_file()
    assert f"warning: --workers: 1000 workers asked for, {cpus} used" in err


def test_a_test_particle_database_agrees_with_coeff(capsys, tmp_path):
    """database --method tpmc: the summary says so, the metadata records the run, and an
    attitude equals `coeff --method tpmc` with that attitude's seed."""
    from adbsat_ros.database.build import attitude_seed

    out = tmp_path / "tp.npz"
    argv = ["database", "intake-box", *FLOW, "--method", "tpmc", "--particles", "30000"]
    assert main([*argv, "--aoa", "0,10,20", "--aos", "0", "--seed", "4", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "test particles (every reflection)" in text and "with 3 standard errors" in text
    db = load_database(out)
    assert db.metadata["solver"]["method"] == "tpmc"
    seed = attitude_seed(4, 1)  # aoa 10 deg, the second attitude
    args = ["coeff", "intake-box", *FLOW, "--method", "tpmc", "--particles", "30000"]
    assert main([*args, "--aoa", "10", "--seed", str(seed), "--json"]) == 0
    row = json.loads(capsys.readouterr().out)[0]
    np.testing.assert_array_equal(db.Cf_G[1, 0], row["Cf_G"])
    assert main([*argv[:-4], "--gsim", "newton", "--method", "tpmc", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "has no test-particle kernel" in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize(
    "signum, method", [("SIGINT", "tpmc"), ("SIGTERM", "panel")], ids=["SIGINT-tpmc", "SIGTERM"]
)
def test_a_signal_stops_the_build_keeping_the_attitudes_done(tmp_path, signum, method):
    """Ctrl-C (to the whole process group) or SIGTERM mid-build: the command ends before the
    grid is done with one line and status 1; the attitudes done are in NAME.PARTIAL.csv, no
    database is written under the final names, no traceback."""
    import csv as csv_module
    import os
    import signal
    import time

    from signal_probes import ignores
    from waiting import HANG_TIMEOUT, child_pids, wait_for

    # The signal comes once the workers run (they are the command's child processes), and some
    # time later for the first attitudes to be done; a machine too loaded to have done one by
    # then gets a longer time in the next attempt (the grid is far too long to finish meanwhile).
    for attempt, later in enumerate((3.0, 10.0, 30.0)):
        out_dir = tmp_path / str(attempt)
        out_dir.mkdir()
        cmd = [sys.executable, "-m", "adbsat_ros.cli", "database", "example", *FLOW]
        cmd += ["--aos", "-90:1:90", "--out", str(out_dir / "db.npz"), "--workers", "2"]
        if method == "tpmc":
            cmd += ["--method", "tpmc", "--particles", "1e6", "--aos", "0"]
        proc = subprocess.Popen(
            cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True
        )
        assert wait_for(lambda: child_pids(proc.pid), proc), "no worker process started"
        # the workers leave a stop to the command (set up as they start): a Dask worker killed by
        # a stop to the group would be started again by its nanny, and log the closing scheduler
        assert wait_for(
            lambda: all(ignores(p, signal.SIGTERM) for p in child_pids(proc.pid)), proc
        ), "a worker dies of SIGTERM"
        time.sleep(later)
        assert proc.poll() is None, "the build ended before the signal"
        os.killpg(proc.pid, getattr(signal, signum))
        out, err = proc.communicate(timeout=HANG_TIMEOUT)
        assert proc.returncode == 1 and "Traceback" not in err, err
        lines = err.strip().splitlines()
        assert len(lines) == 1 and "stopped by a signal after" in lines[0], err
        assert "PARTIAL" in lines[0]
        done, total = (
            int(x) for x in lines[0].split("after ")[1].split(" attitudes")[0].split(" of ")
        )
        if done > 0:
            break
    assert 0 < done < total
    assert not (out_dir / "db.npz").exists() and not (out_dir / "db.csv").exists()
    with open(out_dir / "db.PARTIAL.csv", encoding="utf-8") as stream:
        rows = list(csv_module.reader(line for line in stream if not line.startswith("#")))
    assert len(rows) - 1 == done  # a header, then one row per attitude done
    assert all(np.isfinite([float(x) for x in row]).all() for row in rows[1:])


def test_a_urdf_database_at_joint_positions_agrees_with_coeff(capsys, tmp_path):
    """database MESH.urdf --joint: the body posed there (ray-cast shading, one wing turned), the
    same numbers as coeff at those joints, and the joints in the mesh spec."""
    out = tmp_path / "wings.npz"
    joints = ["--joint", "wing_left_hinge=40", "--joint", "wing_right_hinge=-15"]
    argv = ["example-articulated", *FLOW, *joints, "--aoa", "0,30", "--aos", "0,20"]
    code, _, _ = run(capsys, *argv, "--out", out)
    assert code == 0
    db = load_database(out)
    assert db.metadata["mesh"]["joints"]["wing_left_hinge"] == pytest.approx(np.radians(40.0))
    model, _ = model_from_metadata(db.metadata, out)  # the posed body reloads
    assert model.mesh.fingerprint() == db.metadata["mesh"]["fingerprint"]
    assert main(["coeff", *argv[:-4], "--aoa", "30", "--aos", "20", "--json"]) == 0
    row = json.loads(capsys.readouterr().out)[0]
    np.testing.assert_allclose(db.Cf_G[1, 1], row["Cf_G"], rtol=1e-12, atol=1e-15)
    assert (
        main(["coeff", "example-articulated", *FLOW, "--aoa", "30", "--aos", "20", "--json"]) == 0
    )
    flat = json.loads(capsys.readouterr().out)[0]
    assert not np.allclose(db.Cf_G[1, 1], flat["Cf_G"], rtol=1e-3)
