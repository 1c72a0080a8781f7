"""A single flat fin on a hinge, as a URDF, and its Newtonian hinge torque by hand: the shared
reference of the articulated-body tests."""

from __future__ import annotations

import math

import numpy as np

#: A fin (0.2 m chord x 0.15 m span x 0.01 m box) whose hinge runs along y through its leading
#: edge at (0.3, 0.2, 0) of a geometry-less base link.
FIN_URDF = """<robot name="fin">
  <link name="base"/>
  <link name="fin"><visual><origin xyz="-0.1 0.075 0"/>
    <geometry><box size="0.2 0.15 0.01"/></geometry></visual></link>
  <joint name="hinge" type="revolute"><parent link="base"/><child link="fin"/>
    <origin xyz="0.3 0.2 0"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"""


def rotation_y(theta: float) -> np.ndarray:
    """Rotation by ``theta`` [rad] about y."""
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def newton_hinge_torque(d: float, u) -> float:
    """The Newtonian fin's hinge torque coefficient (about +y through the hinge, A_ref = L_ref
    = 1) by hand, the fin turned by ``d`` [rad], flow direction ``u``: each face of the box, a
    rectangle of area A and outward normal n facing the flow (c = -u . n > 0), carries
    2 c^2 A along -n at its centre."""
    rot = rotation_y(d)
    size = np.array([0.2, 0.15, 0.01])
    centre = np.array([-0.1, 0.075, 0.0])
    torque = 0.0
    for axis in range(3):
        for sign in (1.0, -1.0):
            n_local = np.zeros(3)
            n_local[axis] = sign
            area = float(np.prod(np.delete(size, axis)))
            n = rot @ n_local
            c = -float(np.asarray(u) @ n)
            if c > 0.0:
                arm = rot @ (centre + 0.5 * size[axis] * n_local)  # (the hinge is the origin)
                torque += float(np.cross(arm, -2.0 * c * c * area * n)[1])
    return torque
