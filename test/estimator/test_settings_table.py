"""The parameter table gives the settings, the node's set-up and the read-only parameters."""

from __future__ import annotations

import datetime as dt
from pathlib import Path

import pytest

from adbsat_ros.estimator.parameters import PARAMETERS, READ_ONLY_PARAMETERS
from adbsat_ros.estimator.settings import WrenchSettings, setup_from_settings
from adbsat_ros.physics.gsi_models import ModelOptions
from adbsat_ros.physics.setup import BodySpec, ShadingPolicy

ROOT = Path(__file__).resolve().parents[2]


def test_every_parameter_is_a_field_of_the_frozen_settings():
    settings = WrenchSettings.from_parameters()
    assert [p.name for p in PARAMETERS] == list(settings.as_parameters())
    with pytest.raises(AttributeError):
        settings.mass = 2.0
    assert hash(settings) == hash(WrenchSettings.from_parameters())


def test_the_settings_give_the_set_up_each_parameter_names():
    settings = WrenchSettings.from_parameters(
        mesh=" cylinder ",
        mesh_scale=2.0,
        mesh_accept_size=True,
        gsi_model="CLL",
        alpha=0.25,
        alpha_n=0.5,
        sigma_n=0.6,
        sigma_t=0.7,
        wall_temperature=350.0,
        specular_reflectivity=0.1,
        diffuse_reflectivity=0.2,
        material_overrides=["panel:alpha=0.9", " "],
        incident_temperature="kinetic",
        adbsat_compat=True,
        center_of_mass=[0.0, 0.1, 0.2],
        shading="projection",
        shading_samples=8,
        shading_cache_resolution_deg=0.5,
        shading_cache_size=100,
        shading_interpolation=False,
        joint_shading_resolution_deg=1.0,
        joint_shading_resolution_m=0.01,
        joint_shading_interpolation=True,
        joint_shading_cache_size=4,
        joint_shading_exact=True,
    )
    setup = setup_from_settings(settings)
    assert setup.body == BodySpec("cylinder", 2.0, True, urdf="")
    assert setup.model == "cll" and setup.options == ModelOptions("kinetic", True)
    surface = setup.surface
    assert (surface.alpha, surface.alpha_n, surface.sigma_n, surface.sigma_t) == (
        0.25,
        0.5,
        0.6,
        0.7,
    )
    assert surface.wall_temperature == 350.0
    assert (surface.specular_reflectivity, surface.diffuse_reflectivity) == (0.1, 0.2)
    assert setup.overrides == ("panel:alpha=0.9",)
    assert setup.reference.moment_point == (0.0, 0.1, 0.2)
    assert setup.shading == ShadingPolicy(
        "projection", 8, 0.5, 100, False, 1.0, 0.01, True, 4, True
    )


def test_the_settings_go_back_to_parameter_values_and_return():
    settings = WrenchSettings.from_parameters(
        inertia=[2.0, 0, 0, 0, 3.0, 0, 0, 0, 4.0],
        ap_history=[4, 5, 6, 7, 8, 9, 10],
        material_overrides=["panel:alpha=0.9"],
        time_mode="epoch",
        epoch_utc="2027-03-01T12:00:00Z",
    )
    assert settings.epoch_utc == dt.datetime(2027, 3, 1, 12, tzinfo=dt.timezone.utc)
    values = settings.as_parameters()
    assert values["inertia"] == [2.0, 0.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0, 4.0]
    assert values["ap_history"] == [4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0]
    assert WrenchSettings.from_parameters(values) == settings
    defaults = WrenchSettings.from_parameters()
    unused = defaults.as_parameters()
    assert defaults.inertia is None and unused["inertia"] == [0.0] * 9
    assert defaults.ap_history is None and unused["ap_history"] == [0.0]
    assert defaults.material_overrides == () and unused["material_overrides"] == [""]
    assert WrenchSettings.from_parameters(unused) == defaults


def test_the_read_only_parameters_are_those_the_docs_and_the_params_file_mark():
    expected = {
        "mesh",
        "mesh_scale",
        "mesh_accept_size",
        "robot_description",
        "qos_depth",
        "body_frame_id",
        "executor",
    }
    assert set(READ_ONLY_PARAMETERS) == expected
    node_md = " ".join((ROOT / "docs" / "node.md").read_text(encoding="utf-8").split())
    listed = node_md.split("keeps read-only (", 1)[1].split(")", 1)[0]
    assert {name.strip(" `") for name in listed.split(",")} == expected
    marked, comment = set(), ""
    for line in (ROOT / "config" / "adbsat.yaml").read_text(encoding="utf-8").splitlines():
        text = line.strip()
        if text.startswith("#"):
            comment += text
        elif ":" in text:
            if "(read-only)" in comment and line.startswith("    "):  # (a parameter's line)
                marked.add(text.split(":")[0])
            comment = ""
    assert marked == expected
