"""What the .obj fast path saves: ``read_obj`` (numbers converted at once) against
``read_obj_by_line`` (the reference), on the reader, on ``load_mesh`` with no store and on a
whole cold ``adbsat-ros coeff`` (one attitude, a free stream given directly, the default raycast
shading, ``ADBSAT_ROS_CACHE_DIR=off``: the file parsed and checked, as at its first load).

The meshes are written to a temporary directory: UV spheres of radius 1 m with about
``--faces`` triangles each (default 5,120 and 100,000), ``v x y z`` and ``f i j k`` lines. The
two readers are interleaved (A B B A ...) in one run; printed: the median and range of the CPU
time (user + system) of each, and what the fast path saves as a share of the line reader's.
Both readers' arrays, and both ``coeff`` outputs, are checked equal. Run::

    python bench/bench_obj_reader.py --rounds 5
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

THIS_TREE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(THIS_TREE))

from adbsat_ros.geometry import mesh_files  # noqa: E402
from adbsat_ros.geometry.loading import load_mesh  # noqa: E402

#: ``coeff`` in a fresh process with the .obj reader named by its first argument.
WRAPPER = """
import sys
from adbsat_ros.geometry import mesh_files
if sys.argv.pop(1) == "line":
    mesh_files.TEXT_READERS[".obj"] = mesh_files.read_obj_by_line
from adbsat_ros.cli import main
sys.exit(main(sys.argv[1:]))
"""
COEFF = ["--aoa", "10", "--aos", "5", "--speed", "7800", "--temperature", "1000"]
COEFF += ["--mean-mass", "16", "--density", "1e-11"]
READERS = {"fast": mesh_files.read_obj, "line": mesh_files.read_obj_by_line}


def write_sphere(directory: Path, faces: int) -> Path:
    """A UV sphere of about ``faces`` triangles written as .obj."""
    import trimesh

    n = max(4, round((faces / 4) ** 0.5))
    mesh = trimesh.creation.uv_sphere(radius=1.0, count=[n + 2, n])
    path = directory / f"sphere{len(mesh.faces)}.obj"
    with open(path, "w") as fh:
        fh.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in mesh.vertices.tolist())
        fh.writelines(f"f {a} {b} {c}\n" for a, b, c in (mesh.faces + 1).tolist())
    return path


def cpu(who=resource.RUSAGE_SELF) -> float:
    usage = resource.getrusage(who)
    return usage.ru_utime + usage.ru_stime


def measure(path: Path, rounds: int) -> None:
    text = mesh_files.decode_text(path.read_bytes(), str(path))
    fast, line = (reader(text, str(path)) for reader in READERS.values())
    assert all(np.array_equal(a, b) for a, b in zip(fast, line))
    env = dict(os.environ, PYTHONPATH=str(THIS_TREE), ADBSAT_ROS_CACHE_DIR="off")
    times = {name: {"read": [], "load_mesh": [], "coeff": []} for name in READERS}
    outputs = {}
    for k in range(rounds):
        order = list(READERS.items())
        for name, reader in order if k % 2 == 0 else order[::-1]:
            start = cpu()
            reader(text, str(path))
            times[name]["read"].append(cpu() - start)
            mesh_files.TEXT_READERS[".obj"] = reader
            start = cpu()
            load_mesh(path, store=None)
            times[name]["load_mesh"].append(cpu() - start)
            mesh_files.TEXT_READERS[".obj"] = READERS["fast"]
            start = cpu(resource.RUSAGE_CHILDREN)
            run = subprocess.run(
                [sys.executable, "-c", WRAPPER, name, "coeff", str(path), *COEFF],
                env=env,
                capture_output=True,
                text=True,
                check=True,
            )
            times[name]["coeff"].append(cpu(resource.RUSAGE_CHILDREN) - start)
            outputs[name] = run.stdout
    assert outputs["fast"] == outputs["line"]
    print(f"{len(fast.faces):,} faces, {rounds} rounds, CPU s: median [min-max]")
    for job in ("read", "load_mesh", "coeff"):
        fast_s, line_s = (statistics.median(times[name][job]) for name in READERS)
        ranges = "  ".join(
            f"{name} {statistics.median(times[name][job]):.3f} "
            f"[{min(times[name][job]):.3f}-{max(times[name][job]):.3f}]"
            for name in READERS
        )
        saved = line_s - fast_s
        print(f"  {job:9s} {ranges}  saved {saved:.3f} s, {100 * saved / line_s:.1f} %")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--faces", type=int, nargs="+", default=[5120, 100_000])
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as directory:
        for faces in args.faces:
            measure(write_sphere(Path(directory), faces), args.rounds)


if __name__ == "__main__":
    main()
