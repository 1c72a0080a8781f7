"""The node as a server of coefficients, and its database mode, with real rclpy.

* The ``coefficients`` topic times q A_ref (q A_ref L_ref for moments) equals the ``wrench``
  topic to 1e-9, with q = rho V^2 / 2 from the node's own /diagnostics (printed with repr, so
  exact).
* With ``coefficients_source: database`` the wrench agrees with the live panel method within the
  database's stated interpolation error at attitudes between grid nodes. The database is built
  for the flow the node sees (NRLMSISE-00 at the test's stamp), so the only difference left is
  the interpolation; the body is a convex box with shading 'none', so shading plays no part.
* A database made for another mesh, model or reference is refused, naming the mismatch, at
  start-up and as a parameter change (which leaves the old value in place).
"""

import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

import datetime as dt
import math

import numpy as np
import rclpy
from meshes import grid_box, write_obj
from rclpy.parameter import Parameter
from ros_harness import Peer, circular_orbit_state, make_context, stamp_to_float

from adbsat_ros.database.build import build_database
from adbsat_ros.environment.atmosphere import SpaceWeather
from adbsat_ros.environment.flight_conditions import flight_conditions
from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.parameters import PARAMETER_DEFAULTS
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.geometry.loading import load_mesh
from adbsat_ros.geometry.mesh import panels_from_arrays
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.ros.node import AdbsatNode

EPOCH = "2026-03-20T12:00:00"
ALTITUDE = 300e3
COM = [0.05, -0.02, 0.03]  # centre of mass [m], not the database's moment point (the origin)


@pytest.fixture(scope="module")
def box_file(tmp_path_factory):
    """A 0.6 x 0.3 x 0.2 m box (convex) as an OBJ file."""
    path = tmp_path_factory.mktemp("mesh") / "box.obj"
    write_obj(
        panels_from_arrays(*grid_box((0, 0, 0), (0.6, 0.3, 0.2), (2, 2, 2)), source="box"), path
    )
    return str(path)


def node_settings(box_file, **changes) -> WrenchSettings:
    values = dict(PARAMETER_DEFAULTS)
    values.update(
        mesh=box_file, shading="none", time_mode="epoch", epoch_utc=EPOCH, center_of_mass=COM
    )
    values.update(changes)
    return WrenchSettings.from_parameters(values)


def flow_seen_by_node(t):
    """The free stream the node computes at stamp t for the test's orbit (same settings)."""
    pos, vel = circular_orbit_state(ALTITUDE)
    utc = dt.datetime.fromisoformat(EPOCH).replace(tzinfo=dt.timezone.utc) + dt.timedelta(seconds=t)
    cond = flight_conditions(
        utc,
        np.add(pos, np.multiply(vel, t)),
        vel,
        SpaceWeather(150, 150, 4),
        frame="eci",
        accommodation_model="fixed",
        accommodation_options={"alpha": 1.0},
    )
    return cond.free_stream()


@pytest.fixture(scope="module")
def databases(box_file, tmp_path_factory):
    """A matching database (the node's own set-up at its flow) and three mismatched ones."""
    out = tmp_path_factory.mktemp("db")
    method = AeroWrenchEstimator(node_settings(box_file)).method
    # the database's moment point is the origin; the node's is COM: moments must be carried over
    method = PanelMethod(
        method.mesh,
        method.model,
        method.materials,
        options=method.options,
        reference=Reference(area=method.reference.area, length=method.reference.length),
    )
    flow = flow_seen_by_node(0.05)
    grid = dict(
        aoa_deg=np.arange(-180.0, 180.1, 10.0),
        aos_deg=np.arange(-90.0, 90.1, 10.0),
        shading="none",
        workers=1,
        progress=False,
        mesh_spec=box_file,
    )
    paths = {}
    db = build_database(method, flow, **grid)
    paths["good"] = db.save(out / "good.npz")
    newton = PanelMethod(method.mesh, "newton", method.materials, reference=method.reference)
    paths["model"] = build_database(newton, flow, **grid).save(out / "newton.npz")
    bigger = Reference(area=2.0 * method.reference.area, length=method.reference.length)
    other_ref = PanelMethod(
        method.mesh, method.model, method.materials, options=method.options, reference=bigger
    )
    paths["reference"] = build_database(other_ref, flow, **grid).save(out / "aref.npz")
    other_mesh_file = out / "box2.obj"
    write_obj(
        panels_from_arrays(*grid_box((0, 0, 0), (0.6, 0.3, 0.22), (2, 2, 2)), source="box2"),
        other_mesh_file,
    )
    other_mesh = PanelMethod(
        load_mesh(other_mesh_file),
        method.model,
        method.materials,
        options=method.options,
        reference=method.reference,
    )
    paths["mesh"] = build_database(
        other_mesh, flow, **dict(grid, mesh_spec=str(other_mesh_file))
    ).save(out / "box2.npz")
    # made by test particles (a coarse grid: each attitude is a run of 2 x 65,536 molecules);
    # on a convex body they agree with the panel method within their standard errors
    coarse = dict(
        grid, aoa_deg=np.arange(-180.0, 180.1, 30.0), aos_deg=np.arange(-90.0, 90.1, 30.0)
    )
    tpmc = build_database(
        method, flow, **dict(coarse, workers=2), solver="tpmc", particles=131_072, seed=1
    )
    paths["tpmc"] = tpmc.save(out / "tpmc.npz")
    stated = {
        "good": db.metadata["interpolation_error"],
        "tpmc": tpmc.metadata["interpolation_error"],
    }
    return paths, stated


