"""ADBSat's aerodynamic frames and angles (docs/physics.md, section 2).

G: the mesh frame (the node's body frame); B: ADBSat's body frame, ``L_GB = diag(1, -1, -1)``;
W: wind; F: flight, ``diag(-1, 1, -1)`` of B. Gas along u_G = (-cos a cos b, sin b, sin a cos b).
"""

from __future__ import annotations

import math

import numpy as np


def cross(a, b) -> np.ndarray:
    """Cross product a x b over the last axis, as ``np.cross`` evaluates it without its checks."""
    a = np.asarray(a)
    b = np.asarray(b)
    if a.ndim == 1 and b.ndim == 1:
        a0, a1, a2 = a.tolist()
        b0, b1, b2 = b.tolist()
        return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


#: Mesh frame G to ADBSat body frame B (and back: it is its own inverse).
L_GB = np.diag([1.0, -1.0, -1.0])
#: ADBSat body frame B to flight frame F.
L_FB = np.diag([-1.0, 1.0, -1.0])


def cross_matrix(a) -> np.ndarray:
    """The (3, 3) matrix [a]x of the cross product with ``a``: a x b = [a]x @ b."""
    x, y, z = np.asarray(a, dtype=float).tolist()
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def _floats(value, name: str) -> np.ndarray:
    """``value`` as a flat float array, or ValueError naming ``name`` if it holds no numbers."""
    try:
        return np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a finite non-zero 3-vector, got {value!r}") from None


def direction_components(value, name: str = "flow direction") -> tuple:
    """(x, y, z) of a direction; ValueError naming ``name`` unless a finite non-zero 3-vector."""
    u = _floats(value, name)
    if u.shape == (3,):
        x, y, z = u.tolist()
        if math.isfinite(x) and math.isfinite(y) and math.isfinite(z) and (x or y or z):
            return x, y, z
    raise ValueError(f"{name} must be a finite non-zero 3-vector, got {value!r}")


def unit_vector(value, name: str = "flow direction") -> np.ndarray:
    """``value`` as a unit 3-vector; ValueError naming ``name`` as :func:`direction_components`."""
    u = _floats(value, name)
    norm = math.sqrt(u.dot(u)) if u.shape == (3,) else math.nan  # np.linalg.norm(u), exactly
    if u.shape != (3,) or not math.isfinite(norm) or norm == 0.0:
        raise ValueError(f"{name} must be a finite non-zero 3-vector, got {value!r}")
    return u / norm


def flow_direction(aoa, aos):
    """u_G = (-cos a cos b, sin b, sin a cos b), shape (..., 3), of aoa, aos [rad] broadcast."""
    if np.ndim(aoa) == 0 and np.ndim(aos) == 0:
        ca, sa, cb, sb = math.cos(aoa), math.sin(aoa), math.cos(aos), math.sin(aos)
        return np.array([-ca * cb, sb, sa * cb])
    aoa = np.asarray(aoa, dtype=float)
    aos = np.asarray(aos, dtype=float)
    ca, sa, cb, sb = np.cos(aoa), np.sin(aoa), np.cos(aos), np.sin(aos)
    return np.stack(np.broadcast_arrays(-ca * cb, sb, sa * cb), axis=-1)


def attitude_flow(aoa=None, aos=None, direction=None) -> tuple:
    """``(u_G, (aoa, aos) or None)`` of angles [rad] or a gas ``direction`` in G."""
    if direction is not None:
        if aoa is not None or aos is not None:
            raise ValueError("give either aoa/aos or flow_direction, not both")
        return unit_vector(direction, "flow_direction"), None
    aoa = 0.0 if aoa is None else float(aoa)
    aos = 0.0 if aos is None else float(aos)
    if not (math.isfinite(aoa) and math.isfinite(aos)):
        raise ValueError(f"aoa and aos must be finite, got {aoa!r}, {aos!r}")
    return flow_direction(aoa, aos), (aoa, aos)


def angles_of_flow(u_G):
    """aoa in (-pi, pi], aos in [-pi/2, pi/2] [rad] of gas directions ``u_G`` (aoa 0 at poles)."""
    u = np.asarray(u_G, dtype=float)
    if u.shape == (3,):
        x, y, z = u.tolist()
        n = math.hypot(x, y, z)
        return math.atan2(z / n, -x / n), math.asin(max(-1.0, min(1.0, y / n)))
    u = u / np.linalg.norm(u, axis=-1, keepdims=True)
    # vehicle velocity in B: L_GB (-u_G)
    vx, vy, vz = -u[..., 0], u[..., 1], u[..., 2]
    aos = np.arcsin(np.clip(vy, -1.0, 1.0))
    aoa = np.arctan2(vz, vx)
    return aoa, aos


def body_to_wind(aoa, aos):
    """L_WB, B to W: [[ca cb, sb, sa cb], [-ca sb, cb, -sa sb], [-sa, 0, ca]], (..., 3, 3)."""
    if np.ndim(aoa) == 0 and np.ndim(aos) == 0:  # one attitude: skip the array machinery
        ca, sa, cb, sb = math.cos(aoa), math.sin(aoa), math.cos(aos), math.sin(aos)
        return np.array([[ca * cb, sb, sa * cb], [-ca * sb, cb, -sa * sb], [-sa, 0.0, ca]])
    aoa = np.asarray(aoa, dtype=float)
    aos = np.asarray(aos, dtype=float)
    ca, sa, cb, sb = np.cos(aoa), np.sin(aoa), np.cos(aos), np.sin(aos)
    ca, sa, cb, sb = np.broadcast_arrays(ca, sa, cb, sb)
    zero = np.zeros_like(ca)
    return np.stack(
        [
            np.stack([ca * cb, sb, sa * cb], axis=-1),
            np.stack([-ca * sb, cb, -sa * sb], axis=-1),
            np.stack([-sa, zero, ca], axis=-1),
        ],
        axis=-2,
    )


def mesh_to_wind(aoa, aos):
    """DCM that maps G vectors to W: L_WB L_GB (ADBSat's L_gw transposed)."""
    return body_to_wind(aoa, aos) @ L_GB


def quaternion_matrix_floats(x: float, y: float, z: float, w: float) -> tuple:
    """R of a unit quaternion (x, y, z, w), ROS/Hamilton (``R @ v_body`` in its frame), as nine
    floats, row-major: scipy's ``Rotation.from_quat([x, y, z, w]).as_matrix()``; the caller
    normalises."""
    xx, yy, zz = x * x, y * y, z * z
    xy, xz, yz = x * y, x * z, y * z
    wx, wy, wz = w * x, w * y, w * z
    return (
        1.0 - 2.0 * (yy + zz),
        2.0 * (xy - wz),
        2.0 * (xz + wy),
        2.0 * (xy + wz),
        1.0 - 2.0 * (xx + zz),
        2.0 * (yz - wx),
        2.0 * (xz - wy),
        2.0 * (yz + wx),
        1.0 - 2.0 * (xx + yy),
    )
