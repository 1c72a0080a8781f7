"""The scenario generator: Keplerian invariants, closed forms, an independent integration,
attitudes."""

import datetime as dt
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from adbsat_ros.bags import scenario
from adbsat_ros.physics.constants import EARTH_MU

MU = EARTH_MU


def energy(r, v):
    return 0.5 * np.sum(v * v, axis=1) - MU / np.linalg.norm(r, axis=1)


def test_circular_orbit_radius_speed_and_invariants():
    sc = scenario.Scenario(duration_s=600, altitude_km=400, inclination_deg=51.6, raan_deg=30)
    t = np.linspace(0, 600, 61)
    r, v = scenario.kepler_states(sc, t)
    radius = np.linalg.norm(r, axis=1)
    np.testing.assert_allclose(radius, scenario.EARTH_RADIUS + 400e3, rtol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), math.sqrt(MU / radius[0]), rtol=1e-12)
    np.testing.assert_allclose(
        np.sum(r * v, axis=1) / (radius * np.linalg.norm(v, axis=1)), 0.0, atol=1e-12
    )
    h = np.cross(r, v)
    np.testing.assert_allclose(h, np.broadcast_to(h[0], h.shape), rtol=1e-11)
    # orbit normal at the inclination; ascending node at the RAAN
    assert math.degrees(math.acos(h[0, 2] / np.linalg.norm(h[0]))) == pytest.approx(51.6, abs=1e-9)
    node = np.cross([0, 0, 1.0], h[0])
    assert math.degrees(math.atan2(node[1], node[0])) == pytest.approx(30.0, abs=1e-9)


def test_elliptic_orbit_perigee_apogee_energy_momentum_period():
    sc = scenario.Scenario(
        altitude_km=300,
        eccentricity=0.1,
        inclination_deg=98.0,
        raan_deg=40,
        arg_perigee_deg=70,
        true_anomaly_deg=0,
    )
    rp = scenario.EARTH_RADIUS + 300e3
    ra = rp * (1 + 0.1) / (1 - 0.1)
    assert sc.apogee_radius == pytest.approx(ra, rel=1e-14)
    t = np.linspace(0.0, sc.period, 20001)
    r, v = scenario.kepler_states(sc, t)
    radius = np.linalg.norm(r, axis=1)
    assert radius.min() == pytest.approx(rp, rel=1e-12)
    assert radius[0] == pytest.approx(rp, rel=1e-12)
    assert radius.max() == pytest.approx(ra, rel=1e-8)  # sampled near apogee
    a = (rp + ra) / 2
    np.testing.assert_allclose(energy(r, v), -MU / (2 * a), rtol=1e-11)
    h = np.cross(r, v)
    np.testing.assert_allclose(
        np.linalg.norm(h - h[0], axis=1) / np.linalg.norm(h[0]), 0.0, atol=1e-11
    )
    # periodic: back at perigee after one period; the perigee direction is set by RAAN and arg of
    # perigee
    np.testing.assert_allclose(r[-1], r[0], rtol=0, atol=1e-4)
    perigee_dir = Rotation.from_euler("ZXZ", [40, 98, 70], degrees=True).apply([1.0, 0, 0])
    np.testing.assert_allclose(r[0] / rp, perigee_dir, atol=1e-12)


def test_kepler_matches_numerical_two_body_integration():
    """An independent path: integrate r'' = -mu r / |r|^3 from the generator's initial state."""
    sc = scenario.Scenario(
        altitude_km=350,
        eccentricity=0.05,
        inclination_deg=20,
        arg_perigee_deg=10,
        true_anomaly_deg=123,
    )
    t = np.linspace(0, 3000, 31)
    r, v = scenario.kepler_states(sc, t)

    def rhs(_, y):
        rr = y[:3]
        return np.concatenate([y[3:], -MU * rr / np.linalg.norm(rr) ** 3])

    sol = solve_ivp(
        rhs,
        (0, 3000),
        np.concatenate([r[0], v[0]]),
        t_eval=t,
        rtol=1e-12,
        atol=1e-6,
        method="DOP853",
    )
    np.testing.assert_allclose(sol.y[:3].T, r, atol=1e-2)  # metres over 3000 s
    np.testing.assert_allclose(sol.y[3:].T, v, atol=1e-5)


