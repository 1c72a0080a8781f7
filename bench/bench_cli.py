"""Start-up time of the command line, as whole processes: ``--help`` and a one-attitude ``coeff``.

Cases, each a fresh process with the working directory set to the tree measured (so that tree's
package is the one imported), started in two ways: ``python -m adbsat_ros.cli ...`` (``-m``), and
as the installed ``adbsat-ros`` console script does it, ``from adbsat_ros.cli import main`` run
by ``python -c`` (``script``):

* ``python -c pass``: the interpreter alone (in a venv with the ROS 2 wheels, their bootstrapper
  re-executes python at every start; ``-c pass (no re-exec)`` sets the bootstrapper's guard
  variable to show what that costs);
* ``--help``: the list of subcommands (target: under 0.3 s);
* ``coeff``: one attitude (aoa 0, aos 0, the default raycast shading, a free stream given
  directly) on a 5,120-face icosphere written as STL (target: under 0.5 s), the mesh read back
  from the store of checked meshes (:mod:`adbsat_ros.geometry.mesh_store`, in a directory of
  this run, filled by one run before the timed ones: what every run after a file's first load
  sees); ``coeff, no store`` the same with the store off (``ADBSAT_ROS_CACHE_DIR=off``: a file's
  first load, parsed and checked with trimesh); ``coeff concave`` and ``coeff concave, no
  store`` the same on the example satellite refined to 6,496 faces (an OBJ with two materials,
  three bodies that shade each other: the shader's topology and its ray scene are made).

The compiled modules (.pyc) go to a directory of this run (``PYTHONPYCACHEPREFIX``), written by
the first runs, so that every tree is measured as installed, and none is written to. Every tree
given with ``--tree`` (default: the tree holding this script) is measured in the same
run, the cases interleaved (A B A B ...) so that a change in the machine's load touches all
alike. Printed: the median of ``--repeat`` runs (default 10) of the wall time and of the CPU
time (user + system) of the process, with the fastest and slowest wall times.

The two ways of starting can differ by up to ~0.15 s of system time on CPython 3.11: its frame
stack grows in 16 KiB chunks, and when a loop of calls sits on a chunk boundary every call maps
and unmaps a chunk (measured: up to 28,000 mmap/munmap pairs while coeff's modules are imported,
in scipy's docstring processing, scipy._lib._docscrape, some 400,000 Python calls reached
through trimesh; their depth is set by the chain of imports above them). ``-m`` adds the frames
of runpy and moves that depth.
``--packages`` adds ``python -c "import numpy"`` and the like for the third-party packages on
coeff's path, to tell what they cost by themselves. ``--importtime`` also runs ``coeff`` (as the
script) 5 times per tree under ``python -X importtime`` and prints where its import time goes,
by top-level package. Run::

    python bench/bench_cli.py --tree ../baseline --tree .
    python bench/bench_cli.py --importtime --mesh satellite.stl
    python bench/bench_cli.py --tree ../baseline --tree . --case "coeff (script)" --case "coeff, no"

``--case TEXT`` (repeatable) keeps only the cases whose name starts with one of them.
"""

from __future__ import annotations

import argparse
import collections
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

THIS_TREE = Path(__file__).resolve().parents[1]
#: Targets of the whole-process wall time [s].
TARGETS = {"--help": 0.3, "coeff": 0.5}
#: How the installed console script starts the command line (``python -c`` this, then args).
SCRIPT = "import sys; from adbsat_ros.cli import main; sys.exit(main())"
#: The two ways of starting the command line.
STARTS = {"-m": ["-m", "adbsat_ros.cli"], "script": ["-c", SCRIPT]}
#: The one-attitude coeff call (a free stream given directly, the default shading).
COEFF_OPTIONS = ["--speed", "7700", "--temperature", "900", "--mean-mass", "16"]
#: With --packages: the third-party imports on coeff's path, each alone in a fresh process.
PACKAGE_IMPORTS = (
    "numpy",
    "numpy, scipy.special",
    "numpy, scipy.special, scipy.spatial",
    "trimesh",
    "trimesh, embreex, scipy.special",
)
#: The mesh store's directory variable (adbsat_ros.geometry.mesh_store.CACHE_DIR_VARIABLE).
CACHE_DIR_VARIABLE = "ADBSAT_ROS_CACHE_DIR"
#: Guard variable of the ROS 2 wheels' bootstrapper: set, it does not re-execute python.
BOOTSTRAP_GUARD = "_ROS_WHEELS_BOOTSTRAP_COMPLETE"


def write_satellite(folder: Path) -> Path:
    """The example satellite refined to 6,496 faces, as an OBJ file in ``folder``."""
    from meshes import write_obj

    from adbsat_ros.geometry.example_satellite import example_satellite

    path = folder / "satellite_6496.obj"
    write_obj(example_satellite(max_edge=0.08), path)
    return path


def write_sphere(folder: Path) -> Path:
    """An icosphere of radius 1 m with 5,120 faces, as an STL file in ``folder``."""
    import trimesh

    path = folder / "icosphere_5120.stl"
    trimesh.creation.icosphere(subdivisions=4, radius=1.0).export(path)
    return path


