"""The `adbsat-ros coeff` command: output, ranges, and one-line errors with exit status 2."""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from adbsat_ros import FreeStream, PanelMethod, load_mesh
from adbsat_ros.cli import main
from adbsat_ros.cli.options import CommandLineError, parse_angle_list

FLOW = ["--speed", "7700", "--temperature", "900", "--mean-mass", "16"]


def run_cli(capsys, *argv):
    code = main(["coeff", *argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def box_file(tmp_path_factory):
    import trimesh

    path = tmp_path_factory.mktemp("mesh") / "box.stl"
    box = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    box.apply_translation((0.2, 0.0, 0.0))
    box.export(path)
    return path


def test_angle_lists_and_ranges():
    assert parse_angle_list("0,10,20:5:30", "--aoa").tolist() == [0, 10, 20, 25, 30]
    assert parse_angle_list("-180:90:180", "--aoa").tolist() == [-180, -90, 0, 90, 180]
    assert parse_angle_list("10:-5:0", "--aoa").tolist() == [10, 5, 0]
    for bad in ("a", "1:2", "0:0:5", "0:-1:5", "1,,2", "nan"):
        with pytest.raises(CommandLineError, match="--aoa"):
            parse_angle_list(bad, "--aoa")


def test_json_has_one_object_per_attitude_pair(capsys, box_file):
    code, out, _ = run_cli(
        capsys,
        str(box_file),
        "--shading",
        "none",
        "--aoa",
        "0:30:60",
        "--aos",
        "0,10",
        "--density",
        "1e-11",
        "--moment-ref",
        "0.2,0,0",
        "--json",
        *FLOW,
    )
    assert code == 0
    data = json.loads(out)
    assert [(d["aoa_deg"], d["aos_deg"]) for d in data] == [
        (a, b) for a in (0, 30, 60) for b in (0, 10)
    ]
    for key in (
        "Cf_w",
        "Cf_f",
        "Cm_B",
        "Aref",
        "Lref",
        "AreaProj",
        "CD",
        "CL",
        "CY",
        "force_N",
        "torque_Nm",
    ):
        assert key in data[0]
    # the same numbers as the Python API
    method = PanelMethod(load_mesh(box_file), "sentman", reference=None)
    flow = FreeStream(7700.0, 900.0, mean_mass_amu=16.0, density=1e-11)
    ref = method.coefficients(flow, math.radians(30), math.radians(10))
    assert np.allclose(data[3]["Cf_w"], ref.Cf_w, rtol=1e-12)
    assert data[3]["Aref"] == pytest.approx(3.0) and data[3]["Lref"] == pytest.approx(1.0)
    # force in newtons = q Aref Cf_G
    q = 0.5 * 1e-11 * 7700.0**2
    assert np.allclose(data[3]["force_N"], q * 3.0 * np.asarray(data[3]["Cf_G"]))
    # a cube centred on the moment point has no moment at aoa = aos = 0
    assert np.allclose(data[0]["Cm_B"], 0.0, atol=1e-12)


def test_table_output(capsys, box_file):
    code, out, _ = run_cli(
        capsys, str(box_file), "--shading", "none", "--gsim", "newton", "--aoa", "0", *FLOW
    )
    assert code == 0
    lines = out.strip().splitlines()
    assert lines[2].split()[:3] == ["aoa", "aos", "CD"]
    # Newton cube head-on: C_D = 2 * 1 m^2 / Aref(3 m^2)
    assert float(lines[3].split()[2]) == pytest.approx(2.0 / 3.0, abs=1e-5)


@pytest.mark.parametrize(
    "argv,needle",
    [
        (["--gsim", "nope"], "--gsim"),
        (["--alpha", "1.5"], "--alpha"),
        (["--speed", "-3"], "--speed"),
        (["--aoa", "0:0:10"], "--aoa"),
        (["--moment-ref", "1,2"], "--moment-ref"),
        (["--shading", "fancy"], "--shading"),
        (["--species", "Xe=1e12"], "--species"),
        (["--gsim", "cll"], "--species"),
        (["--material", "nothere:alpha=0.5"], "--material"),
        (["--material", "default:beta=0.5"], "--material"),
        (["--method", "tpmc", "--gsim", "newton"], "has no test-particle kernel"),
        (["--method", "monte"], "--method"),
        (["--method", "tpmc", "--particles", "0"], "--particles"),
        (["--method", "tpmc", "--particles", "2.5"], "--particles"),
        (["--method", "tpmc", "--tolerance", "1"], "--tolerance"),
        (["--method", "tpmc", "--seed", "-1"], "--seed"),
    ],
)
def test_bad_values_give_one_line_and_status_2(box_file, argv, needle):
    base = [sys.executable, "-m", "adbsat_ros.cli", "coeff", str(box_file), "--shading", "none"]
    flow = [] if "--speed" in argv else FLOW
    proc = subprocess.run(base + flow + argv, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0], proc.stderr


def test_missing_mesh_is_status_2(capsys):
    code, _, err = run_cli(capsys, "missing.obj", *FLOW)
    assert code == 2 and "missing.obj" in err and len(err.strip().splitlines()) == 1
    assert err.startswith("adbsat-ros coeff: error: MESH: ")


def test_flight_conditions_give_the_gas(capsys, box_file):
    """--time/--altitude/--lat/--lon: NRLMSISE-00 gives the gas, as ADBSat's environment path."""
    import datetime as dt

    from adbsat_ros.environment.atmosphere import SpaceWeather
    from adbsat_ros.environment.circular_orbit import flight_conditions_circular_orbit

    code, out, _ = run_cli(
        capsys,
        str(box_file),
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
        "--f107",
        "121.7",
        "--f107a",
        "138.1",
        "--ap",
        "4",
        "--accommodation",
        "langmuir",
        "--json",
    )
    assert code == 0
    data = json.loads(out)[0]
    cond = flight_conditions_circular_orbit(
        dt.datetime(2015, 1, 19),
        300e3,
        0.0,
        0.0,
        SpaceWeather(121.7, 138.1, 4.0),
        accommodation_model="langmuir",
    )
    assert cond.alpha == pytest.approx(0.97, abs=0.02)
    method = PanelMethod(load_mesh(box_file), "sentman")
    flow = cond.free_stream()
    expected = method.coefficients(
        flow, 0.0, 0.0, surface=method.surface_with(alpha=cond.alpha, alpha_n=cond.alpha)
    )
    assert data["CD"] == pytest.approx(expected.drag, rel=1e-12)
    assert data["dynamic_pressure_Pa"] == pytest.approx(
        0.5 * cond.mass_density * cond.speed**2, rel=1e-12
    )
    # alpha < 1 changes the drag: the accommodation model is really used
    full = method.coefficients(flow, 0.0, 0.0)
    assert abs(full.drag - expected.drag) > 1e-4


def test_direct_gas_and_flight_conditions_are_exclusive(capsys, box_file):
    code, _, err = run_cli(
        capsys,
        str(box_file),
        "--time",
        "2015-01-19T00:00:00Z",
        "--altitude",
        "300",
        "--lat",
        "0",
        "--lon",
        "0",
        "--speed",
        "7000",
    )
    assert code == 2 and "--speed" in err


def test_negative_ranges_and_lists_need_no_equals_sign(capsys, box_file):
    """argparse takes "-60:30:60" after an option for an option of its own; the command line joins
    it to --aoa/--aos, so both spellings give the same attitudes, and a plain negative number and
    the other options are left as they are."""
    outputs = []
    for argv in (["--aoa=-60:30:60", "--aos=-10,0"], ["--aoa", "-60:30:60", "--aos", "-10,0"]):
        assert main(["coeff", str(box_file), *FLOW, *argv, "--json"]) == 0
        outputs.append(json.loads(capsys.readouterr()[0]))
    assert outputs[0] == outputs[1]
    assert [(r["aoa_deg"], r["aos_deg"]) for r in outputs[1]] == [
        (a, b) for a in (-60.0, -30.0, 0.0, 30.0, 60.0) for b in (-10.0, 0.0)
    ]
    from adbsat_ros.cli import join_signed_lists

    assert join_signed_lists(["--aoa", "-.5:0.25:0", "--aos", "-5", "--gsim", "-1:2"]) == [
        "--aoa=-.5:0.25:0",
        "--aos",
        "-5",
        "--gsim",
        "-1:2",
    ]


def test_the_two_methods_side_by_side(capsys, box_file):
    """--method both: each method's full record and the test particles' difference from the
    panel method with its error; on a convex box the difference is within three errors."""
    argv = [str(box_file), *FLOW, "--aoa", "0,30", "--method", "both", "--particles", "200000"]
    code, out, err = run_cli(capsys, *argv, "--json")
    assert code == 0, err
    rows = json.loads(out)
    assert [(r["aoa_deg"], r["aos_deg"]) for r in rows] == [(0.0, 0.0), (30.0, 0.0)]
    for r in rows:
        panel, tpmc, diff = r["panel"], r["tpmc"], r["difference"]
        assert tpmc["method"] == "tpmc" and tpmc["particles"] == 4 * 65_536 and tpmc["seed"] == 0
        assert diff["CD"] == pytest.approx(tpmc["CD"] - panel["CD"], abs=1e-15)
        assert diff["CD_error"] == tpmc["CD_error"] > 0.0
        assert abs(diff["CD"]) <= 3.0 * diff["CD_error"]
        assert len(tpmc["Cf_w_error"]) == 3 and "force_N" not in tpmc
    code, out, err = run_cli(capsys, *argv)
    assert code == 0, err
    lines = out.splitlines()
    assert "panel method against test-particle Monte Carlo" in lines[2]
    assert len(lines) == 4 + 2 and "+-" in lines[4]


@pytest.mark.parametrize("signum", ["SIGINT", "SIGTERM"])
def test_a_signal_stops_a_test_particle_run_and_keeps_what_it_traced(signum):
    """Ctrl-C (or SIGTERM) ends a long run after its current block: the JSON of the molecules
    traced so far is written, marked stopped, with one line on stderr and status 1."""
    import signal

    from waiting import HANG_TIMEOUT, child_pids, wait_for

    cmd = [sys.executable, "-m", "adbsat_ros.cli", "coeff", "intake-box", *FLOW]
    cmd += ["--method", "tpmc", "--particles", "1e9", "--workers", "2", "--aoa", "0,10", "--json"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    # the signal comes once the run traces (its worker processes, started while it stops on
    # signals, exist), however long this machine takes to get there; a stop ends the run after
    # its current block of molecules (the run itself is endless)
    assert wait_for(lambda: child_pids(proc.pid), proc), "no worker process started"
    proc.send_signal(getattr(signal, signum))
    out, err = proc.communicate(timeout=HANG_TIMEOUT)
    assert proc.returncode == 1, err
    rows = json.loads(out)
    assert len(rows) == 1 and rows[0]["stopped"] is True  # the second attitude was not run
    assert rows[0]["particles"] % (4 * 65_536) == 0 and rows[0]["particles"] > 0
    assert rows[0]["CD_error"] > 0.0
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "interrupted" in lines[0] and "Traceback" not in err


def test_a_urdf_body_at_given_joint_positions(capsys, tmp_path):
    """MESH may be a URDF with --joint NAME=DEGREES: the articulated example at zero is the rigid
    example; a wing turned 90 deg faces the flow; bad joints are one line with status 2."""
    from adbsat_ros.geometry.example_urdf import example_satellite_urdf

    path = tmp_path / "sat.urdf"
    path.write_text(example_satellite_urdf())
    rows = {}
    for name, argv in {
        "rigid": ["example"],
        "zero": [str(path)],
        "turned": [str(path), "--joint", "wing_left_hinge=90"],
    }.items():
        code, out, err = run_cli(capsys, *argv, *FLOW, "--json")
        assert code == 0, err
        rows[name] = json.loads(out)[0]
    assert rows["zero"]["CD"] == pytest.approx(rows["rigid"]["CD"], rel=1e-12)
    assert "links" not in rows["rigid"]
    turned = rows["turned"]
    assert set(turned["links"]) == {"body", "wing_left", "wing_right"}
    total = np.sum([link["Cf_G"] for link in turned["links"].values()], axis=0)
    np.testing.assert_allclose(total, turned["Cf_G"], rtol=0, atol=1e-13)
    hinge = turned["joints"]["wing_left_hinge"]
    assert hinge["position"] == pytest.approx(math.pi / 2, rel=1e-15)  # SI: radians
    assert hinge["effort_coefficient"] != 0.0 and "torque_Nm" not in hinge  # no density given
    # the turned wing shows its 1.0 m x 0.5 m face instead of its 1.0 m x 0.03 m edge
    assert rows["turned"]["AreaProj"] - rows["zero"]["AreaProj"] == pytest.approx(0.47, rel=1e-9)
    for argv, needle in [
        (["--joint", "wing_left_hinge=200"], "outside its limits"),
        (["--joint", "knee=3"], "joint 'knee' is not a moving joint"),
        (["--joint", "wing_left_hinge"], "expected NAME=VALUE"),
    ]:
        code, _, err = run_cli(capsys, str(path), *FLOW, *argv)
        assert code == 2 and needle in err and len(err.strip().splitlines()) == 1, err
    code, _, err = run_cli(capsys, "example", *FLOW, "--joint", "a=1")
    assert code == 2 and "is no URDF" in err


def test_a_byte_order_mark_before_a_cube_changes_no_coefficient(capsys, tmp_path):
    import trimesh

    cube = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    lines = [f"v {x} {y} {z}" for x, y, z in cube.vertices.tolist()] + ["v 5 5 5"]
    lines += ["f " + " ".join(str(i + 1) for i in face) for face in cube.faces]
    text = "\n".join(lines) + "\n"
    plain, marked = tmp_path / "cube.obj", tmp_path / "cube_marked.obj"
    plain.write_text(text)
    marked.write_bytes(b"\xef\xbb\xbf" + text.replace("\n", "\r\n").encode())
    rows = []
    for path in (plain, marked):
        code, out, err = run_cli(capsys, str(path), "--shading", "none", "--json", *FLOW)
        assert code == 0 and not err, err
        rows.append(json.loads(out)[0])
    assert rows[1]["Aref"] == rows[0]["Aref"] == pytest.approx(3.0)  # half of the 6 m^2
    assert rows[1]["CD"] == rows[0]["CD"] and rows[1]["Cm_B"] == rows[0]["Cm_B"]


def test_a_directory_bad_line_or_far_vertex_is_one_line_and_status_2(capsys, tmp_path):
    far = tmp_path / "far.obj"
    far.write_text("v 1e300 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n")
    short = tmp_path / "short.obj"
    short.write_text("v 0 0 0\nv 0 1\nv 0 0 1\nf 1 2 3\n")
    for mesh, needle in [
        (tmp_path, f"MESH: {tmp_path}: is a directory, not a mesh file"),
        (far, "vertex 0 at (1e+300, 0, 0) m has a coordinate outside [-1e+06, 1e+06] m"),
        (short, f"MESH: {short}, line 2: a vertex has three coordinates x y z"),
    ]:
        code, _, err = run_cli(capsys, str(mesh), *FLOW)
        assert code == 2 and len(err.strip().splitlines()) == 1 and needle in err, err
