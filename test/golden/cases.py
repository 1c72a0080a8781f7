"""The outputs the golden test pins: coeff, database, bag analyze and node wrenches.

Everything is computed through the package's user-facing entry points (the ``adbsat-ros``
command line and the ROS node), on the bundled example satellite, its URDF examples at given
joint positions and small test meshes, over several gas-surface models, shading modes, the
panel method and test particles with a seed, so that any change of behaviour anywhere on those
paths shows as a changed number. (The estimator fed an articulated body's joint states is in
``joint_cases.py``.) ``make_golden.py`` writes the reference file once; the test
compares a fresh computation against it.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import math
from pathlib import Path

import numpy as np
import trimesh

FLOW = ["--speed", "7700", "--temperature", "900", "--mean-mass", "16", "--density", "3e-11"]
SPECIES = [
    "--speed",
    "7650",
    "--temperature",
    "1000",
    "--species",
    "He=1e12,O=4e15,N2=8e14,O2=4e13,Ar=1e10,H=2e11,N=3e12",
    "--density",
    "2e-11",
]
ANGLES = ["--aoa=-40,0,25,90", "--aos=-10,0,30"]


def write_meshes(folder: Path) -> dict:
    """The test meshes, written to ``folder``: name -> path."""
    folder.mkdir(parents=True, exist_ok=True)
    box = trimesh.creation.box(extents=(1.0, 0.6, 0.4))
    box.apply_translation((0.2, 0.05, -0.1))
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.5)
    # a concave body: a cube upstream of a plate, so one shades the other
    cube = trimesh.creation.box(extents=(0.5, 0.5, 0.5))
    cube.apply_translation((1.0, 0.0, 0.0))
    plate = trimesh.creation.box(extents=(0.05, 1.6, 1.2))
    shadowed = trimesh.util.concatenate([cube, plate])
    paths = {}
    for name, mesh in (("box", box), ("sphere", sphere), ("cube_plate", shadowed)):
        paths[name] = folder / f"{name}.stl"
        mesh.export(paths[name])
    return paths


#: coeff cases: (name, test mesh key or bundled body, options)
COEFF_CASES = (
    (
        "example_sentman_raycast",
        "example",
        ["--gsim", "sentman", "--shading", "raycast", *ANGLES, *FLOW],
    ),
    (
        "example_newton_projection",
        "example",
        ["--gsim", "newton", "--shading", "projection", *ANGLES, *FLOW],
    ),
    (
        "example_dria_raycast_materials",
        "example",
        [
            "--gsim",
            "dria",
            "--shading",
            "raycast",
            "--alpha",
            "0.9",
            "--material",
            "solar_array:alpha=0.7,wall_temperature=350",
            *ANGLES,
            *SPECIES,
        ],
    ),
    (
        "box_cook_none",
        "box",
        ["--gsim", "cook", "--alpha", "0.8", "--shading", "none", *ANGLES, *FLOW],
    ),
    (
        "box_schaaf_perpanel",
        "box",
        [
            "--gsim",
            "schaaf",
            "--sigma-n",
            "0.9",
            "--sigma-t",
            "0.8",
            "--shading",
            "none",
            "--per-panel",
            "--moment-ref",
            "0.1,0.2,-0.3",
            *ANGLES,
            *FLOW,
        ],
    ),
    (
        "box_storch_none",
        "box",
        ["--gsim", "storch", "--sigma-n", "0.85", "--shading", "none", *ANGLES, *FLOW],
    ),
    (
        "sphere_cll_none",
        "sphere",
        [
            "--gsim",
            "cll",
            "--alpha-n",
            "0.9",
            "--sigma-t",
            "0.95",
            "--shading",
            "none",
            *ANGLES,
            *SPECIES,
        ],
    ),
    (
        "sphere_maxwell_compat",
        "sphere",
        [
            "--gsim",
            "maxwell",
            "--alpha",
            "0.9",
            "--adbsat-compat",
            "--shading",
            "none",
            *ANGLES,
            *FLOW,
        ],
    ),
    (
        "sphere_sentman_kinetic",
        "sphere",
        [
            "--gsim",
            "sentman",
            "--incident-temperature",
            "kinetic",
            "--alpha",
            "0.85",
            "--shading",
            "none",
            *ANGLES,
            *FLOW,
        ],
    ),
    (
        "cube_plate_maxwell_raycast",
        "cube_plate",
        ["--gsim", "maxwell", "--alpha", "0.8", "--shading", "raycast", *ANGLES, *FLOW],
    ),
    (
        "cube_plate_sentman_projection",
        "cube_plate",
        [
            "--gsim",
            "sentman",
            "--shading",
            "projection",
            "--aref",
            "2.0",
            "--lref",
            "1.5",
            *ANGLES,
            *FLOW,
        ],
    ),
    (
        "box_environment_langmuir",
        "box",
        [
            "--gsim",
            "sentman",
            "--shading",
            "none",
            "--time",
            "2015-01-19T00:00:00Z",
            "--altitude",
            "300",
            "--lat",
            "10",
            "--lon",
            "20",
            "--f107",
            "121.7",
            "--f107a",
            "138.1",
            "--ap",
            "4",
            "--accommodation",
            "langmuir",
            *ANGLES,
        ],
    ),
    (
        "box_environment_state",
        "box",
        [
            "--gsim",
            "dria",
            "--shading",
            "none",
            "--time",
            "2024-05-01T12:00:00Z",
            "--position",
            "6778137,0,0",
            "--velocity",
            "0,7668.6,0",
            "--frame",
            "eci",
            "--wind",
            "10,-5,0",
            "--accommodation",
            "sesam",
            *ANGLES,
        ],
    ),
    (
        "articulated_sentman_raycast_joints",
        "example-articulated",
        [
            "--joint",
            "wing_left_hinge=20",
            "--joint",
            "wing_right_hinge=-35",
            "--gsim",
            "sentman",
            "--shading",
            "raycast",
            *ANGLES,
            *FLOW,
        ],
    ),
    (
        "finned_dria_projection_joints",
        "example-finned",
        [
            "--joint",
            "fin_py_hinge=12.5",
            "--joint",
            "fin_nz_hinge=-20",
            "--gsim",
            "dria",
            "--alpha",
            "0.9",
            "--shading",
            "projection",
            "--moment-ref=-0.1,0.02,0.0",
            "--aoa=-10,25",
            "--aos=0,15",
            *SPECIES,
        ],
    ),
    (
        "box_maxwell_tpmc_seed",
        "box",
        [
            "--gsim",
            "maxwell",
            "--alpha",
            "0.8",
            "--method",
            "tpmc",
            "--particles",
            "2000",
            "--seed",
            "7",
            *ANGLES,
            *FLOW,
        ],
    ),
    (
        "cube_plate_sentman_both_seed",
        "cube_plate",
        [
            "--gsim",
            "sentman",
            "--shading",
            "raycast",
            "--method",
            "both",
            "--particles",
            "2000",
            "--seed",
            "7",
            "--aoa=-40,25",
            "--aos=0,30",
            *FLOW,
        ],
    ),
)

#: database cases: (name, test mesh key or bundled body, options)
DATABASE_CASES = (
    (
        "example_sentman_raycast",
        "example",
        ["--gsim", "sentman", "--shading", "raycast", "--aoa=-30:15:30", "--aos=-20:20:20", *FLOW],
    ),
    (
        "box_cll_none",
        "box",
        ["--gsim", "cll", "--shading", "none", "--aoa=-180:30:180", "--aos=-90:30:90", *SPECIES],
    ),
    (
        "box_maxwell_tpmc_seed",
        "box",
        [
            "--gsim",
            "maxwell",
            "--alpha",
            "0.8",
            "--method",
            "tpmc",
            "--particles",
            "2000",
            "--seed",
            "3",
            "--aoa=-30:30:30",
            "--aos=-20:20:20",
            "--workers",
            "1",  # (the same numbers as on 2, without starting processes)
            *FLOW,
        ],
    ),
)

PARAMS_FILES = {
    "fixed": {
        "gsi_model": "sentman",
        "shading": "raycast",
        "shading_interpolation": False,  # (the golden outputs were made with the nearest cell)
        "center_of_mass": [0.1, 0.0, -0.05],
    },
    "langmuir_cll": {
        "gsi_model": "cll",
        "alpha_n": 0.9,
        "sigma_t": 0.9,
        "shading": "projection",
        "shading_interpolation": False,
        "accommodation_model": "langmuir",
        "conditions_step": 0.0,
    },
    "interpolated_solar": {  # (the node's default shading_interpolation, on a coarse cache)
        "gsi_model": "maxwell",
        "alpha": 0.85,
        "shading": "raycast",
        "shading_interpolation": True,
        "shading_cache_resolution_deg": 2.0,
        "solar_pressure": True,
        "specular_reflectivity": 0.3,
        "diffuse_reflectivity": 0.2,
        "center_of_mass": [0.05, -0.02, 0.0],
    },
}

#: node cases: (name, parameters); messages from node_messages()
NODE_CASES = (
    (
        "example_sentman_raycast",
        {
            "mesh": "example",
            "shading": "raycast",
            "shading_interpolation": False,
            "gsi_model": "sentman",
            "accommodation_model": "langmuir",
            "center_of_mass": [0.05, 0.01, -0.02],
        },
    ),
    (
        "box_dria_exact_conditions",
        {
            "mesh": "@box",
            "shading": "none",
            "gsi_model": "dria",
            "conditions_step": 0.0,
            "alpha": 0.9,
        },
    ),
)


def cli(argv) -> int:
    from adbsat_ros.cli import main

    return main([str(a) for a in argv])


def mesh_argument(key: str, meshes: dict) -> str:
    """A test mesh's path, or the name of a bundled body."""
    return str(meshes[key]) if key in meshes else key


