"""A sweep's sizes and its moment point: refused before any work (no store made), with the
name, the value and the range or the memory estimate, by the command line in one line and
exit status 2."""

from __future__ import annotations

import pytest
import yaml

from adbsat_ros import bounds
from adbsat_ros.cli import main
from adbsat_ros.sweep import engine
from adbsat_ros.sweep.spec import SpecError, parse_spec

BASE = {"mesh": "example", "shading": "none", "axes": {"aoa": "0:30:60", "aos": [0, 20]}}


def run_spec(tmp_path, capsys, data) -> str:
    """Run ``data`` as a sweep on one worker; assert status 2, one line, no store; the line."""
    path = tmp_path / "spec.yaml"
    path.write_text(yaml.safe_dump(data))
    out = tmp_path / "out.zarr"
    code = main(["sweep", str(path), "--out", str(out), "--workers", "1", "--no-progress"])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert not out.exists()
    return err


def test_a_grid_of_billions_of_points_is_refused_at_once():
    axes = {"aoa": "-180:0.01:180", "aos": "-90:0.01:90", "alpha": "0:0.01:1"}
    with pytest.raises(SpecError) as caught:
        parse_spec({**BASE, "axes": axes}, "")
    rule = bounds.BOUNDS["sweep_points"]
    text = str(caught.value)
    assert text.startswith(f"axes: the points (36001 x 18001 x 101) must be in {rule.text()}")
    assert text.endswith(f"got {36001 * 18001 * 101}")


def test_an_axis_of_too_many_values_is_refused_before_they_are_made():
    with pytest.raises(SpecError, match=r"^axes.aoa: the values of '0:1e-9:360' must be in \["):
        parse_spec({**BASE, "axes": {"aoa": "0:1e-9:360"}}, "")


def test_a_moment_point_is_a_point_of_the_body(tmp_path, capsys):
    with pytest.raises(SpecError, match=r"^reference.moment_point x must be in \[-1000, 1000\] m"):
        parse_spec({**BASE, "reference": {"moment_point": [1e300, 0, 0]}}, "")
    far = {**BASE, "reference": {"moment_point": [0, 0, 100]}}  # (within 1 km, not the body's)
    err = run_spec(tmp_path, capsys, far)
    assert "error: reference.moment_point z must be in [" in err and "body" in err


def test_a_sweep_larger_than_the_memory_is_refused_with_its_estimate(tmp_path, capsys, monkeypatch):
    spec = parse_spec(BASE, "")
    what, estimate = engine.memory_estimate(spec)
    assert what == "the sweep of 6 points in 1 chunks of 256 points" and estimate > 0
    monkeypatch.setattr(bounds, "available_memory", lambda: int(estimate) - 1)
    err = run_spec(tmp_path, capsys, BASE)
    assert f"error: {what} needs about" in err and "more than the" in err