@pytest.fixture
def ros(box_file):
    ctx, executor = make_context()
    created = []

    def start(**params):
        overrides = [
            Parameter(k, value=v)
            for k, v in dict(
                mesh=box_file,
                shading="none",
                time_mode="epoch",
                epoch_utc=EPOCH,
                center_of_mass=COM,
                diagnostics_period=0.1,
                qos_depth=100,
                **params,
            ).items()
        ]
        node = AdbsatNode(context=ctx, parameter_overrides=overrides)
        executor.add_node(node)
        created.append(node)
        return node

    peer = Peer(ctx, executor)
    yield start, peer
    executor.shutdown()
    peer.node.destroy_node()
    for node in created:
        node.destroy_node()
    rclpy.try_shutdown(context=ctx)


def vec(v):
    return np.array([v.x, v.y, v.z])


def quaternion_z(angle):
    return (0.0, 0.0, math.sin(angle / 2), math.cos(angle / 2))


def exchange(peer, attitudes, t0=0.05):
    """Send a state at 0 and one attitude per entry at t0 + 1e-3 k; return {stamp: (wrench,
    coefficients)}."""
    pos, vel = circular_orbit_state(ALTITUDE)
    peer.wrenches.clear()
    peer.coefficients.clear()
    peer.send_state(0.0, pos, vel)
    peer.spin_for(0.05)
    stamps = [t0 + 1e-3 * k for k in range(len(attitudes))]
    for t, q in zip(stamps, attitudes):
        peer.send_attitude(t, q)
    n = len(attitudes)
    assert peer.spin_until(lambda: len(peer.wrenches) == n and len(peer.coefficients) == n), (
        f"got {len(peer.wrenches)} wrenches, {len(peer.coefficients)} coefficients of {n}"
    )
    w = {round(stamp_to_float(m.header.stamp), 6): m for m in peer.wrenches}
    c = {round(stamp_to_float(m.header.stamp), 6): m for m in peer.coefficients}
    return [(w[round(t, 6)], c[round(t, 6)]) for t in stamps]


def latest_diagnostics(peer, after_published):
    """Values of the first /diagnostics status that counts at least ``after_published`` wrenches."""

    def ready():
        for msg in peer.diagnostics:
            values = {kv.key: kv.value for kv in msg.status[0].values}
            if int(values.get("published", 0)) >= after_published:
                return values
        return None

    assert peer.spin_until(lambda: ready() is not None)
    return ready()


@pytest.mark.parametrize("source", ["panel", "database"])
def test_coefficients_topic_times_q_aref_is_the_wrench(ros, databases, source):
    start, peer = ros
    params = (
        {}
        if source == "panel"
        else dict(coefficients_source="database", database_path=databases[0]["good"])
    )
    node = start(**params)
    assert peer.wait_for_subscribers()
    area = node.get_parameter("reference_area").value
    length = node.get_parameter("reference_length").value
    for k, angle in enumerate(
        (0.3, 1.1, 2.5)
    ):  # one attitude at a time: diagnostics then hold its q
        peer.diagnostics.clear()
        [(w, c)] = exchange(peer, [quaternion_z(angle)], t0=0.05 + 0.01 * k)
        values = latest_diagnostics(peer, after_published=k + 1)
        assert values["coefficients_source"] == source
        assert (
            float(values["reference_area_m2"]) == area
            and float(values["reference_length_m"]) == length
        )
        q = 0.5 * float(values["density_kg_m3"]) * float(values["relative_speed_m_s"]) ** 2
        force, torque = vec(w.wrench.force), vec(w.wrench.torque)
        assert np.linalg.norm(force) > 0 and c.header.frame_id == w.header.frame_id
        np.testing.assert_allclose(
            q * area * vec(c.wrench.force), force, rtol=1e-9, atol=1e-9 * np.linalg.norm(force)
        )
        np.testing.assert_allclose(
            q * area * length * vec(c.wrench.torque),
            torque,
            rtol=1e-9,
            atol=1e-9 * np.linalg.norm(torque),
        )