def coeff_outputs(meshes: dict) -> dict:
    out = {}
    for name, key, options in COEFF_CASES:
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            code = cli(["coeff", mesh_argument(key, meshes), "--json", *options])
        assert code == 0, name
        out[name] = json.loads(printed.getvalue())
    return out


def database_outputs(meshes: dict, folder: Path) -> dict:
    out = {}
    for name, key, options in DATABASE_CASES:
        path = folder / f"{name}.npz"
        workers = [] if "--workers" in options else ["--workers", "2"]
        code = cli(["database", mesh_argument(key, meshes), *workers, "--out", path, *options])
        assert code == 0, name
        with np.load(path, allow_pickle=False) as data:
            out[name] = {
                k: data[k].tolist() for k in sorted(data.files) if data[k].dtype.kind in "fiu"
            }
        with open(path.with_suffix(".csv"), newline="", encoding="utf-8") as f:
            rows = [row for row in csv.reader(line for line in f if not line.startswith("#"))]
        out[name]["csv"] = [[float(x) for x in row] for row in rows[1:]]
        out[name]["csv_header"] = rows[0]
    return out


def bag_outputs(meshes: dict, folder: Path) -> dict:
    import yaml

    bag = folder / "flight"
    assert (
        cli(
            [
                "simulate",
                "--out",
                bag,
                "--duration",
                "12",
                "--rate",
                "5",
                "--state-rate",
                "1",
                "--altitude",
                "280",
                "--eccentricity",
                "0.01",
                "--attitude",
                "tumble",
                "--tumble-rate",
                "7",
                "--seed",
                "3",
            ]
        )
        == 0
    )
    params = []
    for label, values in PARAMS_FILES.items():
        path = folder / f"{label}.yaml"
        path.write_text(
            yaml.safe_dump({"adbsat_node": {"ros__parameters": values}}), encoding="utf-8"
        )
        params += ["--params", path]
    out_bag = folder / "flight_aero"
    assert (
        cli(
            [
                "bag",
                "analyze",
                bag,
                *params,
                "--out",
                out_bag,
                "--no-plots",
                "--no-progress",
                "--workers",
                "2",
            ]
        )
        == 0
    )
    csv_path = Path(str(out_bag) + ".csv")
    with open(csv_path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    header, body = rows[0], rows[1:]
    columns = {}
    for i, name in enumerate(header):
        values = []
        for row in body:
            try:
                values.append(float(row[i]))
            except ValueError:
                values.append(row[i])
        columns[name] = values
    return {"columns": columns}


def node_messages():
    """(kind, t, payload): states every 0.5 s on an inclined 300 km orbit, attitudes between them
    at stamps on and off the 10 ms knots."""
    mu, r = 3.986004418e14, 6378137.0 + 300e3
    v = math.sqrt(mu / r)
    inc = math.radians(51.6)
    w = v / r
    messages = []
    for k in range(4):
        t = 0.5 * k
        c, s = math.cos(w * t), math.sin(w * t)
        position = [r * c, r * s * math.cos(inc), r * s * math.sin(inc)]
        velocity = [-v * s, v * c * math.cos(inc), v * c * math.sin(inc)]
        messages.append(("state", t, (position, velocity)))
        for j, dt in enumerate((0.0, 0.01, 0.0137, 0.25, 0.4931)):
            angle = 0.3 * k + 0.41 * j
            axis = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
            q = [*(math.sin(angle / 2) * axis), math.cos(angle / 2)]
            messages.append(("attitude", t + dt, q))
    return messages


def node_outputs(meshes: dict) -> dict:
    import rclpy
    from rclpy.parameter import Parameter
    from ros_harness import Peer, make_context

    from adbsat_ros.ros.node import AdbsatNode

    out = {}
    for name, parameters in NODE_CASES:
        ctx, executor = make_context("single_threaded")
        values = dict(parameters, time_mode="epoch", epoch_utc="2026-03-20T12:00:00")
        if values["mesh"].startswith("@"):
            values["mesh"] = str(meshes[values["mesh"][1:]])
        node = AdbsatNode(
            context=ctx, parameter_overrides=[Parameter(k, value=v) for k, v in values.items()]
        )
        executor.add_node(node)
        peer = Peer(ctx, executor)
        try:
            assert peer.wait_for_subscribers()
            peer.spin_until(lambda: node.coefficients_pub.get_subscription_count() > 0)
            peer.spin_for(0.3)
            wrenches = []
            for kind, t, payload in node_messages():
                if kind == "state":
                    peer.send_state(t, *payload)
                    peer.spin_for(0.15)
                    continue
                n = len(peer.wrenches)
                peer.send_attitude(t, payload)
                assert peer.spin_until(
                    lambda: len(peer.wrenches) > n and len(peer.coefficients) > n
                ), (name, t)
            for w, c in zip(peer.wrenches, peer.coefficients):
                stamp = w.header.stamp.sec + 1e-9 * w.header.stamp.nanosec
                f, m = w.wrench.force, w.wrench.torque
                cf, cm = c.wrench.force, c.wrench.torque
                wrenches.append(
                    {
                        "stamp": stamp,
                        "force": [f.x, f.y, f.z],
                        "torque": [m.x, m.y, m.z],
                        "force_coefficients": [cf.x, cf.y, cf.z],
                        "moment_coefficients": [cm.x, cm.y, cm.z],
                    }
                )
            out[name] = wrenches
        finally:
            executor.shutdown()
            peer.node.destroy_node()
            node.destroy_node()
            rclpy.try_shutdown(context=ctx)
    return out


#: Numbers of a record (a JSON object of numbers and 3-vectors) that are rounding noise around
#: zero are judged within this fraction of the record's largest magnitude times the tolerance: a
#: sphere's moments about its centre (~1e-17 of its drag) round differently with another numpy,
#: and are zero either way.
RECORD_FLOOR = 1e-4


def _magnitude(value) -> float:
    """The largest finite magnitude of the numbers in a nested output (0 if none)."""
    if isinstance(value, dict):
        return max((_magnitude(v) for v in value.values()), default=0.0)
    if isinstance(value, list):
        return max((_magnitude(v) for v in value), default=0.0)
    if isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value):
        return abs(value)
    return 0.0


