"""A sweep's spec: axes as lists or ranges, and every bad field refused with its name (by the
command line too: one line, exit status 2)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbsat_ros.cli import main
from adbsat_ros.geometry.loading import articulated_body
from adbsat_ros.sweep.spec import SpecError, axis_values, load_spec, parse_spec

BASE = {"mesh": "example", "axes": {"aoa": "0:30:60", "aos": [0, 20]}}


def spec(**changes):
    """BASE with ``changes`` (a field changed to None is left out)."""
    data = {k: v for k, v in {**BASE, **changes}.items() if v is not None}
    return parse_spec(data, "")


def test_axes_are_lists_or_inclusive_ranges():
    np.testing.assert_array_equal(axis_values("-10:5:10", "aoa"), [-10, -5, 0, 5, 10])
    np.testing.assert_allclose(axis_values("0:0.1:0.3", "x"), [0.0, 0.1, 0.2, 0.3], atol=1e-15)
    np.testing.assert_array_equal(axis_values([1, 2.5], "x"), [1.0, 2.5])
    np.testing.assert_array_equal(axis_values(7, "x"), [7.0])
    s = spec(axes={"aoa": "0:30:60", "aos": [0, 20], "speed": [7000, 7800]})
    assert s.shape == (3, 2, 2) and list(s.axes) == ["aoa", "aos", "speed"]
    assert spec(axes={"aoa": 5}).shape == (1, 1)  # aos a single 0 when not swept


def test_a_range_of_numbers_below_60_in_a_file_is_a_range_not_a_base_60_number(tmp_path):
    """YAML 1.1 reads ``-10:5:10`` as the base-60 number -36310 (and ``0:5:45.5`` as 345.5): a
    spec file's ranges stay ranges; other scalars read as ``yaml.safe_load`` reads them."""
    path = tmp_path / "spec.yaml"
    path.write_text(
        "mesh: example\naxes:\n  aoa: -10:5:10\n  aos: 0:5:45.5\n"
        "  speed: [7.5e+3, 0x1F40, 8_500]\nchunk_points: 12\n"
    )
    text, data = load_spec(path)
    s = parse_spec(data, text)
    np.testing.assert_array_equal(s.axes["aoa"], [-10, -5, 0, 5, 10])
    np.testing.assert_array_equal(s.axes["aos"], [0, 5, 10, 15, 20, 25, 30, 35, 40, 45])
    np.testing.assert_array_equal(s.axes["speed"], [7500, 8000, 8500])
    assert s.chunk_points == 12 and isinstance(data["chunk_points"], int)


def test_the_fingerprint_changes_with_what_is_swept_only():
    a = spec()
    assert a.fingerprint == parse_spec(dict(BASE), "# another comment\n").fingerprint
    assert a.fingerprint != spec(model="cook").fingerprint
    assert a.fingerprint != spec(axes={"aoa": "0:30:90", "aos": [0, 20]}).fingerprint