def run_once(argv, cwd, env=None) -> tuple:
    """Wall and CPU time [s] of one process and its standard output; raises if it fails."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(argv, cwd=cwd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        command = " ".join(map(str, argv))
        raise RuntimeError(f"{command} (in {cwd}) failed:\n{done.stdout}\n{done.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, done.stdout


def import_breakdown(tree: Path, mesh: Path, env: dict, runs: int, top: int) -> str:
    """Self import time of ``coeff`` (started as the console script) by top-level package.

    The median over ``runs`` runs under ``python -X importtime``, largest first.
    """
    argv = [sys.executable, "-X", "importtime", *STARTS["script"], "coeff", str(mesh)]
    counts = []
    for _ in range(runs):
        done = subprocess.run(
            argv + COEFF_OPTIONS, cwd=tree, env=env, capture_output=True, text=True
        )
        by_package = collections.Counter()
        for line in done.stderr.splitlines():
            if not line.startswith("import time:") or "self [us]" in line:
                continue
            self_us, _, name = (part.strip() for part in line[len("import time:") :].split("|"))
            by_package[name.split(".")[0]] += int(self_us)
        counts.append(by_package)
    packages = set().union(*counts)
    median = {p: statistics.median(count[p] for count in counts) for p in packages}
    total = statistics.median(sum(count.values()) for count in counts)
    lines = [
        f"  imports of coeff (script) in {tree}: {total / 1e6:.3f} s in all, median of {runs} "
        "runs under -X importtime (which inflates them)"
    ]
    for package, us in sorted(median.items(), key=lambda item: -item[1])[:top]:
        lines.append(f"    {package:<28} {us / 1e6:7.3f} s  {100 * us / total:5.1f} %")
    return "\n".join(lines)


def main() -> int:
    """Run the cases and print the table; returns the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--tree",
        action="append",
        type=Path,
        metavar="DIR",
        help="source tree to measure (repeat to compare; default: this script's tree)",
    )
    parser.add_argument("--repeat", type=int, default=10, help="runs per case (default 10)")
    parser.add_argument(
        "--mesh", type=Path, help="mesh file for coeff (default: a 5,120-face icosphere)"
    )
    parser.add_argument(
        "--importtime", action="store_true", help="also print coeff's import time by package"
    )
    parser.add_argument(
        "--packages",
        action="store_true",
        help="also time python -c 'import X' for the third-party packages coeff imports",
    )
    parser.add_argument(
        "--case", action="append", metavar="TEXT", help="only the cases starting so (repeat)"
    )
    args = parser.parse_args()
    trees = [tree.resolve() for tree in (args.tree or [THIS_TREE])]
    for tree in trees:
        if not (tree / "adbsat_ros" / "cli").is_dir():
            parser.error(f"--tree: {tree} holds no adbsat_ros/cli package")

    with tempfile.TemporaryDirectory() as folder:
        mesh = args.mesh.resolve() if args.mesh else write_sphere(Path(folder))
        concave = write_satellite(Path(folder))
        # as started from a shell: without the guard this process may have inherited
        unset = (BOOTSTRAP_GUARD, "PYTHONDONTWRITEBYTECODE")
        shell = {k: v for k, v in os.environ.items() if k not in unset}
        shell[CACHE_DIR_VARIABLE] = str(Path(folder) / "cache")  # (this run's mesh store)
        # compiled modules kept by this run (written by the first runs), none in the trees
        shell["PYTHONPYCACHEPREFIX"] = str(Path(folder) / "pycache")
        no_store = dict(shell, **{CACHE_DIR_VARIABLE: "off"})
        no_reexec = dict(shell, **{BOOTSTRAP_GUARD: "1"})
        cases = [
            ("python -c pass", None, [sys.executable, "-c", "pass"], shell),
            ("python -c pass (no re-exec)", None, [sys.executable, "-c", "pass"], no_reexec),
        ]
        if args.packages:
            for names in PACKAGE_IMPORTS:
                argv = [sys.executable, "-c", f"import {names}"]
                cases.append((f"import {names}", None, argv, shell))
        for tree in trees:
            for start, how in STARTS.items():
                cli = [sys.executable, *how]
                cases.append((f"--help ({start})", tree, cli + ["--help"], shell))
                coeff = cli + ["coeff", str(mesh)] + COEFF_OPTIONS
                cases.append((f"coeff ({start})", tree, coeff, shell))
            cli = [sys.executable, *STARTS["script"]]
            for name, path in (("coeff", mesh), ("coeff concave", concave)):
                coeff = cli + ["coeff", str(path)] + COEFF_OPTIONS
                if name != "coeff":
                    cases.append((f"{name} (script)", tree, coeff, shell))
                cases.append((f"{name}, no store (script)", tree, coeff, no_store))
        if args.case:
            cases = [case for case in cases if case[0].startswith(tuple(args.case))]
        for _, tree, argv, env in cases:  # modules compiled; the mesh store filled: read back
            run_once(argv, tree or THIS_TREE, env)
        times = {index: [] for index in range(len(cases))}
        for _ in range(args.repeat):
            for index, (_, tree, argv, env) in enumerate(cases):
                times[index].append(run_once(argv, tree or THIS_TREE, env)[:2])

        print(
            f"# python {platform.python_version()} ({sys.executable}), {os.cpu_count()} CPUs, "
            f"load average {os.getloadavg()[0]:.2f}; coeff mesh {mesh.name}; "
            f"median of {args.repeat} runs"
        )
        print(f"{'case':<40} {'tree':<20} {'wall s':>7} {'cpu s':>7} {'min':>6} {'max':>6}  target")
        for index, (name, tree, _, _) in enumerate(cases):
            wall = [w for w, _ in times[index]]
            cpu = [c for _, c in times[index]]
            target = TARGETS.get(name.split(" (")[0])
            verdict = ""
            if target is not None:
                met = statistics.median(wall) < target
                verdict = f"< {target:g} s {'met' if met else 'NOT met'}"
            print(
                f"{name:<40} {str(tree or '-'):<20} {statistics.median(wall):7.3f} "
                f"{statistics.median(cpu):7.3f} {min(wall):6.3f} {max(wall):6.3f}  {verdict}"
            )
        if args.importtime:
            for tree in trees:
                print(import_breakdown(tree, mesh, shell, runs=5, top=12))
    return 0


if __name__ == "__main__":
    sys.exit(main())
