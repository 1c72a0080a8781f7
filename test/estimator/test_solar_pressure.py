"""Solar radiation pressure in the estimator: a plate facing the Sun gets the closed-form force
(absorbing, specular, diffuse), nothing in umbra, a force that fades continuously through the
penumbra of a real orbit, the body's shadow on a wing behind it; the same force from an ECEF
state as from the ECI one; and the wrenches reach the handler's messages and bag analysis."""

from __future__ import annotations

import datetime as dt
import math

import numpy as np
import pytest
from meshes import grid_box

from adbsat_ros.environment.earth_frames import earth_orientation
from adbsat_ros.environment.sun import sun_position_eci, sun_state
from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.geometry.mesh import panels_from_arrays

EPOCH = dt.datetime(2026, 3, 20, 12, 0, 0)
R = 6378137.0 + 500e3
V = math.sqrt(3.986004418e14 / R)


def plate(size=(0.001, 1.0, 1.0), center=(0.0, 0.0, 0.0)):
    """A thin box: a plate whose +x face has the area size[1] x size[2]."""
    vertices, faces = grid_box(center, size, (1, 2, 2))
    return vertices, faces


def estimator(mesh, **overrides) -> AeroWrenchEstimator:
    params = dict(
        PARAMETER_DEFAULTS,
        mesh="@test",
        time_mode="epoch",
        epoch_utc=EPOCH.isoformat(),
        solar_pressure=True,
        shading="raycast",
        conditions_step=0.0,
    )
    params.update(overrides)
    return AeroWrenchEstimator(WrenchSettings.from_parameters(params), mesh)


def quaternion_turning_x_to(direction) -> tuple:
    """(x, y, z, w) of the shortest rotation taking the body's +x axis to ``direction``."""
    d = np.asarray(direction, float) / np.linalg.norm(direction)
    axis = np.cross([1.0, 0.0, 0.0], d)
    s, c = np.linalg.norm(axis), d[0]
    if s < 1e-15:
        return (0.0, 0.0, 0.0, 1.0) if c > 0 else (0.0, 0.0, 1.0, 0.0)
    half = 0.5 * math.atan2(s, c)
    return (*(math.sin(half) * axis / s), math.cos(half))


def sunward_state(stamp: float):
    """A position on the Sun's side of the Earth at ``stamp`` [s] after EPOCH, and a circular
    velocity normal to it."""
    sun = sun_position_eci(EPOCH + dt.timedelta(seconds=stamp))
    u = sun / np.linalg.norm(sun)
    velocity = np.cross([0.0, 0.0, 1.0], u)
    return R * u, V * velocity / np.linalg.norm(velocity)


@pytest.mark.parametrize(
    "specular, diffuse",
    [(0.0, 0.0), (0.8, 0.0), (0.0, 0.7), (0.3, 0.4)],
    ids=["absorbing", "specular", "diffuse", "mixed"],
)
def test_a_plate_facing_the_sun_gets_the_closed_form_force(specular, diffuse):
    """F = -P A (1 + rho_s + 2 rho_d / 3) s (Montenbruck & Gill 2000, eq. 3.75 at normal
    incidence), and no torque about the plate's centre."""
    mesh = panels_from_arrays(*plate())
    est = estimator(mesh, specular_reflectivity=specular, diffuse_reflectivity=diffuse)
    position, velocity = sunward_state(10.0)
    est.on_state(10.0, position, velocity)
    utc = EPOCH + dt.timedelta(seconds=10.0)
    sun = sun_state(utc, position)
    sample = est.on_attitude(10.0, quaternion_turning_x_to(sun.direction_eci))
    solar = sample.solar
    assert solar.lit_fraction == 1.0
    np.testing.assert_allclose(solar.sun_direction_body, [1.0, 0.0, 0.0], atol=1e-9)
    expected = -sun.pressure * 1.0 * (1.0 + specular + 2.0 * diffuse / 3.0)
    np.testing.assert_allclose(solar.force, [expected, 0.0, 0.0], rtol=1e-9, atol=1e-9 * -expected)
    np.testing.assert_allclose(solar.torque, 0.0, atol=1e-12)
    assert solar.area_lit == pytest.approx(1.0, rel=1e-9)
    np.testing.assert_array_equal(sample.total_force, sample.force + solar.force)


def test_nothing_pushes_in_umbra():
    mesh = panels_from_arrays(*plate())
    est = estimator(mesh)
    position, velocity = sunward_state(0.0)
    est.on_state(0.0, -position, -velocity)  # behind the Earth, in line with the Sun
    sample = est.on_attitude(0.0, (0.0, 0.0, 0.0, 1.0))
    assert sample.solar.lit_fraction == 0.0
    np.testing.assert_array_equal(sample.solar.force, 0.0)
    np.testing.assert_array_equal(sample.total_force, sample.force)
    assert np.linalg.norm(sample.force) > 0.0  # the air still pushes


