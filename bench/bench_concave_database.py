"""Benchmark of concave bodies' database builds on one worker, against another tree.

The 73 x 37 grid (aoa -180:5:180, aos -90:5:90, 2701 attitudes), Sentman, ray-cast shading,
``--workers 1``, of (a) a T-shape, 864 faces: a 1 x 1 x 2.25 m stem into a 1 x 3 x 1 m bar
across its top, each a closed box of 6 x 6-cell faces (two convex parts, each shading the
other); (b) the example satellite. Each build runs in a fresh process of each tree in turn,
round by round (interleaved); the figures are its wall clock and CPU time (the build only, not
the start-up). Run (``--baseline`` may be given more than once)::

    python bench/bench_concave_database.py --baseline ../base1696 --rounds 5
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parents[1]
BUILD = """
import json, sys, time
import numpy as np
from adbsat_ros import FreeStream, PanelMethod
from adbsat_ros.database.build import build_database
from adbsat_ros.geometry.loading import resolve_mesh
spec = sys.argv[1]
method = PanelMethod(resolve_mesh(spec), "sentman")
aoa, aos = np.arange(-180.0, 180.001, 5.0), np.arange(-90.0, 90.001, 5.0)
wall, cpu = time.perf_counter(), time.process_time()
build_database(method, FreeStream(7500.0, 900.0, mean_mass_amu=16.0), aoa, aos,
               shading="raycast", workers=1, progress=False, mesh_spec=spec)
print(json.dumps([time.perf_counter() - wall, time.process_time() - cpu]))
"""


def box(lo, hi, n: int) -> tuple:
    """A closed box lo..hi [m], each face n x n cells of two triangles, normals outward."""
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    s, t = (g.ravel() for g in np.meshgrid(*2 * [np.linspace(0.0, 1.0, n + 1)], indexing="ij"))
    i, j = (g.ravel() for g in np.meshgrid(np.arange(n), np.arange(n), indexing="ij"))
    v00 = i * (n + 1) + j
    cells = np.vstack(
        [
            np.column_stack([v00, v00 + n + 1, v00 + n + 2]),
            np.column_stack([v00, v00 + n + 2, v00 + 1]),
        ]
    )
    vertices, faces = [], []
    for axis in range(3):
        a, b = (axis + 1) % 3, (axis + 2) % 3  # (a, b, axis) right-handed: cells face +axis
        for side, value in ((1, hi[axis]), (-1, lo[axis])):
            v = np.empty((s.size, 3))
            v[:, axis], v[:, a], v[:, b] = (
                value,
                lo[a] + s * (hi[a] - lo[a]),
                lo[b] + t * (hi[b] - lo[b]),
            )
            faces.append((cells if side > 0 else cells[:, ::-1]) + sum(map(len, vertices)))
            vertices.append(v)
    return np.vstack(vertices), np.vstack(faces)


def write_t_shape(path: Path) -> Path:
    """The T-shape (module docstring) as an OBJ file."""
    stem, bar = (
        box((-0.5, -0.5, -1.0), (0.5, 0.5, 1.25), 6),
        box((-0.5, -1.5, 1.0), (0.5, 1.5, 2.0), 6),
    )
    vertices = np.vstack([stem[0], bar[0]])
    faces = np.vstack([stem[1], bar[1] + len(stem[0])])
    lines = [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in faces]
    path.write_text("\n".join(lines) + "\n")
    return path


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--baseline", action="append", default=[], help="another tree, measured alternately"
    )
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args(argv)
    trees = [("this tree", HERE)] + [
        (f"baseline{k or ''}", Path(tree).resolve()) for k, tree in enumerate(args.baseline)
    ]
    for name, tree in trees:
        commit = subprocess.run(
            ["git", "-C", str(tree), "rev-parse", "--short", "HEAD"], capture_output=True, text=True
        )
        print(f"{name}: {tree} at {commit.stdout.strip() or '?'}")
    print(f"command: {' '.join([os.path.basename(sys.executable)] + sys.argv)}")
    with tempfile.TemporaryDirectory() as folder:
        bodies = [
            ("T-shape 864 faces", str(write_t_shape(Path(folder) / "t_shape.obj"))),
            ("example satellite", "example"),
        ]
        times: dict = {}
        for _ in range(args.rounds):
            for name, tree in trees:
                for body, spec in bodies:
                    env = dict(os.environ, PYTHONPATH=str(tree))
                    out = subprocess.run(
                        [sys.executable, "-c", BUILD, spec],
                        env=env,
                        cwd=tree,
                        capture_output=True,
                        text=True,
                        check=True,
                    )
                    times.setdefault((body, name), []).append(
                        json.loads(out.stdout.splitlines()[-1])
                    )
    print(f"2701 attitudes, --workers 1, {args.rounds} rounds: median (range) [s]")
    for (body, name), runs in times.items():
        wall, cpu = np.array(runs).T
        span = " ".join(
            f"{what} {statistics.median(v):6.2f} ({v.min():.2f}-{v.max():.2f})"
            for what, v in (("wall", wall), ("CPU", cpu))
        )
        print(f"{body:<20} {name:<10} {span}")
    print("this tree's CPU over each baseline's, round by round: median (range)")
    for (body, name), runs in times.items():
        if name != trees[0][0]:
            ratio = np.array(times[body, trees[0][0]])[:, 1] / np.array(runs)[:, 1]
            spread = f"({ratio.min():.2f}-{ratio.max():.2f})"
            print(f"{body:<20} {name:<10} {np.median(ratio):.2f} {spread}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
