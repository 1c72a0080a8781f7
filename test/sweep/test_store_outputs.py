"""A sweep store's creation and replacement: a run killed at any step of making the store leaves
one the next run finishes, equal file for file to an uninterrupted run's; ``--overwrite``
replaces a sweep store only, and refuses anything else at ``--out`` by name."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import yaml
import zarr.storage

from adbsat_ros.cli import main
from adbsat_ros.sweep.engine import run_sweep
from adbsat_ros.sweep.evaluate import SweepSetup
from adbsat_ros.sweep.spec import parse_spec
from adbsat_ros.sweep.store import StoreError, SweepStore

SMALL = {
    "mesh": "example",
    "model": "sentman",
    "shading": "none",
    "fixed": {"temperature": 900, "mean_mass_amu": 16, "speed": 7500},
    "axes": {"aoa": [0, 30], "aos": [0, 10]},
    "chunk_points": 2,
}


def spec_of(data):
    return parse_spec(data, yaml.safe_dump(data, sort_keys=False))


def files(path: Path) -> dict:
    """Every file under ``path`` by relative name, with its bytes."""
    return {
        str(p.relative_to(path)): p.read_bytes() for p in sorted(path.rglob("*")) if p.is_file()
    }


def copy_if_there(source, target):
    """shutil.copy2, passing over a file that is gone meanwhile."""
    try:
        shutil.copy2(source, target)
    except FileNotFoundError:
        pass


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The files of an uninterrupted run's store."""
    out = tmp_path_factory.mktemp("reference") / "r.zarr"
    report = run_sweep(spec_of(SMALL), out, workers=1)
    assert report.computed == report.chunks == 2
    return files(out)


def test_a_sweep_killed_at_any_step_of_making_its_store_resumes_to_the_same_store(
    reference, tmp_path, monkeypatch
):
    """What is on disk before each write of the store's creation, and after it, is what a kill
    there leaves: from each, the next run makes the store an uninterrupted run makes."""
    spec = spec_of(SMALL)
    made = tmp_path / "made"
    made.mkdir()
    states = []

    def snapshot():
        # (zarr writes several files at once: one may be renamed while this copies; what a
        # kill leaves then is the copy without it)
        state = tmp_path / f"state{len(states)}"
        shutil.copytree(made, state, copy_function=copy_if_there)
        states.append(state)

    write = zarr.storage.LocalStore._set

    async def recorded(self, key, value, **options):
        snapshot()
        return await write(self, key, value, **options)

    with monkeypatch.context() as patch:
        patch.setattr(zarr.storage.LocalStore, "_set", recorded)
        SweepStore.open(made / "r.zarr", spec, SweepSetup(spec))
    snapshot()
    assert len(states) > 10  # (the group, every array's layout, the coordinates)
    outcomes = {}  # (states alike at the store's path behave alike: one of each runs)
    for state in states:
        at_path = state / "r.zarr"
        outcomes.setdefault(str(files(at_path)) if at_path.exists() else None, state)
    for state in outcomes.values():
        report = run_sweep(spec, state / "r.zarr", workers=1)
        assert not report.stopped and report.already_done == 0, state.name
        assert files(state / "r.zarr") == reference, state.name


def test_an_unfinished_store_of_an_older_version_is_made_again(reference, tmp_path):
    """A store with the spec's attributes but not every array (what a kill left before the
    store was made whole) is this spec's unfinished start: the next run completes it."""
    spec = spec_of(SMALL)
    out = tmp_path / "r.zarr"
    SweepStore.open(out, spec, SweepSetup(spec))
    shutil.rmtree(out / "Cf_G")
    shutil.rmtree(out / "chunk_done")
    report = run_sweep(spec, out, workers=1)
    assert report.computed == report.chunks == 2
    assert files(out) == reference


@pytest.fixture
def spec_path(tmp_path):
    path = tmp_path / "ok.yaml"
    path.write_text(yaml.safe_dump(SMALL, sort_keys=False))
    return path


def test_overwrite_refuses_a_directory_that_is_not_a_sweep_store(spec_path, tmp_path, capsys):
    out = tmp_path / "d"
    out.mkdir()
    (out / "keep.txt").write_text("x")
    for more in ([], ["--overwrite"]):
        code = main(["sweep", str(spec_path), "--out", str(out), "--workers", "1", *more])
        _, err = capsys.readouterr()
        assert code == 2, err
        assert f"{out / 'keep.txt'} is not an output of adbsat-ros sweep" in err
        assert "Traceback" not in err and len(err.strip().splitlines()) == 1
        assert (out / "keep.txt").read_text() == "x"
        assert sorted(p.name for p in out.iterdir()) == ["keep.txt"]