def test_the_force_fades_continuously_through_the_penumbra_of_a_real_orbit():
    """A 500 km orbit in the plane of the Sun, flown through the shadow's edge at 2 Hz with the
    plate kept facing the Sun: the force is the sunlit force times the lit fraction, which
    falls from 1 to 0 without a jump over the ~9 s of penumbra."""
    mesh = panels_from_arrays(*plate())
    est = estimator(mesh)
    sun = sun_position_eci(EPOCH)
    u = sun / np.linalg.norm(sun)
    e2 = np.cross(u, [0.0, 0.0, 1.0])
    e2 /= np.linalg.norm(e2)
    w = V / R
    edge = math.pi - math.asin(6378137.0 / R)  # the orbit angle of the shadow's edge
    fractions, forces, pressures = [], [], []
    for k in range(81):
        t = (edge - math.radians(0.6)) / w + 0.5 * k
        theta = w * t
        position = R * (math.cos(theta) * u + math.sin(theta) * e2)
        velocity = V * (-math.sin(theta) * u + math.cos(theta) * e2)
        est.on_state(t, position, velocity)
        facing = sun_state(EPOCH + dt.timedelta(seconds=t), position).direction_eci
        sample = est.on_attitude(t, quaternion_turning_x_to(facing))
        fractions.append(sample.solar.lit_fraction)
        forces.append(sample.solar.force[0])
        pressures.append(sample.solar.pressure)
    fractions, forces = np.array(fractions), np.array(forces)
    assert fractions[0] == 1.0 and fractions[-1] == 0.0
    fading = (fractions > 0.0) & (fractions < 1.0)
    assert 6 <= np.count_nonzero(fading) * 0.5 <= 12  # seconds of penumbra
    assert np.all(np.diff(fractions) <= 0.0) and np.abs(np.diff(fractions)).max() < 0.2
    # absorbing, 1 m^2 facing the Sun: F = -P f A
    np.testing.assert_allclose(forces, -np.array(pressures) * fractions, rtol=1e-9, atol=1e-18)


def test_the_body_shades_a_wing_behind_it():
    """A 1 m cube before a 2 m x 1 m wing, the Sun along +x: the wing's part behind the cube is
    dark, so the sunlit area (projected on the Sun's direction) is 1 + 1 m^2, not 1 + 2, and the
    force falls with it (absorbing surfaces: F = P A_lit), as does the dark part's torque about
    a centre of mass 0.3 m off its line (0.3 m x P x 1 m^2)."""
    cube = grid_box((0.0, 0.0, 0.0), (1.0, 1.0, 1.0), (4, 4, 4))
    wing = grid_box((-1.5, 0.5, 0.0), (0.002, 2.0, 1.0), (1, 8, 4))
    vertices = np.concatenate([cube[0], wing[0]])
    faces = np.concatenate([cube[1], wing[1] + len(cube[0])])
    mesh = panels_from_arrays(vertices, faces)
    position, velocity = sunward_state(0.0)
    results = {}
    for shading in ("raycast", "none"):
        est = estimator(mesh, shading=shading, center_of_mass=[0.0, 0.3, 0.0])
        est.on_state(0.0, position, velocity)
        sun = sun_state(EPOCH, position)
        results[shading] = est.on_attitude(0.0, quaternion_turning_x_to(sun.direction_eci)).solar
    assert results["raycast"].area_lit == pytest.approx(2.0, rel=0.02)
    assert results["none"].area_lit == pytest.approx(3.0, rel=1e-9)
    pressure = results["raycast"].pressure
    assert -results["raycast"].force[0] == pytest.approx(pressure * 2.0, rel=0.02)
    dark_torque = results["none"].torque[2] - results["raycast"].torque[2]
    assert dark_torque == pytest.approx(-0.3 * pressure, rel=0.03)


def test_an_ecef_state_gives_the_force_of_the_same_eci_state():
    mesh = panels_from_arrays(*grid_box((0.0, 0.0, 0.0), (1.0, 0.6, 0.3), (2, 2, 2)))
    position, velocity = sunward_state(5.0)
    attitude = quaternion_turning_x_to([0.3, 0.8, -0.2])
    eci = estimator(mesh)
    eci.on_state(5.0, position, velocity)
    expected = eci.on_attitude(5.0, attitude).solar
    frame = earth_orientation(EPOCH + dt.timedelta(seconds=5.0))
    p_ecef, v_ecef = frame.eci_to_ecef(position, velocity)
    body_to_eci = _matrix(attitude)
    q_ecef = _quaternion(frame.celestial_to_terrestrial @ body_to_eci)
    ecef = estimator(mesh, state_frame="ecef")
    ecef.on_state(5.0, p_ecef, v_ecef)
    got = ecef.on_attitude(5.0, q_ecef).solar
    np.testing.assert_allclose(got.sun_direction_body, expected.sun_direction_body, atol=1e-8)
    np.testing.assert_allclose(got.force, expected.force, rtol=1e-6, atol=1e-14)


def _matrix(q) -> np.ndarray:
    x, y, z, w = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def _quaternion(m) -> tuple:
    w = math.sqrt(max(0.0, 1.0 + m[0, 0] + m[1, 1] + m[2, 2])) / 2.0
    return (
        (m[2, 1] - m[1, 2]) / (4 * w),
        (m[0, 2] - m[2, 0]) / (4 * w),
        (m[1, 0] - m[0, 1]) / (4 * w),
        w,
    )


def test_reflectivities_summing_over_one_are_refused_by_name():
    with pytest.raises(ValueError, match="specular_reflectivity and diffuse_reflectivity"):
        WrenchSettings.from_parameters({"specular_reflectivity": 0.7, "diffuse_reflectivity": 0.4})
