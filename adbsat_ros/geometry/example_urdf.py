"""Bundled URDFs: ``example-articulated`` (the example satellite, hinged wings), ``example-finned``.

``example-articulated``: revolute ``wing_left_hinge``, ``wing_right_hinge`` along y, +-pi.
"""

from __future__ import annotations

from adbsat_ros.geometry.example_satellite import BODY_SIZE, WING_GAP, WING_SIZE, WING_X_CENTRE

#: Name that stands for this URDF wherever a mesh or URDF file is expected.
EXAMPLE_URDF_NAME = "example-articulated"


def _box(size) -> str:
    return f'<box size="{size[0]!r} {size[1]!r} {size[2]!r}"/>'


def example_satellite_urdf() -> str:
    """The URDF text of the articulated example (module docstring)."""
    root_y = BODY_SIZE[1] / 2 + WING_GAP
    half_span = WING_SIZE[1] / 2
    lines = [
        '<?xml version="1.0"?>',
        '<robot name="example_satellite">',
        '  <material name="body"><color rgba="0.7 0.7 0.7 1"/></material>',
        '  <material name="solar_array"><color rgba="0.1 0.1 0.5 1"/></material>',
        '  <link name="body">',
        f'    <visual><geometry>{_box(BODY_SIZE)}</geometry><material name="body"/></visual>',
        "  </link>",
    ]
    for name, sign in (("wing_left", 1.0), ("wing_right", -1.0)):
        lines += [
            f'  <link name="{name}">',
            f'    <visual><origin xyz="0 {sign * half_span!r} 0"/>',
            f'      <geometry>{_box(WING_SIZE)}</geometry><material name="solar_array"/>',
            "    </visual>",
            "  </link>",
            f'  <joint name="{name}_hinge" type="revolute">',
            f'    <parent link="body"/><child link="{name}"/>',
            f'    <origin xyz="{WING_X_CENTRE!r} {sign * root_y!r} 0"/>',
            '    <axis xyz="0 1 0"/>',
            '    <limit lower="-3.141592653589793" upper="3.141592653589793" effort="1" '
            'velocity="1"/>',
            "  </joint>",
        ]
    lines.append("</robot>")
    return "\n".join(lines) + "\n"


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
    lines = [
        '<?xml version="1.0"?>',
        '<robot name="finned_body">',
        '  <link name="body">',
        f'    <visual><geometry>{_box(FINNED_BODY_SIZE)}</geometry><material name="body"/>',
        "    </visual>",
        "  </link>",
    ]
    # (name, hinge position, span direction, fin box size in the fin's frame)
    fins = [
        ("fin_py", (0.0, half, 0.0), (0.0, 1.0, 0.0), (chord, span, thick)),
        ("fin_ny", (0.0, -half, 0.0), (0.0, -1.0, 0.0), (chord, span, thick)),
        ("fin_pz", (0.0, 0.0, half), (0.0, 0.0, 1.0), (chord, thick, span)),
        ("fin_nz", (0.0, 0.0, -half), (0.0, 0.0, -1.0), (chord, thick, span)),
    ]
    for name, (_, hy, hz), direction, size in fins:
        centre = [-chord / 2] + [d * span / 2 for d in direction[1:]]
        axis = " ".join(repr(abs(d)) for d in direction)
        lines += [
            f'  <link name="{name}">',
            f'    <visual><origin xyz="{centre[0]!r} {centre[1]!r} {centre[2]!r}"/>',
            f'      <geometry>{_box(size)}</geometry><material name="fin"/>',
            "    </visual>",
            "  </link>",
            f'  <joint name="{name}_hinge" type="revolute">',
            f'    <parent link="body"/><child link="{name}"/>',
            f'    <origin xyz="{FIN_HINGE_X!r} {hy!r} {hz!r}"/>',
            f'    <axis xyz="{axis}"/>',
            '    <limit lower="-0.6" upper="0.6" effort="1" velocity="1"/>',
            "  </joint>",
        ]
    lines.append("</robot>")
    return "\n".join(lines) + "\n"
