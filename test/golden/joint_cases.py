"""The estimator's outputs for an articulated body whose joints move: the golden ``estimator``
group.

The bundled finned body (``example-finned``, four fins on hinges) is fed, ROS-free and in stamp
order as bag analysis and the node feed it, a short tumbling flight with joint states between
the attitudes (one of them beyond a hinge's limits, which is refused). Three ways to shade a
moving body are pinned: the nearest point of the configuration grid and the nearest cell of the
direction cache; the blend of the grid's points around the joint positions and of the cells
around the flow direction (on coarse grids, so that the blends weigh several parts); and the
exact shading of the body posed at every attitude's own joint positions.
"""

from __future__ import annotations

import math

#: The fins' hinges, in the body's order.
HINGES = ("fin_py_hinge", "fin_ny_hinge", "fin_pz_hinge", "fin_nz_hinge")
#: The settings common to every case.
COMMON = {
    "mesh": "example-finned",
    "gsi_model": "sentman",
    "shading": "raycast",
    "center_of_mass": [-0.02, 0.01, 0.005],
    "joint_state_timeout": 2.0,
}
#: estimator cases: (name, settings over COMMON)
JOINT_CASES = (
    ("grid_nearest", {"shading_interpolation": False, "joint_shading_interpolation": False}),
    (
        "grid_interpolated",
        {
            "shading_interpolation": True,
            "shading_cache_resolution_deg": 5.0,
            "joint_shading_interpolation": True,
            "joint_shading_resolution_deg": 5.0,
        },
    ),
    ("exact", {"joint_shading_exact": True}),
)
NS = 1_000_000_000


def flight():
    """The messages: ``[(stamp_ns, kind, payload)]`` in stamp order, kind "state" (position,
    velocity in ECI), "attitude" (quaternion x, y, z, w) or "joints" (the hinges' positions
    [rad]). A 3 s tumble at 10 deg/s, attitudes at 5 Hz, states at 1 Hz, joint states at 1 Hz
    off the attitudes' stamps (the first after the first attitude, which is refused), every
    fin turning on its own, off the configuration grids; and a refused joint state."""
    from adbsat_ros.bags import scenario

    messages = scenario.generate(
        scenario.Scenario(
            duration_s=3,
            rate_hz=5,
            state_rate_hz=1,
            altitude_km=300,
            attitude="tumble",
            tumble_rate_deg_s=10.0,
            tumble_axis=(0.3, 0.8, -0.5),
            seed=11,
        )
    )
    s, a = messages.states, messages.attitudes
    events = [
        (int(t), "state", (s.position_eci[i].tolist(), s.velocity_eci[i].tolist()))
        for i, t in enumerate(s.stamps_ns)
    ]
    events += [
        (int(t), "attitude", a.quaternion_xyzw[i].tolist()) for i, t in enumerate(a.stamps_ns)
    ]
    t0 = int(a.stamps_ns[0])
    for k in range(3):
        positions = [0.45 * math.sin(1.6 * k + 1.3 * j + 0.4) + 0.0123 * j for j in range(4)]
        events.append((t0 + k * NS + 130_000_000, "joints", positions))
    events.append((t0 + 3 * NS // 2 + 30_000_000, "joints", [0.9, 0.0, 0.0, 0.0]))
    events.sort(key=lambda e: (e[0], e[1] != "state"))
    return events


def _sample_output(sample) -> dict:
    """One sample's outputs: its stamp, the joint positions used, and two records, one in
    newtons (the wrench, the joint efforts, every link's force and torque) and one of
    coefficients."""
    joints = sample.joints
    newtons = {"force": sample.force.tolist(), "torque": sample.torque.tolist()}
    for name, effort in zip(joints.names, joints.efforts.tolist()):
        newtons[f"effort.{name}"] = effort
    for name, force, torque in zip(
        joints.link_names, joints.link_forces.tolist(), joints.link_torques.tolist()
    ):
        newtons[f"link_force.{name}"] = force
        newtons[f"link_torque.{name}"] = torque
    return {
        "stamp": sample.stamp,
        "joint_positions": joints.positions.tolist(),
        "flow_direction_body": sample.flow_direction_body.tolist(),
        "newtons": newtons,
        "coefficients": {
            "force_coefficients": sample.force_coefficients.tolist(),
            "moment_coefficients": sample.moment_coefficients.tolist(),
            "dynamic_pressure": sample.dynamic_pressure,
        },
    }


def estimator_outputs() -> dict:
    """Every case's samples (a refused attitude as its reason) and counted rejections."""
    from adbsat_ros.estimator.estimator import AeroWrenchEstimator
    from adbsat_ros.estimator.samples import Rejection
    from adbsat_ros.estimator.settings import WrenchSettings

    events = flight()
    out = {}
    for name, overrides in JOINT_CASES:
        est = AeroWrenchEstimator(WrenchSettings.from_parameters({**COMMON, **overrides}))
        samples = []
        for t_ns, kind, payload in events:
            t = t_ns / NS
            try:
                if kind == "state":
                    est.on_state(t, *payload)
                elif kind == "joints":
                    est.on_joint_state(t, HINGES, payload)
                else:
                    samples.append(_sample_output(est.on_attitude(t, payload)))
            except Rejection as exc:
                if kind == "attitude":
                    samples.append({"stamp": t, "rejected": exc.reason})
        out[name] = {
            "samples": samples,
            "rejections": {k: v for k, v in sorted(est.rejections.items()) if v},
        }
    return out
