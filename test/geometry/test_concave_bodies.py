"""The bundled concave bodies: closed, the sizes they claim, and where the panel method's single
collision is wrong (ADBSat's validation, Sinpetru et al. 2022, paper 108327: the grooves of a
cylinder's front face barely change its drag, which the panel method overestimates)."""

from __future__ import annotations

import math

import pytest

from adbsat_ros.geometry.concave_bodies import GROOVE_DEPTH, GROOVES, LENGTH, RADIUS
from adbsat_ros.geometry.loading import resolve_mesh
from adbsat_ros.geometry.mesh import MeshError, signed_volume
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.physics.tpmc.method import TestParticleMethod

SECTORS = 96
# a regular polygon of n sides inscribed in the circle has area n/2 r^2 sin(2 pi / n)
POLYGON = SECTORS / (2.0 * math.pi) * math.sin(2.0 * math.pi / SECTORS)


@pytest.mark.parametrize(
    "name, volume",
    [
        ("cylinder", POLYGON * math.pi * RADIUS**2 * LENGTH),
        (
            "grooved-cylinder",
            POLYGON
            * math.pi
            * (RADIUS**2 * LENGTH - GROOVE_DEPTH * sum(b * b - a * a for a, b in GROOVES)),
        ),
        ("intake-box", 2.0 * 1.0 * 1.0 - 0.6 * 0.6 * 1.5),
    ],
)
def test_each_bundled_body_is_closed_with_its_volume(name, volume):
    mesh = resolve_mesh(name)
    assert mesh.to_trimesh().is_watertight
    assert signed_volume(mesh.vertices) == pytest.approx(volume, rel=1e-9)
    with pytest.raises(MeshError, match=f"the {name} mesh is in metres"):
        resolve_mesh(name, scale=2.0)


def test_grooves_barely_change_the_drag_but_the_panel_method_says_otherwise():
    flow = FreeStream(7800.0, 1000.0, mean_mass_amu=16.0)
    ref = Reference(area=math.pi * RADIUS**2, length=LENGTH)
    drag = {}
    for name in ("cylinder", "grooved-cylinder"):
        mesh = resolve_mesh(name)
        panel = PanelMethod(mesh, reference=ref).coefficients(flow)
        tpmc = TestParticleMethod(mesh, reference=ref).coefficients(
            flow, tolerance=0.003, seed=5, workers=1
        )
        drag[name] = (panel.drag, tpmc.drag, tpmc.drag_error)
    plain, grooved = drag["cylinder"], drag["grooved-cylinder"]
    assert abs(plain[1] - plain[0]) <= 3.0 * plain[2]  # convex: the two methods agree
    assert grooved[1] == pytest.approx(plain[1], rel=0.02)  # with every reflection: as plain
    assert grooved[0] > 1.15 * plain[0]  # one collision per molecule: far too much drag