@pytest.mark.parametrize(
    "changes, message",
    [
        ({"axes": {"aoa": 0, "altitutde": [300]}}, "axes.altitutde: not an axis; the axes are"),
        ({"axes": {"aoa": 0, "speed": []}}, "axes.speed: empty"),
        ({"axes": {"aoa": 0, "speed": [7000, 30000]}}, r"axes.speed must be in \[1, 20000\] m/s"),
        ({"axes": {"aoa": [0, 400]}}, r"axes.aoa must be in \[-360, 360\] deg"),
        ({"axes": {"aoa": "10:5:0"}}, "axes.aoa: start:step:stop needs a step > 0"),
        ({"axes": {"aoa": [0, 0]}}, "axes.aoa: a value appears twice"),
        ({"axes": {"aoa": 0, "alpha": [0.5, "high"]}}, "axes.alpha: expected numbers"),
        ({"axes": {"aoa": 0, "alpha": [0.5]}, "fixed": {"alpha": 1}}, "axes.alpha: also fixed"),
        ({"fixed": {"speed": -1}}, r"fixed.speed must be in \[1, 20000\] m/s"),
        ({"fixed": {"aoa": 3}}, "fixed.aoa: not an input"),
        ({"axes": {"aoa": 0, "joint.hinge": [0]}}, "axes.joint.hinge: the mesh example is no URDF"),
        ({"model": "newtonian"}, "model: 'newtonian' is not one of"),
        ({"shading": "rays"}, "shading: 'rays' is not one of"),
        ({"chunk_points": 0}, r"chunk_points: a whole number in \[1, 1000000\]"),
        ({"mesh": ""}, "mesh: missing"),
        ({"axes": {}}, "axes: missing"),
        ({"colour": "red"}, "colour: not a spec field"),
        (
            {"fixed": {"altitude": 300}, "axes": {"aoa": 0, "scale.Xe": [1, 2]}},
            "axes.scale.Xe: 'Xe' is not a species of NRLMSISE-00",
        ),
        (
            {"fixed": {"altitude": 300}, "axes": {"aoa": 0, "scale.O": [1, 200]}},
            r"axes.scale.O must be in \[0, 100\]",
        ),
        ({"axes": {"aoa": 0, "scale.O": [1, 2]}}, "scale: species are scaled in the atmosphere"),
        ({"fixed": {"latitude": 10}}, "altitude: the atmosphere's gas .* needs an altitude"),
        (
            {"time": "2099-12-01T00:00:00", "fixed": {"altitude": 300}, "axes": {"time": [0, 1e5]}},
            "axes.time: 100000 h after 2099-12-01T00:00:00 is outside 1958..2100",
        ),
        ({"axes": {"aoa": 0, "mesh": ["example", "cylinder"]}}, "axes.mesh: also the field mesh"),
        (
            {"mesh": None, "axes": {"aoa": 0, "mesh": ["example", "cylinder"]}},
            "reference: mesh variants are compared at one reference area and length",
        ),
        ({"mesh": None, "axes": {"aoa": 0, "mesh": []}}, "axes.mesh: a list of mesh files"),
        ({"solver": {"method": "dsmc"}}, "solver.method: 'dsmc' is not panel or tpmc"),
        (
            {"solver": {"method": "tpmc", "particles": 0}},
            "solver: particles must be a whole number >= 1",
        ),
        ({"solver": {"method": "panel", "seed": 1}}, "solver: particles, tolerance and seed"),
    ],
)
def test_bad_fields_are_refused_by_name(changes, message):
    with pytest.raises(SpecError, match=message):
        spec(**changes)


def test_joint_axes_are_checked_against_the_urdf():
    body = articulated_body("example-finned")
    data = {"mesh": "example-finned", "axes": {"aoa": 0, "joint.fin_py_hinge": "-20:10:20"}}
    s = parse_spec(data, "", body.joints)
    assert s.joint_axes() == {"fin_py_hinge": "joint.fin_py_hinge"}
    data["axes"]["joint.fin_py_hinge"] = [0, 40]  # the hinge stops at 0.6 rad (34.4 deg)
    with pytest.raises(SpecError, match=r"40 deg is outside the joint's limits \[-34.3775"):
        parse_spec(data, "", body.joints)
    data["axes"] = {"aoa": 0, "joint.rudder": [0]}
    with pytest.raises(SpecError, match="'rudder' is not a moving joint of example-finned"):
        parse_spec(data, "", body.joints)
    assert math.isclose(math.degrees(0.6), 34.37746770784939)


@pytest.mark.parametrize(
    "text, message",
    [
        ("mesh: example\naxes: {aoa: 0, colour: [1]}\n", "axes.colour: not an axis"),
        ("mesh: example\naxes: {aoa: 0, speed: []}\n", "axes.speed: empty"),
        ("mesh: example\naxes: {aoa: [0, 500]}\n", r"axes.aoa must be in \[-360, 360\]"),
        ("mesh: no-such-mesh.obj\naxes: {aoa: 0}\n", "no-such-mesh.obj"),
        ("mesh: [unclosed\n", "not YAML"),
    ],
)
def test_the_command_line_says_what_is_wrong_in_one_line_with_status_2(
    tmp_path, capsys, text, message
):
    path = tmp_path / "spec.yaml"
    path.write_text(text)
    assert main(["sweep", str(path), "--out", str(tmp_path / "out.zarr")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("adbsat-ros sweep: error: ")
    assert __import__("re").search(message, err), err
    assert not (tmp_path / "out.zarr").exists()


def test_the_gas_is_the_atmospheres_or_given_not_both():
    assert spec(axes={"aoa": 0, "altitude": [300, 400]}).atmosphere
    assert not spec().atmosphere
    with pytest.raises(SpecError, match="the gas is the atmosphere's"):
        spec(axes={"aoa": 0, "altitude": [300]}, fixed={"temperature": 900})
    with pytest.raises(SpecError, match=r"axes.altitude must be in \[100, 1000\] km"):
        spec(axes={"aoa": 0, "altitude": [50]})
    with pytest.raises(SpecError, match="time: '2026-13-01' is no UTC time"):
        spec(time="2026-13-01")