def _is_vector(value) -> bool:
    """Whether ``value`` is a list of at most three numbers (a vector of a record)."""
    return (
        isinstance(value, list)
        and len(value) <= 3
        and all(isinstance(x, (int, float)) for x in value)
    )


def compare(reference, actual, rtol: float, path: str = "", floor: float = 0.0) -> list:
    """Differences between two nested outputs: numbers within ``rtol`` of the largest magnitude
    of their list (so components near zero are judged on the list's scale) plus ``floor``, the
    rest equal. Entering a record sets the floor to ``RECORD_FLOOR * rtol`` times its largest
    magnitude (a record: an object of numbers and 3-vectors, as one attitude's output), and so
    does entering an object of lists (a database: its tables and axes). A row of a table whose
    entries are all rounding noise about zero (the lift of a box in a plane of symmetry,
    1e-17) is then judged on the database's scale: the last bits of a platform's vectorised
    sines and cosines (AVX-512 or AVX2 kernels) move such entries by 1e-18."""
    problems = []
    if isinstance(reference, dict):
        if set(reference) != set(actual):
            return [f"{path}: keys {sorted(set(reference) ^ set(actual))} differ"]
        if all(not isinstance(v, (list, dict)) or _is_vector(v) for v in reference.values()):
            floor = RECORD_FLOOR * rtol * _magnitude(reference)  # one attitude's record
        elif reference and all(isinstance(v, list) for v in reference.values()):
            floor = max(floor, RECORD_FLOOR * rtol * _magnitude(reference))  # a database
        for key in reference:
            problems += compare(reference[key], actual[key], rtol, f"{path}/{key}", floor)
        return problems
    if isinstance(reference, list):
        if not isinstance(actual, list) or len(reference) != len(actual):
            return [
                f"{path}: length {len(reference)} != "
                f"{len(actual) if isinstance(actual, list) else actual!r}"
            ]
        numbers = [x for x in reference if isinstance(x, (int, float)) and not isinstance(x, bool)]
        scale = max((abs(x) for x in numbers if math.isfinite(x)), default=0.0)
        for i, (a, b) in enumerate(zip(reference, actual)):
            if (
                isinstance(a, (int, float))
                and not isinstance(a, bool)
                and isinstance(b, (int, float))
            ):
                if math.isnan(a) and math.isnan(b):
                    continue
                if not abs(a - b) <= rtol * max(scale, abs(a)) + floor:
                    problems.append(f"{path}[{i}]: {b!r} != {a!r}")
            else:
                problems += compare(a, b, rtol, f"{path}[{i}]", floor)
        return problems
    if isinstance(reference, (int, float)) and not isinstance(reference, bool):
        if (
            isinstance(actual, (int, float))
            and abs(reference - actual) <= rtol * abs(reference) + floor
        ):
            return []
        return [f"{path}: {actual!r} != {reference!r}"]
    return [] if reference == actual else [f"{path}: {actual!r} != {reference!r}"]
