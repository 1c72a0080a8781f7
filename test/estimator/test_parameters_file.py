"""ROS 2 params files read into settings: every fault names the file and the parameter."""

from __future__ import annotations

import pytest

from adbsat_ros.estimator.parameters import (
    PARAMETER_DEFAULTS,
    load_parameters_file,
    typed_parameter_value,
)
from adbsat_ros.estimator.settings import WrenchSettings, settings_from_file


def params_file(tmp_path, body: str, name: str = "p.yaml"):
    path = tmp_path / name
    path.write_text(body, encoding="utf-8")
    return path


def test_a_params_file_gives_the_node_its_settings_and_rclpy_keys_are_allowed(tmp_path):
    path = params_file(
        tmp_path,
        "/**:\n  ros__parameters:\n    use_sim_time: false\n    f107: 120\n"
        "adbsat_node:\n  ros__parameters:\n    f107: 180.0\n    shading: none\n"
        "    qos_overrides:\n      /wrench:\n        publisher:\n          depth: 5\n",
    )
    settings = settings_from_file(path)
    assert settings.f107 == 180.0 and settings.shading == "none"
    assert settings == WrenchSettings.from_parameters(dict(f107=180, shading="none"))
    assert settings.ap == PARAMETER_DEFAULTS["ap"]


@pytest.mark.parametrize(
    "body, text",
    [
        ("adbsat_node:\n  ros__parameters:\n    shadnig: none\n", "did you mean shading?"),
        ("adbsat_node:\n  ros__parameters:\n    f170: 150.0\n", "did you mean f107?"),
        ("adbsat_node:\n  ros__parameters:\n    zzz: 1\n", "unknown; known parameters are mesh"),
        (
            "adbsat_node:\n  ros__parameters:\n    f107: high\n",
            "parameter f107: f107 must be a number",
        ),
        (
            "adbsat_node:\n  ros__parameters:\n    alpha: 2.0\n",
            "parameter alpha: alpha must be in [0, 1]",
        ),
    ],
)
def test_an_unknown_name_or_a_bad_value_is_named_with_the_file(tmp_path, body, text):
    path = params_file(tmp_path, body)
    with pytest.raises(ValueError) as caught:
        settings_from_file(path)
    message = str(caught.value)
    assert message.startswith(f"{path}: ") and text in message and "\n" not in message


@pytest.mark.parametrize(
    "body, text",
    [
        (None, "no such parameters file"),
        ("adbsat_node:\n  ros__parameters:\n    f107: [1,\n", "not valid YAML at line"),
        ("- just\n- a list\n", "not a ROS parameters file"),
        ("other_node:\n  ros__parameters:\n    f107: 100.0\n", "no ros__parameters for"),
        (b"f107: \xe9\n", "cannot be read"),
    ],
)
def test_a_file_that_is_no_params_file_is_named(tmp_path, body, text):
    path = tmp_path / "p.yaml"
    if isinstance(body, bytes):
        path.write_bytes(body)
    elif body is not None:
        path.write_text(body, encoding="utf-8")
    with pytest.raises(ValueError) as caught:
        load_parameters_file(path)
    assert str(caught.value).startswith(f"{path}: ") and text in str(caught.value)


@pytest.mark.parametrize(
    "epoch, taken",
    [
        ("1958-01-01T00:00:00", True),
        ("2100-12-31T23:59:59Z", True),
        ("2026-06-01T12:00:00+02:00", True),
        ("1957-12-31T23:59:59", False),
        ("1900-01-01T00:00:00", False),
        ("2101-01-01T00:00:00", False),
        ("2200-01-01T00:00:00", False),
        ("2100-12-31T23:00:00-05:00", False),  # 2101 in UTC
        ("0001-01-01T00:00:00+01:00", False),  # before any year datetime has, in UTC
    ],
)
def test_epoch_utc_is_refused_outside_the_years_the_models_cover(tmp_path, epoch, taken):
    """epoch_utc within 1958..2100 (the time scales' and the space weather's years), in the
    settings and in a params file; outside, one line naming it and the range."""
    path = params_file(tmp_path, f"adbsat_node:\n  ros__parameters:\n    epoch_utc: '{epoch}'\n")
    if taken:
        assert 1958 <= WrenchSettings.from_parameters(dict(epoch_utc=epoch)).epoch_utc.year <= 2100
        assert settings_from_file(path).epoch_utc.year >= 1958
        return
    text = (
        "parameter epoch_utc: epoch_utc must be from 1958-01-01T00:00:00 to 2100-12-31T23:59:59 "
        f"UTC (the years the time scales and the atmosphere model's space weather cover), got "
        f"'{epoch}'"
    )
    with pytest.raises(ValueError) as caught:
        WrenchSettings.from_parameters(dict(epoch_utc=epoch))
    assert str(caught.value) == text
    with pytest.raises(ValueError) as caught:
        settings_from_file(path)
    assert str(caught.value) == f"{path}: {text}"


@pytest.mark.parametrize(
    "name, given, typed",
    [
        ("f107", 150, 150.0),
        ("mass", 0, 0.0),
        ("center_of_mass", [0, 1, 0.5], [0.0, 1.0, 0.5]),
        ("shading_samples", 32.0, 32),
        ("shading_samples", 2.5, 2.5),  # (a fraction stays: refused by its type)
        ("f107", "150", "150"),
        ("anomalous_oxygen", 1, 1),
        ("f107", True, True),
        ("epoch_utc", "2027-01-01", "2027-01-01"),
    ],
)
def test_a_parameter_value_takes_its_default_type_by_the_rule(name, given, typed):
    value = typed_parameter_value(name, given)
    assert value == typed and type(value) is type(typed)
    if isinstance(typed, list):
        assert [type(x) for x in value] == [type(x) for x in typed]
