"""``--overwrite`` (and the database's outputs, replaced without it) replace only what the
command wrote: a file of the user at an output path survives, and the command refuses in one line
naming it; an earlier output of the same command is replaced."""

from __future__ import annotations

from pathlib import Path

import pytest
from rosbags.rosbag2 import Reader

from adbsat_ros.cli import main


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def contents(path: Path) -> dict:
    return {str(p.relative_to(path)): p.read_bytes() for p in path.rglob("*") if p.is_file()}


def simulate(capsys, out, *more, duration=10):
    argv = ["simulate", "--duration", duration, "--rate", 2, "--state-rate", 1, "--out", out]
    return run(capsys, *argv, *more)


def user_directory(path: Path) -> Path:
    path.mkdir()
    (path / "keep.txt").write_text("x")
    return path / "keep.txt"


def assert_refused(code, err, keep: Path, status: int):
    assert code == status, err
    assert str(keep) in err and "remove it yourself" in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert keep.read_text() == "x" and sorted(p.name for p in keep.parent.iterdir()) == ["keep.txt"]


def messages(bag: Path) -> int:
    with Reader(bag) as reader:
        return reader.message_count


def test_simulate_overwrite_replaces_a_bag_only(tmp_path, capsys):
    keep = user_directory(tmp_path / "d")
    code, _, err = simulate(capsys, tmp_path / "d", "--overwrite")
    assert_refused(code, err, keep, 2)
    out = tmp_path / "sim"
    assert simulate(capsys, out)[0] == 0
    before = messages(out)
    code, _, err = simulate(capsys, out, "--overwrite", duration=20)
    assert code == 0, err
    assert messages(out) > before  # (the longer flight's bag took its place)
    (out / "notes.txt").write_text("x")
    code, _, err = simulate(capsys, out, "--overwrite")
    assert code == 2 and f"holds {out / 'notes.txt'}, which is not part of a rosbag2 bag" in err
    assert (out / "notes.txt").read_text() == "x" and messages(out) > before


@pytest.fixture
def flight(tmp_path, capsys):
    assert simulate(capsys, tmp_path / "sim")[0] == 0
    return tmp_path / "sim"


@pytest.mark.parametrize("option", ["--out", "--plots"])
def test_bag_analyze_overwrite_refuses_a_directory_of_the_user(flight, tmp_path, capsys, option):
    keep = user_directory(tmp_path / "d")
    argv = ["bag", "analyze", flight, "--workers", 1, "--overwrite"]
    argv += [option, keep.parent] + (["--out", tmp_path / "a"] if option == "--plots" else [])
    code, _, err = run(capsys, *argv)
    assert_refused(code, err, keep, 1)


def test_bag_analyze_overwrite_replaces_its_outputs_only(flight, tmp_path, capsys):
    out, plots, table = tmp_path / "a", tmp_path / "plots", tmp_path / "a.csv"
    argv = ["bag", "analyze", flight, "--workers", 1, "--out", out, "--plots", plots]
    assert run(capsys, *argv)[0] == 0
    (plots / "force.png").write_bytes(b"not a png")
    old = contents(plots)
    code, _, err = run(capsys, *argv, "--overwrite")
    assert code == 1 and f"holds {plots / 'force.png'}, which is not part of the PNGs" in err
    assert contents(plots) == old
    (plots / "force.png").unlink()
    code, _, err = run(capsys, *argv, "--overwrite")
    assert code == 0, err
    assert sorted(p.name for p in plots.iterdir()) == [
        "density.png",
        "drag_coefficient.png",
        "force.png",
        "torque.png",
    ]
    table.write_text("my,own,table\n")
    code, _, err = run(capsys, *argv, "--overwrite")
    assert code == 1 and f"output CSV {table}: is not a CSV file of bag analyze" in err
    assert table.read_text() == "my,own,table\n"


def test_bag_analyze_never_replaces_its_input(flight, capsys):
    before = contents(flight)
    for source in (flight, flight / "sim.mcap"):
        argv = ["bag", "analyze", source, "--out", flight, "--no-plots", "--overwrite"]
        code, _, err = run(capsys, *argv)
        assert code == 1 and "holds the input bag" in err
        assert contents(flight) == before


DATABASE = ["database", "example", "--aoa", "0,10", "--aos", "0", "--speed", 7700]
DATABASE += ["--temperature", 900, "--mean-mass", 16, "--workers", 1]


def test_database_replaces_its_own_files_only(tmp_path, capsys):
    out, table = tmp_path / "db.npz", tmp_path / "db.csv"
    table.write_text("x")  # (the CSV's default name, beside --out)
    code, _, err = run(capsys, *DATABASE, "--out", out)
    assert code == 2 and f"{table} is not an output of adbsat-ros database" in err
    assert table.read_text() == "x" and not out.exists()
    table.unlink()
    (tmp_path / "keep.txt").write_text("x")
    for option, path in (("--out", tmp_path / "d.npz"), ("--csv", tmp_path / "d.csv")):
        keep = user_directory(path)
        code, _, err = run(capsys, *DATABASE, "--out", out, option, path)
        assert code == 2 and f"{path} is not an output of adbsat-ros database; " in err
        assert f"choose another {option}" in err and keep.read_text() == "x"
    assert run(capsys, *DATABASE, "--out", out)[0] == 0
    first = out.read_bytes(), table.read_bytes()
    code, _, err = run(capsys, *DATABASE[:3], "0,20", *DATABASE[4:], "--out", out)
    assert code == 0, err
    assert (out.read_bytes(), table.read_bytes()) != first and "20,0," in table.read_text()