def test_messages_stamps_counts_and_unit_quaternions():
    sc = scenario.Scenario(
        epoch_utc="2026-03-04T05:06:07.5Z",
        duration_s=12.0,
        rate_hz=4,
        state_rate_hz=2,
        attitude="tumble",
        tumble_rate_deg_s=3.0,
    )
    m = scenario.generate(sc)
    unix = dt.datetime(2026, 3, 4, 5, 6, 7, 500000, tzinfo=dt.timezone.utc).timestamp()
    assert len(m.attitudes.stamps_ns) == 12 * 4 + 1 and len(m.states.stamps_ns) == 12 * 2 + 1
    assert (
        m.states.stamps_ns[0] == round(unix * 1e9)
        and m.attitudes.stamps_ns[0] == m.states.stamps_ns[0]
    )
    assert np.all(np.diff(m.attitudes.stamps_ns) == 250_000_000)
    np.testing.assert_allclose(np.linalg.norm(m.attitudes.quaternion_xyzw, axis=1), 1.0, atol=1e-14)
    # positions at the stamps are the Kepler states at stamp - epoch
    r, _ = scenario.kepler_states(sc, (m.states.stamps_ns - m.states.stamps_ns[0]) * 1e-9)
    np.testing.assert_array_equal(m.states.position_eci, r)
    epoch_mode = scenario.generate(scenario.Scenario(duration_s=1, time_mode="epoch"))
    assert epoch_mode.states.stamps_ns[0] == 0


@pytest.mark.parametrize("eccentricity", [0.0, 0.08])
def test_nadir_attitude_axes(eccentricity):
    """Body +z to nadir, +y along -h, +x = y x z (the velocity direction within the flight-path
    angle)."""
    sc = scenario.Scenario(
        duration_s=2000, rate_hz=0.01, eccentricity=eccentricity, inclination_deg=63, raan_deg=10
    )
    m = scenario.generate(sc)
    t = (m.attitudes.stamps_ns - m.attitudes.stamps_ns[0]) * 1e-9
    r, v = scenario.kepler_states(sc, t)
    rot = Rotation.from_quat(m.attitudes.quaternion_xyzw)
    x, y, z = (rot.apply(np.tile(e, (len(t), 1))) for e in np.eye(3))
    unit = lambda a: a / np.linalg.norm(a, axis=1, keepdims=True)  # noqa: E731
    np.testing.assert_allclose(z, -unit(r), atol=1e-12)
    np.testing.assert_allclose(y, -unit(np.cross(r, v)), atol=1e-12)
    cos_to_velocity = np.sum(x * unit(v), axis=1)
    # flight-path angle gamma: cos gamma = h / (r v)
    cos_gamma = np.linalg.norm(np.cross(r, v), axis=1) / (
        np.linalg.norm(r, axis=1) * np.linalg.norm(v, axis=1)
    )
    np.testing.assert_allclose(cos_to_velocity, cos_gamma, atol=1e-12)
    if eccentricity == 0:
        np.testing.assert_allclose(cos_to_velocity, 1.0, atol=1e-12)


def test_tumble_turns_about_the_body_axis_at_the_rate():
    sc = scenario.Scenario(
        duration_s=20, rate_hz=2, attitude="tumble", tumble_rate_deg_s=2.5, tumble_axis=(1, 2, 2)
    )
    q = scenario.generate(sc).attitudes.quaternion_xyzw
    rot = Rotation.from_quat(q)
    step = rot[:-1].inv() * rot[1:]  # body-frame increments
    rotvec = step.as_rotvec()
    np.testing.assert_allclose(np.degrees(np.linalg.norm(rotvec, axis=1)), 2.5 * 0.5, rtol=1e-9)
    np.testing.assert_allclose(
        rotvec / np.linalg.norm(rotvec, axis=1, keepdims=True),
        np.tile(np.array([1, 2, 2]) / 3.0, (len(rotvec), 1)),
        atol=1e-9,
    )
    # starts nadir
    nadir = scenario.generate(scenario.Scenario(duration_s=0)).attitudes.quaternion_xyzw[0]
    np.testing.assert_allclose(q[0], nadir, atol=1e-15)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"eccentricity": 1.0}, "eccentricity"),
        ({"altitude_km": -5}, "altitude_km"),
        ({"rate_hz": 0}, "rate_hz"),
        ({"attitude": "spin"}, "attitude"),
        ({"epoch_utc": "yesterday"}, "epoch_utc"),
        ({"duration_s": float("nan")}, "duration_s"),
    ],
)
def test_bad_scenarios_name_the_field(kwargs, name):
    with pytest.raises(ValueError, match=name):
        scenario.Scenario(**kwargs)
