"""What the command line imports at start-up, and the top-level API loaded on first use.

Each check runs in a fresh interpreter, since this test process has long imported everything.
"""

import json
import subprocess
import sys

import pytest

#: Heavy packages the command line must not import before a subcommand needs them.
HEAVY = (
    "numpy",
    "matplotlib",
    "rosbags",
    "trimesh",
    "yourdfpy",
    "scipy",
    "embreex",
    "nrlmsise00",
    "rclpy",
)


def imported_after(code: str) -> dict:
    """Run ``code`` in a fresh interpreter; which HEAVY packages and adbsat_ros modules it left.

    ``code`` may raise SystemExit (as ``--help`` does); the report is printed at exit.
    """
    wrapper = (
        "import atexit, json, sys\n"
        "def report():\n"
        "    heavy = sorted(n for n in %r if n in sys.modules)\n"
        "    ours = sorted(n for n in sys.modules if n.startswith('adbsat_ros'))\n"
        "    sys.__stdout__.write('\\nREPORT' + json.dumps({'heavy': heavy, 'ours': ours}))\n"
        "atexit.register(report)\n" % (HEAVY,)
    )
    proc = subprocess.run(
        [sys.executable, "-c", wrapper + code], capture_output=True, text=True, timeout=120
    )
    assert "REPORT" in proc.stdout, proc.stderr
    return json.loads(proc.stdout.rsplit("REPORT", 1)[1])


def test_importing_the_package_and_the_cli_imports_no_heavy_package():
    report = imported_after("import adbsat_ros, adbsat_ros.cli\nassert adbsat_ros.__version__")
    assert report["heavy"] == []


def test_help_imports_no_subcommand_module_and_no_heavy_package():
    report = imported_after("from adbsat_ros.cli import main\nmain(['--help'])")
    assert report["heavy"] == []
    assert report["ours"] == [
        "adbsat_ros",
        "adbsat_ros._version",
        "adbsat_ros.bounds",  # (the ranges of the options: the standard library only)
        "adbsat_ros.cli",
        "adbsat_ros.cli.options",
        "adbsat_ros.processes",  # (signals handled from the start: the standard library only)
    ]


def test_a_subcommand_imports_what_it_needs_and_not_the_others_needs(tmp_path):
    """The check can fail: coeff does import numpy and trimesh, but not rosbags or matplotlib."""
    code = (
        "from adbsat_ros.cli import main\n"
        "main(['coeff', 'example', '--shading', 'none', '--speed', '7700',"
        " '--temperature', '900', '--mean-mass', '16'])\n"
    )
    report = imported_after(code)
    assert {"numpy", "trimesh", "scipy"} <= set(report["heavy"])
    assert not {"rosbags", "matplotlib", "rclpy"} & set(report["heavy"])
    assert "adbsat_ros.cli.bag" not in report["ours"]


def test_public_names_resolve_to_the_documented_objects_of_the_subpackages():
    import adbsat_ros

    names = [name for name in adbsat_ros.__all__ if name != "__version__"]
    for expected in (
        "load_mesh",
        "PanelMethod",
        "FreeStream",
        "flight_conditions",
        "FlightConditions",
        "AeroWrenchEstimator",
        "CoefficientLookup",
        "load_database",
        "build_database",
        "ShadingCache",
        "MeshError",
    ):
        assert expected in names
    for name in names:
        value = getattr(adbsat_ros, name)
        assert getattr(value, "__module__", "").startswith("adbsat_ros.") or name == "MODELS"
        if callable(value):
            assert value.__doc__ and value.__doc__.strip(), name
    from adbsat_ros.physics.panel_method import PanelMethod

    assert adbsat_ros.PanelMethod is PanelMethod
    from adbsat_ros import AeroWrenchEstimator, CoefficientLookup  # the import statement works

    assert CoefficientLookup.__module__ == "adbsat_ros.database.lookup"
    assert AeroWrenchEstimator.__module__ == "adbsat_ros.estimator.estimator"


