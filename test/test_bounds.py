"""The valid ranges of the physical inputs: one table, applied alike by the command line, the
settings (params files and run-time parameters) and the node's messages."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import yaml
from edges import NUMBER_PARAMETERS, TENSOR_PARAMETERS, as_parameter, edges, parameter_edges

from adbsat_ros.bounds import BOUNDS, bounded
from adbsat_ros.cli import main
from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.handling import MessageHandler
from adbsat_ros.estimator.parameters import (
    PARAMETER_DEFAULTS,
    PARAMETER_RANGES,
    parameter_range_text,
)
from adbsat_ros.estimator.samples import Rejection
from adbsat_ros.estimator.settings import WrenchSettings, settings_from_file
from adbsat_ros.messages.cdr import AttitudeFields, Stamp
from adbsat_ros.messages.decoding import OdometryFields
from adbsat_ros.processes import usable_cpus, worker_count


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


STATE = "atmosphere --time 2025-03-01T00:00:00 --position 6778137,0,0 --json".split()


@pytest.mark.parametrize(
    "template, bound, option",
    [
        ("--velocity=0,{},0", "orbital_speed", "--velocity: the speed"),
        ("--velocity=0,7668,0 --wind=0,0,{}", "wind", "--wind z"),
    ],
)
def test_the_command_line_bounds_a_velocity_and_a_wind(template, bound, option, capsys):
    rule = BOUNDS[bound]
    inside, outside = edges(rule)
    for value in inside[:2]:
        assert main([*STATE, *template.format(repr(value)).split()]) == 0, capsys.readouterr()
    capsys.readouterr()
    for value in outside[1:2] if bound == "orbital_speed" else outside[:2]:
        assert main([*STATE, *template.format(repr(value)).split()]) == 2
        err = capsys.readouterr().err
        assert f"{option} must be in {rule.text()}" in err and "Traceback" not in err, err


def refusal(name) -> str:
    """The start of the error a value of ``name`` out of its range gets."""
    element = {"ap_history": "[6]", "center_of_mass": "[z]", "wind_ecef": "[z]"}.get(name, "")
    return rf"parameter {name}: {re.escape(name + element)} must be (in|a whole number)"


def test_every_number_parameter_has_a_range_with_its_reason():
    assert set(NUMBER_PARAMETERS) | set(TENSOR_PARAMETERS) == set(PARAMETER_RANGES)
    for name in NUMBER_PARAMETERS:
        rule = PARAMETER_RANGES[name]
        default = PARAMETER_DEFAULTS[name]
        for x in default if isinstance(default, list) else [default]:
            assert rule.contains(float(x)), (name, x)
        assert rule.reason and rule.low < rule.high, name


@pytest.mark.parametrize("name", NUMBER_PARAMETERS)
def test_each_number_parameter_takes_its_edges_and_refuses_beyond(name, tmp_path):
    """Through the settings (as the node's parameters and bag analysis take them) and through a
    ROS 2 params file: the edges are taken as given, just beyond is refused by name."""
    inside, outside = parameter_edges(name)
    for i, x in enumerate(inside + outside):
        value = as_parameter(name, x)
        path = tmp_path / f"p{i}.yaml"
        path.write_text(yaml.safe_dump({"adbsat_node": {"ros__parameters": {name: value}}}))
        if x in inside:
            got = getattr(WrenchSettings.from_parameters({name: value}), name)
            assert (got[-1] if isinstance(got, tuple) else got) == x, (name, x)
            assert getattr(settings_from_file(path), name) == getattr(
                WrenchSettings.from_parameters({name: value}), name
            )
            continue
        with pytest.raises(ValueError, match=rf"^{refusal(name)}") as caught:
            WrenchSettings.from_parameters({name: value})
        assert "got" in str(caught.value), caught.value
        with pytest.raises(ValueError, match=rf"^{re.escape(str(path))}: {refusal(name)}"):
            settings_from_file(path)


@pytest.mark.parametrize("name", ["mesh_accept_size", "adbsat_compat", "earth_rotation"])
def test_a_flag_takes_true_or_false_only(name):
    assert getattr(WrenchSettings.from_parameters({name: True}), name) is True
    for value in ("false", 0, 1.0, None):
        with pytest.raises(ValueError, match=rf"^parameter {name}: expected true or false"):
            WrenchSettings.from_parameters({name: value})


def test_a_number_parameter_does_not_take_a_flag_or_text():
    for value in (True, "fast", None, [1.0]):
        with pytest.raises(ValueError, match=r"^parameter alpha: alpha must be a number"):
            WrenchSettings.from_parameters({"alpha": value})


def test_the_settings_bound_the_ap_history_and_the_centre_of_mass():
    history = [4.0] * 7
    assert WrenchSettings.from_parameters({"ap_history": history}).ap_history == tuple(history)
    with pytest.raises(ValueError, match=r"ap_history\[6\] must be in \[0, 400\]"):
        WrenchSettings.from_parameters({"ap_history": [4.0] * 6 + [400.5]})
    with pytest.raises(ValueError, match=r"^parameter ap_history: needs 7 values"):
        WrenchSettings.from_parameters({"ap_history": [4.0] * 6})
    assert WrenchSettings.from_parameters(
        {"center_of_mass": [-1000.0, 0.0, 1000.0]}
    ).center_of_mass == (-1000.0, 0.0, 1000.0)
    with pytest.raises(ValueError, match=r"center_of_mass\[x\] must be in \[-1000, 1000\] m"):
        WrenchSettings.from_parameters({"center_of_mass": [-1000.5, 0.0, 0.0]})
    with pytest.raises(ValueError, match=r"^parameter center_of_mass: expected three numbers"):
        WrenchSettings.from_parameters({"center_of_mass": [0.0, 0.0]})


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


def handler_with(**parameters) -> MessageHandler:
    """The per-message path the node and bag analysis share, on the example satellite."""
    values = dict(PARAMETER_DEFAULTS, mesh="example", shading="none", time_mode="epoch")
    return MessageHandler(AeroWrenchEstimator(WrenchSettings.from_parameters(values, **parameters)))


def state_message(sec, radius, speed) -> OdometryFields:
    """An ECI state on the x axis (geodetic altitude radius - a), moving along y."""
    return OdometryFields(
        Stamp(sec, 0), "eci", "eci", (radius, 0.0, 0.0), (0, 0, 0, 1.0), (0.0, speed, 0.0)
    )


def test_the_messages_take_the_edges_and_refuse_beyond():
    """Through decoded messages: the attitude's norm at max_quaternion_norm_error (at its own
    largest value, 0.5, where 1 +- 0.5 are exact), the state's altitude at min_altitude and its
    speed at the bound of orbital speeds. Each refusal is counted under its reason."""
    a = 6378137.0
    handler = handler_with(max_quaternion_norm_error=0.5, min_altitude=200e3)
    assert handler.on_state(state_message(1, a + 300e3, 7700.0)).reason is None
    for k, (w, reason) in enumerate(
        [
            (1.5, None),
            (0.5, None),
            (float(np.nextafter(1.5, math.inf)), "bad_quaternion"),
            # (|q| - 1 is rounded: 1 - nextafter(0.5, -inf) is 0.5; two steps below it is not)
            (float(np.nextafter(np.nextafter(0.5, -math.inf), -math.inf)), "bad_quaternion"),
        ]
    ):
        outcome = handler.on_attitude(AttitudeFields(Stamp(1, 1000 * (k + 1)), [0.0, 0.0, 0.0, w]))
        assert outcome.reason == reason, (w, outcome.reason)
        assert (outcome.sample is None) == (reason is not None)
    speed = BOUNDS["orbital_speed"].high
    for k, (radius, v, reason) in enumerate(
        [
            (a + 200e3 + 1e-3, 7700.0, None),
            (a + 200e3 - 1e-3, 7700.0, "altitude_out_of_range"),
            (a + 300e3, speed, None),
            (a + 300e3, float(np.nextafter(speed, math.inf)), "bad_state"),
        ]
    ):
        assert handler.on_state(state_message(2 + k, radius, v)).reason == reason, (radius, v)
    assert dict(handler.estimator.rejections) == {
        "bad_quaternion": 2,
        "altitude_out_of_range": 1,
        "bad_state": 1,
    }


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


def test_the_bundled_params_file_shows_every_range():
    """config/adbsat.yaml, the parameters' documentation, gives each number parameter's range
    as the node's descriptors do (``ros2 param describe``)."""
    lines = (Path(__file__).resolve().parents[1] / "config" / "adbsat.yaml").read_text()
    comments, shown = [], {}
    for line in lines.splitlines():
        text = line.strip()
        if text.startswith("#"):
            comments.append(text[1:].strip())
        elif text.endswith(":") or ": " in text:
            shown[text.split(":")[0]] = " ".join(comments)
            comments = []
    for name in PARAMETER_RANGES:
        assert f"valid: {parameter_range_text(name)}" in shown[name], name


