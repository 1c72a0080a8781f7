"""The node's torque is continuous in attitude: along a slow tumble of the example satellite the
cached, interpolated shading gives the exact (uncached) torque within 1e-3 of its range, with no
step between messages larger than twice the exact torque's own step there; the nearest cell's
shading does not (docs/shading.md, "Interpolation")."""

from __future__ import annotations

import math

import numpy as np
import pytest

from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.shading.shader import make_shader

R = 6378137.0 + 300e3
V = math.sqrt(3.986004418e14 / R)
RATE = math.radians(1.0)  # [rad/s]
HZ = 20.0
SECONDS = 30.0
#: The tumble keeps the flow above the arrays' plane. Where it crosses that plane the exact torque
#: itself jumps (the thin arrays seen edge-on: the lit face changes from one side to the other),
#: and any cache spreads that jump over about one cell (docs/shading.md).
PITCH_DEG = 1.0
AXIS = np.array([0.1, 0.2, 1.0]) / np.linalg.norm([0.1, 0.2, 1.0])  # mostly yaw


def quaternion_product(a, b):
    """Hamilton product of (x, y, z, w) quaternions."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def tumble(resolution_deg: float, interpolation: bool, samples: int = 16) -> tuple:
    """Torques [N m] of the estimator and of the exact shading at every message of the tumble."""
    params = dict(
        PARAMETER_DEFAULTS,
        mesh="example",
        shading="raycast",
        shading_cache_resolution_deg=resolution_deg,
        shading_interpolation=interpolation,
        shading_samples=samples,
        time_mode="epoch",
        conditions_step=0.0,
    )
    est = AeroWrenchEstimator(WrenchSettings.from_parameters(params))
    shader = make_shader(est.mesh, mode="raycast", samples=params["shading_samples"])
    # the body's x axis 5 deg off the velocity (+y of the orbit at t = 0), then turning about
    # AXIS: the flow comes more and more from the side, and the body shades the arrays more
    yaw, pitch = math.radians(95.0), math.radians(PITCH_DEG)
    start = quaternion_product(
        (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)),
        (0.0, math.sin(pitch / 2), 0.0, math.cos(pitch / 2)),
    )
    cached, exact = [], []
    for k in range(int(SECONDS * HZ)):
        t = 10.0 + k / HZ
        half = 0.5 * RATE * (t - 10.0)
        turn = (*(math.sin(half) * AXIS), math.cos(half))
        w = V / R
        position = [R * math.cos(w * t), R * math.sin(w * t), 0.0]
        velocity = [-V * math.sin(w * t), V * math.cos(w * t), 0.0]
        est.on_state(t, position, velocity)
        sample = est.on_attitude(t, quaternion_product(start, turn))
        u = sample.flow_direction_body
        coefficients = est.method.coefficients(
            sample.conditions.free_stream(), flow_direction=u, lighting=shader.lighting(u)
        )
        cached.append(sample.torque)
        exact.append(coefficients.torque(sample.dynamic_pressure))
    return np.array(cached), np.array(exact)


def continuity(cached: np.ndarray, exact: np.ndarray) -> tuple:
    """(largest |cached - exact| over the exact torque's range, largest ratio of a step between
    consecutive messages to the exact torque's step there), on torque vectors."""
    span = max(np.linalg.norm(exact - e, axis=1).max() for e in exact)
    error = np.linalg.norm(cached - exact, axis=1).max() / span
    steps = np.linalg.norm(np.diff(cached, axis=0), axis=1)
    exact_steps = np.linalg.norm(np.diff(exact, axis=0), axis=1)
    assert exact_steps.min() > 0.0  # the attitude turns at every message
    return error, (steps / exact_steps).max()


def test_the_interpolated_cache_follows_the_exact_torque_through_a_slow_tumble():
    error, step_ratio = continuity(*tumble(0.25, True))
    assert error < 1e-3
    assert step_ratio <= 2.0


@pytest.mark.parametrize("resolution_deg", [0.25, 1.0])
def test_interpolated_stays_smooth_where_the_nearest_cell_steps_at_cell_borders(resolution_deg):
    """The same tumble with the nearest cell's lighting steps several times the exact step at
    cell borders, and strays further from the exact torque; interpolated, coarser cells stay
    within the bound."""
    error, step_ratio = continuity(*tumble(resolution_deg, True))
    assert error < 1e-3 and step_ratio <= 2.0
    nearest_error, nearest_ratio = continuity(*tumble(resolution_deg, False))
    assert nearest_ratio > 3.0 and nearest_error > 3.0 * error
