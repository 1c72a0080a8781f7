"""How far an articulated body's cached shading puts the wrench from shading at the exact
configuration and flow direction.

Usage:
    python bench/articulated_shading_error.py [--cases 12] [--seed 3]

For the bundled finned body (four fins within +-10 deg) and the example satellite with wings
(two hinges within +-60 deg), at their default refinement: ``--cases`` random flow directions
(angle of attack within +-40 deg, any sideslip) and joint positions. The reference is
:class:`~adbsat_ros.physics.articulated_method.ArticulatedMethod` with the lighting of a ray
cast at the exact configuration and direction; each grid setting gives the node's lighting
(the shading cache of the model those parameters build) to the same method.
Printed per body and setting: the largest error over the cases relative to the exact force's
magnitude, the exact moment's, and the largest exact joint effort (each case's own).
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from adbsat_ros.estimator.settings import WrenchSettings, setup_from_settings
from adbsat_ros.geometry import frames
from adbsat_ros.geometry.articulated import ArticulatedBody
from adbsat_ros.geometry.example_urdf import example_finned_urdf, example_satellite_urdf
from adbsat_ros.physics.articulated_method import ArticulatedMethod
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.model import build_model
from adbsat_ros.physics.model_evaluate import blended_lighting
from adbsat_ros.shading.shader import make_shader

#: Grid settings compared (node parameters), by name.
SETTINGS = {
    "nearest 0.25 deg, directions nearest": {"shading_interpolation": False},
    "nearest 0.25 deg, directions interpolated": {"shading_interpolation": True},
    "nearest 1 deg, directions interpolated": {
        "shading_interpolation": True,
        "joint_shading_resolution_deg": 1.0,
    },
    "nearest 2 deg, directions interpolated": {
        "shading_interpolation": True,
        "joint_shading_resolution_deg": 2.0,
    },
    "blend 2 deg, directions interpolated": {
        "shading_interpolation": True,
        "joint_shading_resolution_deg": 2.0,
        "joint_shading_interpolation": True,
    },
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cases", type=int, default=12)
    parser.add_argument("--seed", type=int, default=3)
    args = parser.parse_args()
    flow = FreeStream(7700.0, 900.0, mean_mass_amu=16.0)
    bodies = (
        ("finned", example_finned_urdf(), math.radians(10.0)),
        ("wings", example_satellite_urdf(), math.radians(60.0)),
    )
    for name, urdf, span in bodies:
        body = ArticulatedBody.from_urdf(urdf, source=name)
        method = ArticulatedMethod(body)
        rng = np.random.default_rng(args.seed)
        cases = []
        for _ in range(args.cases):
            u = frames.flow_direction(
                math.radians(rng.uniform(-40.0, 40.0)), math.radians(rng.uniform(-180.0, 180.0))
            )
            q = dict(zip(body.joints, rng.uniform(-span, span, len(body.joints)).tolist()))
            mesh = body.mesh(q)
            exact = method.coefficients(
                flow,
                q,
                flow_direction=u,
                lighting=make_shader(mesh, topology_store=None).lighting(u),
            )
            cases.append((u, q, exact))
        print(f"{name}: {body.mesh().n_panels} faces, {args.cases} cases")
        for label, parameters in SETTINGS.items():
            settings = WrenchSettings.from_parameters(parameters)
            cache = build_model(setup_from_settings(settings), body).cache
            worst = np.zeros(3)
            for u, q, exact in cases:
                lighting = blended_lighting(cache.read(u, cache.vertices(q)))
                got = method.coefficients(flow, q, flow_direction=u, lighting=lighting)
                errors = (
                    np.linalg.norm(got.total.Cf_G - exact.total.Cf_G)
                    / np.linalg.norm(exact.total.Cf_G),
                    np.linalg.norm(got.total.Cm_G - exact.total.Cm_G)
                    / np.linalg.norm(exact.total.Cm_G),
                    np.abs(got.effort_coefficients - exact.effort_coefficients).max()
                    / np.abs(exact.effort_coefficients).max(),
                )
                worst = np.maximum(worst, errors)
            print(
                f"  {label:45s} force {worst[0]:.1e}  moment {worst[1]:.1e}  "
                f"joint effort {worst[2]:.1e}"
            )


if __name__ == "__main__":
    main()
