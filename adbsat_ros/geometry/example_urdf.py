"""Bundled URDFs: ``example-articulated`` (the example satellite, hinged wings), ``example-finned``.

``example-articulated``: revolute ``wing_left_hinge``, ``wing_right_hinge`` along y, +-pi.
"""

from __future__ import annotations

import math

from adbsat_ros.geometry.example_satellite import BODY_SIZE, WING_GAP, WING_SIZE, WING_X_CENTRE

#: Name that stands for this URDF wherever a mesh or URDF file is expected.
EXAMPLE_URDF_NAME = "example-articulated"


def _xyz(values) -> str:
    return " ".join(repr(float(v)) for v in values)


def _robot(name: str, body_size, hinged) -> str:
    """A URDF: a box ``body`` and links on revolute hinges, each ``(name, centre of its box,
    box size, material, hinge origin, hinge axis, limit)``."""
    lines = [
        '<?xml version="1.0"?>',
        f'<robot name="{name}">',
        '  <material name="body"><color rgba="0.7 0.7 0.7 1"/></material>',
        '  <material name="solar_array"><color rgba="0.1 0.1 0.5 1"/></material>',
        f'  <link name="body"><visual><geometry><box size="{_xyz(body_size)}"/></geometry>',
        '    <material name="body"/></visual></link>',
    ]
    for link, centre, size, material, origin, axis, limit in hinged:
        lines += [
            f'  <link name="{link}"><visual><origin xyz="{_xyz(centre)}"/>',
            f'    <geometry><box size="{_xyz(size)}"/></geometry><material name="{material}"/>',
            "  </visual></link>",
            f'  <joint name="{link}_hinge" type="revolute"><parent link="body"/>',
            f'    <child link="{link}"/><origin xyz="{_xyz(origin)}"/><axis xyz="{_xyz(axis)}"/>',
            f'    <limit lower="{-limit!r}" upper="{limit!r}" effort="1" velocity="1"/></joint>',
        ]
    return "\n".join([*lines, "</robot>"]) + "\n"


def example_satellite_urdf() -> str:
    """The URDF text of the articulated example (module docstring)."""
    root_y, half_span = BODY_SIZE[1] / 2 + WING_GAP, WING_SIZE[1] / 2
    wings = [
        (name, (0, s * half_span, 0), WING_SIZE, "solar_array", (WING_X_CENTRE, s * root_y, 0))
        for name, s in (("wing_left", 1.0), ("wing_right", -1.0))
    ]
    return _robot("example_satellite", BODY_SIZE, [(*w, (0, 1, 0), math.pi) for w in wings])


#: Name of the bundled finned body.
EXAMPLE_FINNED_NAME = "example-finned"
FINNED_BODY_SIZE = (0.6, 0.3, 0.3)
#: Fin chord (x), span and thickness [m]; the hinge runs along the span at the chord's front.
FIN_SIZE = (0.2, 0.15, 0.005)
FIN_HINGE_X = -0.15


def example_finned_urdf() -> str:
    """URDF of a 0.6 m body with four rear fins ``fin_*`` on revolute hinges, +-0.6 rad."""
    chord, span, thick = FIN_SIZE
    half = FINNED_BODY_SIZE[1] / 2
    fins = []
    for name, axis in (("fin_py", 1), ("fin_ny", 1), ("fin_pz", 2), ("fin_nz", 2)):
        d = [0.0, 0.0, 0.0]  # (the span's direction)
        d[axis] = -1.0 if name[4] == "n" else 1.0
        size = (chord, span, thick) if axis == 1 else (chord, thick, span)
        centre = (-chord / 2, d[1] * span / 2, d[2] * span / 2)
        origin = (FIN_HINGE_X, d[1] * half, d[2] * half)
        fins.append((name, centre, size, "fin", origin, [abs(v) for v in d], 0.6))
    return _robot("finned_body", FINNED_BODY_SIZE, fins)