def test_dir_lists_the_public_names_before_they_are_loaded():
    code = (
        "import sys, adbsat_ros\n"
        "listed = dir(adbsat_ros)\n"
        "assert all(name in listed for name in adbsat_ros.__all__), listed\n"
        "assert 'numpy' not in sys.modules\n"
        "namespace = {}\n"
        "exec('from adbsat_ros import *', namespace)\n"
        "assert set(adbsat_ros.__all__) <= set(namespace)\n"
        "assert 'PanelMethod' in vars(adbsat_ros)  # kept once loaded\n"
        "print('ok')\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.stdout.strip() == "ok", proc.stderr


def test_an_unknown_name_is_an_attribute_error_naming_it():
    import adbsat_ros

    with pytest.raises(AttributeError, match="NoSuchThing"):
        adbsat_ros.NoSuchThing  # noqa: B018


def test_unknown_or_missing_subcommand_is_one_line_and_status_2(capsys):
    from adbsat_ros.cli import main

    for argv, needle in ((["coef"], "invalid choice: 'coef'"), ([], "required: COMMAND")):
        with pytest.raises(SystemExit) as exit_info:
            main(argv)
        err = capsys.readouterr().err
        assert exit_info.value.code == 2
        assert needle in err and len(err.strip().splitlines()) == 1, err


def test_verbose_flag_before_the_subcommand(capsys):
    from adbsat_ros.cli import main

    argv = ["-v", "coeff", "example", "--shading", "none", "--speed", "7700"]
    argv += ["--temperature", "900", "--mean-mass", "16", "--json"]
    assert main(argv) == 0
    assert json.loads(capsys.readouterr().out)[0]["aoa_deg"] == 0.0


def test_version(capsys):
    from adbsat_ros import __version__
    from adbsat_ros.cli import main

    with pytest.raises(SystemExit) as exited:
        main(["--version"])
    assert exited.value.code == 0
    assert capsys.readouterr().out.strip() == f"adbsat-ros {__version__}"


def test_the_bundled_params_files_are_valid():
    """config/*.yaml: the node's parameters file and the examples the docs use (bag analysis'
    --params), each read as the node and bag analysis read them."""
    from pathlib import Path

    from adbsat_ros.estimator.settings import settings_from_file

    files = sorted((Path(__file__).resolve().parents[2] / "config").glob("*.yaml"))
    assert {f.name for f in files} >= {"adbsat.yaml", "fixed_alpha.yaml", "langmuir.yaml"}
    settings = {f.stem: settings_from_file(f) for f in files}
    assert settings["langmuir"].accommodation_model == "langmuir"
    assert (
        settings["fixed_alpha"].accommodation_model == "fixed"
        and settings["fixed_alpha"].alpha == 1.0
    )


def test_coeff_on_a_stored_mesh_imports_no_trimesh_and_no_scipy(tmp_path):
    """A mesh file loaded before: ``coeff`` of one attitude (its body, model and shader set up)
    reads it back from the store and imports neither trimesh nor yourdfpy, nor scipy (erf by the
    math module)."""
    import trimesh

    path = tmp_path / "sphere.stl"
    trimesh.creation.icosphere(subdivisions=2).export(path)
    code = (
        "import os\n"
        f"os.environ['ADBSAT_ROS_CACHE_DIR'] = {str(tmp_path / 'cache')!r}\n"
        "from adbsat_ros.cli import main\n"
        f"main(['coeff', {str(path)!r}, '--speed', '7700', '--temperature', '900',"
        " '--mean-mass', '16'])\n"
    )
    first, again = imported_after(code), imported_after(code)
    assert "trimesh" in first["heavy"] and "adbsat_ros.cli.coeff" in again["ours"]
    assert {"numpy", "embreex"} <= set(again["heavy"])
    assert not {"trimesh", "yourdfpy", "scipy"} & set(again["heavy"])
