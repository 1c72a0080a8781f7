"""The ranges of the inputs that came without one: a point of the body (moment reference, centre
of mass) near the body, a composition's implied density, a job's size and memory; negative and
non-finite numbers on the command line named by their option's range."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from adbsat_ros import bounds
from adbsat_ros.bounds import BOUNDS
from adbsat_ros.cli import main
from adbsat_ros.estimator.settings import WrenchSettings, setup_from_settings
from adbsat_ros.geometry.loading import resolve_mesh
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.model import build_model

FLOW = ["--speed", "7500", "--temperature", "900", "--shading", "none"]
GAS = [*FLOW, "--mean-mass", "16", "--density", "1e-12"]


def refusal(capsys, argv) -> str:
    """The one line of stderr of a command line refused with status 2 (argparse's or ours)."""
    try:
        code = main(argv)
    except SystemExit as exited:
        code = exited.code
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    return err


def test_a_body_point_lies_within_ten_body_sizes_of_the_box_of_the_mesh_and_its_origin():
    # a box 2 m along x from 1 to 3, 1 m along y and z: the origin outside it, on the x side
    rules = bounds.body_point_bounds((1.0, -0.5, -0.5), (3.0, 0.5, 0.5))
    margin = bounds.BODY_REACH * 2.0
    assert [(r.low, r.high) for r in rules] == [
        (0.0 - margin, 3.0 + margin),
        (-0.5 - margin, 0.5 + margin),
        (-0.5 - margin, 0.5 + margin),
    ]
    assert bounds.body_point("p", (0, 0, 0), (1, -0.5, -0.5), (3, 0.5, 0.5)) == (0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match=r"^p y must be in \[-20\.5, 20\.5\] m \(a moment "):
        bounds.body_point("p", (0, 20.6, 0), (1, -0.5, -0.5), (3, 0.5, 0.5))


def test_the_mesh_reference_refuses_a_moment_point_far_from_the_body():
    mesh = resolve_mesh("example")
    low, high = mesh.bounds
    reach = bounds.BODY_REACH * float(np.max(high - low))
    edge = float(high[0]) + reach
    assert Reference(moment_point=(edge, 0, 0)).resolved(mesh).moment_point[0] == edge
    with pytest.raises(ValueError, match="^the point x must be in"):
        Reference(moment_point=(np.nextafter(edge, 2 * edge), 0, 0)).resolved(mesh, "the point")


@pytest.mark.parametrize("point", ["1e200,0,0", "0,0,-30", "0,-1e300,0"])
def test_coeff_refuses_a_moment_reference_far_from_the_body(point, capsys):
    err = refusal(capsys, ["coeff", "example", *GAS, f"--moment-ref={point}"])
    assert "--moment-ref " in err and "must be in [" in err and "body" in err


def test_the_node_refuses_a_centre_of_mass_far_from_the_body():
    mesh = resolve_mesh("example")
    near = WrenchSettings.from_parameters(center_of_mass=[0.0, 20.0, 0.0])
    assert build_model(setup_from_settings(near), mesh).method.reference.moment_point == (
        0.0,
        20.0,
        0.0,
    )
    far = WrenchSettings.from_parameters(center_of_mass=[0.0, 500.0, 0.0])
    with pytest.raises(ValueError, match=r"^parameter center_of_mass: center_of_mass y must be"):
        build_model(setup_from_settings(far), mesh)


@pytest.mark.parametrize(
    "species, shown",
    [
        ("Ar=1e26,O2=1e26,N2=1e26", "got 16.5"),  # 16.6 kg/m^3: above the range
        ("H=1e-300", "got 0.0"),  # the mass density underflows: below the range
        ("O=0", "got 0"),
    ],
)
def test_a_composition_must_imply_a_density_in_range(species, shown, capsys):
    err = refusal(capsys, ["coeff", "example", *FLOW, "--species", species])
    rule = BOUNDS["mass_density"]
    assert f"--species: the mass density they imply must be in {rule.text()}" in err
    assert shown in err


def test_a_composition_whose_mass_underflows_is_no_free_stream():
    with pytest.raises(ValueError, match="number_densities: the mass density"):
        FreeStream(speed=7500.0, temperature=900.0, number_densities={"H": 1e-300})


def test_cll_without_its_species_is_a_usage_error(capsys):
    err = refusal(capsys, ["coeff", "example", "--gsim", "cll", *FLOW, "--species", "AnO=1e15"])
    assert "--species: the cll model needs one of the species He, O, N2, O2, H, N" in err


@pytest.mark.parametrize("value", ["-inf", "-1e5", "-nan", "-infinity", "-.5e3"])
def test_a_negative_number_is_a_value_that_its_range_names(value, capsys):
    err = refusal(capsys, ["coeff", "example", *FLOW[2:], "--mean-mass", "16", "--speed", value])
    assert f"--speed must be in {BOUNDS['speed'].text()}" in err and repr(value) in err


@pytest.mark.parametrize(
    "where, option",
    [
        (["--position", "1e300,0,0"], "--position: the distance from the Earth's centre"),
        (["--position", "1e200,1e200,1e200"], "--position: the distance"),
        (["--altitude", "1e308", "--lat", "0", "--lon", "0"], "--altitude must be in [0, 1000] km"),
        (["--altitude", "400", "--lat", "0", "--lon", "1e308"], "--lon must be in [-360, 360]"),
    ],
)
@pytest.mark.parametrize("command", ["atmosphere", "coeff"])
def test_a_far_or_odd_place_is_refused_by_name_without_a_warning(where, option, command, capsys):
    argv = [command, *(["example", "--shading", "none"] if command == "coeff" else [])]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # (a RuntimeWarning would raise)
        err = refusal(capsys, [*argv, "--time", "2020-01-01T00:00:00", *where])
    assert option in err and "nan" not in err


def test_a_job_larger_than_the_memory_is_refused_with_its_estimate(monkeypatch):
    bounds.check_memory("the job", 1e9, available=2_000_000_000)
    with pytest.raises(
        ValueError, match=r"^the job needs about 3 GB of memory, more than the 2 GB"
    ):
        bounds.check_memory("the job", 3e9, available=2_000_000_000)
    assert bounds.available_memory() > 0