def test_overwrite_refuses_a_sweep_store_holding_a_file_of_the_user(spec_path, tmp_path, capsys):
    out = tmp_path / "r.zarr"
    assert main(["sweep", str(spec_path), "--out", str(out), "--workers", "1"]) == 0
    (out / "CD" / "notes.txt").write_text("mine")
    (out / "zarr.json.bak").write_text("mine")
    before = files(out)
    for name in ("zarr.json.bak", "CD/notes.txt"):
        code = main(["sweep", str(spec_path), "--out", str(out), "--workers", "1", "--overwrite"])
        _, err = capsys.readouterr()
        assert code == 2 and f"{out / name} is not an output of adbsat-ros sweep" in err
        assert files(out) == before
        (out / name).unlink()
        del before[name]


def test_overwrite_replaces_a_sweep_store(spec_path, reference, tmp_path, capsys):
    """Another spec's store is refused without --overwrite and replaced with it; so is the
    same spec's (computed again); nothing is left beside it."""
    out = tmp_path / "r.zarr"
    other = tmp_path / "other.yaml"
    other.write_text(yaml.safe_dump({**SMALL, "model": "cook"}))
    assert main(["sweep", str(other), "--out", str(out), "--workers", "1"]) == 0
    code = main(["sweep", str(spec_path), "--out", str(out), "--workers", "1"])
    _, err = capsys.readouterr()
    assert code == 2 and "holds another spec's sweep" in err
    for _ in range(2):
        code = main(["sweep", str(spec_path), "--out", str(out), "--workers", "1", "--overwrite"])
        out_text, err = capsys.readouterr()
        assert code == 0, err
        assert "0 already in" in out_text
        assert files(out) == reference
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ok.yaml", "other.yaml", "r.zarr"]


def test_a_file_or_a_foreign_zarr_store_is_refused(tmp_path):
    spec = spec_of(SMALL)
    path = tmp_path / "file.zarr"
    path.write_text("not a store")
    with pytest.raises(StoreError, match="file.zarr is not an output of adbsat-ros sweep"):
        run_sweep(spec, path, workers=1, overwrite=True)
    assert path.read_text() == "not a store"
    foreign = tmp_path / "foreign.zarr"
    zarr.open_group(str(foreign), mode="w").attrs["title"] = "someone else's"
    with pytest.raises(StoreError, match="foreign.zarr is not an output of adbsat-ros sweep"):
        run_sweep(spec, foreign, workers=1, overwrite=True)
    assert (foreign / "zarr.json").is_file()


def test_a_new_store_follows_the_umask(tmp_path):
    """The store is made under a temporary name (mkdtemp's 0700, zarr's writer makes it again) and
    renamed: its mode is what the user's umask gives a new directory."""
    import os
    import stat

    spec = spec_of(SMALL)
    old = os.umask(0o027)
    try:
        SweepStore.open(tmp_path / "r.zarr", spec, SweepSetup(spec))
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "r.zarr").stat().st_mode) == 0o750


def test_a_new_store_reads_in_xarray_as_the_sweep_with_nothing_computed(tmp_path):
    """The layout written with zarr alone is the Dataset xarray reads: the axes as coordinates
    with their units, every result NaN along the spec's dimensions, no chunk done."""
    import numpy as np
    import xarray as xr

    data = {**SMALL, "axes": {**SMALL["axes"], "alpha": [0.5, 1.0]}}
    spec = spec_of(data)
    SweepStore.open(tmp_path / "new.zarr", spec, SweepSetup(spec))
    ds = xr.open_zarr(tmp_path / "new.zarr", consolidated=False)
    assert list(ds.sizes) == ["aoa", "aos", "alpha", "component", "chunk"]
    assert ds["aoa"].values.tolist() == [0.0, 30.0] and ds["aoa"].attrs["units"] == "deg"
    assert ds["Cf_G"].dims == ("aoa", "aos", "alpha", "component")
    assert ds["Cf_G"].attrs["component"] == "x, y, z" and ds["density"].attrs["units"] == "kg/m^3"
    assert ds["CD"].dtype == np.float64 and np.isnan(ds["CD"].values).all()
    assert ds["chunk_done"].values.tolist() == [0, 0, 0, 0]
    assert ds.attrs["spec_fingerprint"] == spec.fingerprint