def test_the_inertia_is_a_symmetric_positive_definite_tensor_within_its_range():
    """Each of its 9 numbers within the range (at both edges and just beyond, on the diagonal of
    an otherwise valid tensor where the value is positive), symmetric, positive definite; all 0
    means no angular acceleration."""
    rule = PARAMETER_RANGES["inertia"]
    assert WrenchSettings.from_parameters({"inertia": [0.0] * 9}).inertia is None
    inside, outside = edges(rule)
    for x in [v for v in inside if v > 0.0]:
        tensor = [x, 0.0, 0.0, 0.0, x, 0.0, 0.0, 0.0, x]
        assert WrenchSettings.from_parameters({"inertia": tensor}).inertia == tuple(tensor)
    for x in outside:
        tensor = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, x]
        with pytest.raises(ValueError, match=r"^parameter inertia: inertia\[8\] must be in"):
            WrenchSettings.from_parameters({"inertia": tensor})
    with pytest.raises(ValueError, match="must be symmetric"):
        WrenchSettings.from_parameters({"inertia": [2.0, 0.5, 0, 0, 2.0, 0, 0, 0, 2.0]})
    with pytest.raises(ValueError, match="must be positive definite"):
        WrenchSettings.from_parameters({"inertia": [1.0, 2.0, 0, 2.0, 1.0, 0, 0, 0, 1.0]})
    with pytest.raises(ValueError, match=r"expected 9 numbers"):
        WrenchSettings.from_parameters({"inertia": [1.0, 1.0, 1.0]})
    tensor = [rule.low, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]  # in range, not positive
    with pytest.raises(ValueError, match="must be positive definite"):
        WrenchSettings.from_parameters({"inertia": tensor})