@pytest.mark.parametrize("which", ["good", "tpmc"], ids=["panel-database", "tpmc-database"])
def test_database_mode_agrees_with_the_panel_method_within_the_stated_error(ros, databases, which):
    """Also for a database made by test particles, whose stated error adds three of their
    largest standard errors to the interpolation error."""
    paths, stated = databases
    stated = stated[which]
    start, peer = ros
    node = start()
    assert peer.wait_for_subscribers()
    # attitudes between grid nodes: body rotations about z and x give aoa/aos off the 10 deg grid
    rng = np.random.default_rng(11)
    attitudes = []
    for _ in range(12):
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        angle = rng.uniform(0, math.pi)
        attitudes.append(tuple(np.append(axis * math.sin(angle / 2), math.cos(angle / 2))))
    panel = exchange(peer, attitudes)
    result = node.set_parameters(
        [
            Parameter("database_path", value=paths[which]),
            Parameter("coefficients_source", value="database"),
        ]
    )
    assert all(r.successful for r in result), [r.reason for r in result]
    database = exchange(peer, attitudes, t0=0.2)  # new stamps; the flow changes by < 1e-6 relative
    # the stated error, with the moment bound carried from the database's point to the centre of
    # mass
    error = node.estimator.database.error_bound
    carried = (
        stated["moment_coefficient"]
        + np.linalg.norm(COM)
        * stated["force_coefficient"]
        / node.get_parameter("reference_length").value
    )
    assert error["force_coefficient"] == stated["force_coefficient"]
    assert error["moment_coefficient"] == pytest.approx(carried, rel=1e-12)
    area = node.get_parameter("reference_area").value
    length = node.get_parameter("reference_length").value
    worst_f = worst_m = 0.0
    for (wp, cp), (wd, cd) in zip(panel, database):
        df = np.linalg.norm(vec(cd.wrench.force) - vec(cp.wrench.force))
        dm = np.linalg.norm(vec(cd.wrench.torque) - vec(cp.wrench.torque))
        worst_f, worst_m = max(worst_f, df), max(worst_m, dm)
        # newtons: same relation through q A (the flow differs by far less than the error bound)
        scale = np.linalg.norm(vec(wp.wrench.force)) / np.linalg.norm(vec(cp.wrench.force))
        assert np.linalg.norm(vec(wd.wrench.force) - vec(wp.wrench.force)) <= scale * (
            error["force_coefficient"] + 1e-6
        )
    print(
        f"worst |dCf| {worst_f:.3g} (bound {error['force_coefficient']:.3g}), "
        f"|dCm| {worst_m:.3g} (bound {error['moment_coefficient']:.3g})"
    )
    assert worst_f <= error["force_coefficient"] + 1e-6
    assert worst_m <= error["moment_coefficient"] + 1e-6
    assert worst_f > 0.0  # the attitudes really are between nodes: interpolation is not exact there
    assert area > 0 and length > 0


@pytest.mark.parametrize(
    "which, words",
    [
        ("model", ["gsi_model", "newton", "sentman"]),
        ("reference", ["reference area"]),
        ("mesh", ["mesh", "fingerprint"]),
    ],
)
def test_mismatched_database_is_refused_naming_the_mismatch(ros, databases, which, words):
    paths, _ = databases
    start, peer = ros
    with pytest.raises(ValueError) as info:
        start(coefficients_source="database", database_path=paths[which])
    assert "database_path" in str(info.value)
    for word in words:
        assert word in str(info.value)
    # as a run-time change: rejected with the reason, the node keeps computing with the panel method
    node = start()
    result = node.set_parameters(
        [
            Parameter("database_path", value=paths[which]),
            Parameter("coefficients_source", value="database"),
        ]
    )
    assert not all(r.successful for r in result)
    assert any(words[0] in r.reason for r in result)
    assert node.get_parameter("coefficients_source").value == "panel"
    assert node.estimator.database is None


def test_database_mode_needs_a_fixed_accommodation(ros, databases):
    start, _ = ros
    with pytest.raises(ValueError, match="accommodation_model"):
        start(
            coefficients_source="database",
            database_path=databases[0]["good"],
            accommodation_model="langmuir",
        )


def test_unreadable_database_is_refused_naming_the_file(ros, tmp_path):
    start, _ = ros
    bad = tmp_path / "not_a_database.npz"
    bad.write_bytes(b"this is not an npz file")
    with pytest.raises(ValueError) as info:
        start(coefficients_source="database", database_path=str(bad))
    assert "database_path" in str(info.value) and "not_a_database.npz" in str(info.value)
