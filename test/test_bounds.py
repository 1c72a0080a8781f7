"""The valid ranges of the physical inputs: one table, applied alike by the command line, the
settings (params files and run-time parameters) and the node's messages."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from adbsat_ros.bounds import BOUNDS, bounded
from adbsat_ros.cli import main
from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS
from adbsat_ros.estimator.samples import Rejection
from adbsat_ros.estimator.settings import WrenchSettings, settings_from_file
from adbsat_ros.processes import usable_cpus, worker_count


def edges(bound):
    """(values inside, values just outside) of a Bound."""
    low_in = np.nextafter(bound.low, math.inf) if bound.low_open else bound.low
    inside = [low_in, bound.high, 0.5 * (bound.low + bound.high)]
    outside = [
        bound.low if bound.low_open else np.nextafter(bound.low, -math.inf),
        np.nextafter(bound.high, math.inf),
        math.nan,
        math.inf,
    ]
    return [float(x) for x in inside], [float(x) for x in outside]


@pytest.mark.parametrize("name", sorted(BOUNDS))
def test_every_bound_takes_its_edges_and_refuses_just_beyond(name):
    bound = BOUNDS[name]
    assert bound.reason and bound.low < bound.high
    inside, outside = edges(bound)
    for value in inside:
        assert bounded("x", value, name) == value
    for value in outside:
        with pytest.raises(ValueError) as caught:
            bounded("the_input", value, name)
        text = str(caught.value)
        assert text.startswith(f"the_input must be in {bound.text()} ({bound.reason})")
    with pytest.raises(ValueError, match="the_input must be a number, got 'fast'"):
        bounded("the_input", "fast", name)


COEFF = ["coeff", "example", "--shading", "none", "--speed", "7700", "--temperature", "900"]
ATMOSPHERE = "atmosphere --time 2025-03-01T00:00:00 --altitude 300 --lat 0 --lon 0".split()
OPTIONS = [
    (
        ["coeff", "example", "--shading", "none", "--temperature", "900", "--mean-mass", "16"],
        "--speed",
        "speed",
    ),
    (COEFF[:6] + ["--mean-mass", "16"], "--temperature", "temperature"),
    (COEFF, "--mean-mass", "mean_mass_amu"),
    (COEFF + ["--mean-mass", "16"], "--density", "mass_density"),
    (COEFF + ["--mean-mass", "16"], "--wall-temperature", "wall_temperature"),
    (COEFF + ["--mean-mass", "16"], "--aref", "area"),
    (COEFF + ["--mean-mass", "16"], "--lref", "length"),
    (
        ATMOSPHERE,
        "--f107",
        "f107",
    ),
    (
        ATMOSPHERE,
        "--ap",
        "ap",
    ),
]


@pytest.mark.parametrize("argv, option, name", OPTIONS, ids=[o for _, o, _ in OPTIONS])
def test_the_command_line_takes_the_edges_and_refuses_beyond_with_status_2(
    argv, option, name, capsys
):
    bound = BOUNDS[name]
    inside, outside = edges(bound)
    for value in inside[:2]:
        assert main([*argv, f"{option}={value!r}"]) == 0, (option, value, capsys.readouterr().err)
    capsys.readouterr()
    for value in outside[:2]:
        with pytest.raises(SystemExit) as exited:
            main([*argv, f"{option}={value!r}"])
        assert exited.value.code == 2
        err = capsys.readouterr().err
        assert f"{option} must be in {bound.text()}" in err and "Traceback" not in err


@pytest.mark.parametrize(
    "name, bound", [("f107", "f107"), ("f107a", "f107"), ("ap", "ap"), ("wall_temperature", None)]
)
def test_the_settings_take_the_edges_and_refuse_beyond(name, bound, tmp_path):
    rule = BOUNDS[bound or name]
    inside, outside = edges(rule)
    for value in inside:
        assert getattr(WrenchSettings.from_parameters({name: value}), name) == value
    for value in outside:
        with pytest.raises(ValueError, match=rf"^parameter {name}: {name} must be in"):
            WrenchSettings.from_parameters({name: value})
    path = tmp_path / "p.yaml"
    path.write_text(f"adbsat_node:\n  ros__parameters:\n    {name}: {outside[1]!r}\n")
    with pytest.raises(ValueError, match=rf"^{path}: parameter {name}: {name} must be in"):
        settings_from_file(path)


def test_the_settings_bound_the_ap_history_and_the_centre_of_mass():
    history = [4.0] * 7
    assert WrenchSettings.from_parameters({"ap_history": history}).ap_history == tuple(history)
    with pytest.raises(ValueError, match=r"ap_history\[6\] must be in \[0, 400\]"):
        WrenchSettings.from_parameters({"ap_history": [4.0] * 6 + [400.5]})
    assert WrenchSettings.from_parameters(
        {"center_of_mass": [-1000.0, 0.0, 1000.0]}
    ).center_of_mass == (-1000.0, 0.0, 1000.0)
    with pytest.raises(ValueError, match=r"center_of_mass\[z\] must be in \[0, 1000\] m"):
        WrenchSettings.from_parameters({"center_of_mass": [0.0, 0.0, -1000.5]})


def test_a_state_faster_than_any_earth_orbit_is_refused():
    est = AeroWrenchEstimator(
        WrenchSettings.from_parameters(
            dict(PARAMETER_DEFAULTS, mesh="example", shading="none", time_mode="epoch")
        )
    )
    r = 6378137.0 + 300e3
    est.on_state(1.0, [r, 0.0, 0.0], [0.0, 20_000.0, 0.0])
    for speed in (np.nextafter(20_000.0, math.inf), 1e100):
        with pytest.raises(Rejection, match=r"state speed .* is not in \[0, 20000\] m/s") as c:
            est.on_state(2.0, [r, 0.0, 0.0], [0.0, speed, 0.0])
        assert c.value.reason == "bad_state"
    assert est.state.stamp == 1.0 and est.rejections == {"bad_state": 2}


def test_the_table_is_the_one_docs_physics_shows():
    text = (Path(__file__).resolve().parents[1] / "docs" / "physics.md").read_text()
    for name, bound in BOUNDS.items():
        assert f"| `{name}` | {bound.text()} | {bound.reason} |" in text, name


def test_workers_are_capped_at_the_usable_cpus_with_a_note():
    cpus = usable_cpus()
    assert worker_count(None) == (cpus, None) and worker_count(1) == (1, None)
    count, note = worker_count(1000)
    assert count == cpus and note == f"1000 workers asked for, {cpus} used: the usable CPUs here"
    for bad in (0, -3, 2.5, True):
        with pytest.raises(ValueError, match="workers must be a whole number >= 1"):
            worker_count(bad)
