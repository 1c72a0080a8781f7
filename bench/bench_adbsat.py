"""Reference bench: ADBSat under GNU Octave against this tree (and a baseline tree), interleaved.

ADBSat (GPL, not part of this project) runs unmodified from the directory given with
``--adbsat DIR`` (or ``ADBSAT_DIR``); a driver of a few lines calling its public functions
(``ADBSatImport``, ``ADBSatFcn``) is written to a temporary directory. Without ``octave`` or
that directory the ADBSat columns say so and the rest runs. Every tool computes the same thing:
Sentman, alpha 1, wall 300 K, a free stream of 7500 m/s, 900 K, 16 amu given directly (ADBSat:
its speed ratio and ``Tinf``), shading on (ADBSat: its barycentre projection; this package:
``--shading``, default raycast), the same OBJ file (read by ADBSat's own importer). Cases:

* ``one``: one attitude (aoa 10, aos 5) on a 5,120-face icosphere, each a whole process. ADBSat:
  Octave importing the OBJ and computing (``from OBJ``), and Octave computing from the model
  file its importer wrote before (``from .mat``); both after an untimed run (file cache warm).
  This package: ``adbsat-ros coeff`` (as the console script starts it) with an empty mesh store
  (``first run``, a fresh ``ADBSAT_ROS_CACHE_DIR`` each time) and with the store filled
  (``later runs``). Wall and CPU time of the process.
* ``sphere-db``, ``tshape-db``: the 2,701-attitude database (aoa -180:5:180, aos -90:5:90;
  ``--step`` coarsens it) of the icosphere and of the T-shape of
  ``bench_concave_database.py``, one worker: ADBSat's ``ADBSatFcn`` (its per-attitude files
  and their merge included) timed inside Octave, against ``build_database`` timed in its
  process; wall and CPU.

Rounds alternate the tools (the order reversed every other round). Printed: medians (range),
the load average at each figure, ADBSat / this tree ratios, and max |dC| (Cf_w, Cm_B) of this
tree against ADBSat, so that like is timed against like. Run::

    python bench/bench_adbsat.py --adbsat ../adbsat_src --baseline ../base1696
    python bench/bench_adbsat.py --adbsat ../adbsat_src --case one --rounds 10
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from bench_cli import BOOTSTRAP_GUARD, CACHE_DIR_VARIABLE, SCRIPT
from bench_cli import run_once as timed
from bench_concave_database import write_t_shape

HERE = Path(__file__).resolve().parents[1]
SPEED, TEMPERATURE, MASS_AMU, ALPHA, WALL_K = 7500.0, 900.0, 16.0, 1.0, 300.0
BOLTZMANN, AMU = 1.3806503e-23, 1.66053906660e-27  # as adbsat_ros.physics.constants
GAS = ["--speed", f"{SPEED:g}", "--temperature", f"{TEMPERATURE:g}", "--mean-mass", f"{MASS_AMU:g}"]
ONE = (10.0, 5.0)
CASES = ("one", "sphere-db", "tshape-db")
#: Left out of the processes' environment: as started from a shell, modules compiled once.
UNSET = (BOOTSTRAP_GUARD, "PYTHONDONTWRITEBYTECODE")
#: Octave driver: ADBSat's public functions only; %-fields filled from Python.
DRIVER = """addpath(genpath('{adbsat}'));
p.gsi_model = 'sentman'; p.alpha = {alpha!r}; p.Tw = {wall!r}; p.Tinf = {tinf!r}; p.s = {s!r};
if {from_mat}, model = '{mat}'; else, model = ADBSatImport('{obj}', '{work}', 0); end
w = tic; c = cputime;
out = ADBSatFcn(model, '{result}', p, {aoa}, {aos}, 1, 0, 0, 1, 0);
t = [toc(w), cputime - c];
load(out);
if exist('aedb', 'var')
  a = aedb.aero;
  rows = [aedb.aoa(:), aedb.aos(:), a.Cf_wX(:), a.Cf_wY(:), a.Cf_wZ(:), ...
          a.Cm_BX(:), a.Cm_BY(:), a.Cm_BZ(:)];
else
  rows = [aoa, aos, Cf_w', Cm_B'];
end
dlmwrite('{table}', rows, 'precision', 17);
printf('ADBSAT_TIMES %.6f %.6f\\n', t);
"""
#: This package's database build, timed in its process; the coefficients saved for the check.
BUILD = """
import json, sys, time
import numpy as np
from adbsat_ros import FreeStream, PanelMethod
from adbsat_ros.database.build import build_database
from adbsat_ros.geometry.loading import resolve_mesh
spec, out, step, shading = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
method = PanelMethod(resolve_mesh(spec), "sentman")
aoa, aos = np.arange(-180.0, 180.001, step), np.arange(-90.0, 90.001, step)
wall, cpu = time.perf_counter(), time.process_time()
db = build_database(method, FreeStream(%r, %r, mean_mass_amu=%r), aoa, aos,
                    shading=shading, workers=1, progress=False, mesh_spec=spec)
print(json.dumps([time.perf_counter() - wall, time.process_time() - cpu]))
np.savez(out, aoa=db.aoa_deg, aos=db.aos_deg, Cf_w=db.Cf_w, Cm_B=db.Cm_B)
""" % (SPEED, TEMPERATURE, MASS_AMU)


def octave_command() -> list | None:
    """The Octave interpreter, quiet and without start-up files, or None."""
    exe = shutil.which("octave-cli") or shutil.which("octave")
    return [exe, "-q", "--norc", "--no-window-system"] if exe else None


def adbsat_run(octave, adbsat, folder, obj, aoa, aos, from_mat, tag) -> tuple:
    """Run the driver; returns (process wall, process CPU, ADBSat's own (wall, CPU), table)."""
    s = SPEED / np.sqrt(2.0 * BOLTZMANN * TEMPERATURE / (MASS_AMU * AMU))
    work = folder / "adbsat"
    result = work / f"result_{tag}"
    result.mkdir(parents=True, exist_ok=True)
    table = work / f"table_{tag}.csv"
    script = work / f"driver_{tag}.m"
    script.write_text(
        DRIVER.format(
            adbsat=adbsat,
            alpha=ALPHA,
            wall=WALL_K,
            tinf=TEMPERATURE,
            s=float(s),
            obj=obj,
            work=work,
            mat=work / f"{obj.stem}.mat",
            from_mat=int(from_mat),
            result=result,
            aoa=aoa,
            aos=aos,
            table=table,
        )
    )
    wall, cpu, out = timed(octave + [str(script)], work)
    line = [x for x in out.splitlines() if x.startswith("ADBSAT_TIMES")]
    if not line:
        raise RuntimeError(f"ADBSat under Octave printed no times:\n{out}")
    inner = tuple(map(float, line[0].split()[1:]))
    return wall, cpu, inner, np.loadtxt(table, delimiter=",", ndmin=2)


def adbsat_table(rows: np.ndarray) -> dict:
    """ADBSat's rows (aoa, aos [rad], Cf_w, Cm_B) keyed by rounded degrees."""
    return {
        (round(float(np.degrees(r[0])), 6), round(float(np.degrees(r[1])), 6)): r[2:] for r in rows
    }


def max_difference(ours: dict, theirs: dict) -> str:
    """max |dCf_w|, max |dCm_B| over the attitudes both have, and where the first is."""
    keys = sorted(set(ours) & set(theirs))
    d = np.array([np.abs(ours[k] - theirs[k]) for k in keys])
    worst = keys[int(np.argmax(d[:, :3].max(axis=1)))]
    return (
        f"max |dCf_w| {d[:, :3].max():.3g} (at aoa, aos {worst}), max |dCm_B| {d[:, 3:].max():.3g}"
        f" over {len(keys)} attitudes"
    )


def commit_of(tree: Path) -> str:
    done = subprocess.run(["git", "-C", str(tree), "rev-parse", "--short", "HEAD"], text=True,
                          capture_output=True)  # fmt: skip
    return done.stdout.strip() or "?"


def summary(name: str, runs: list, loads: list, unit: str = "s") -> str:
    """One printed line: wall and CPU medians (ranges), load averages."""
    wall, cpu = np.array(runs).T
    return (
        f"  {name:<34} wall {statistics.median(wall):8.3f} ({wall.min():.3f}-{wall.max():.3f})"
        f"  CPU {statistics.median(cpu):8.3f} ({cpu.min():.3f}-{cpu.max():.3f}) {unit}"
        f"  load {min(loads):.2f}-{max(loads):.2f}"
    )


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--adbsat", type=Path, default=os.environ.get("ADBSAT_DIR"),
                        help="ADBSat's source directory (default: $ADBSAT_DIR)")  # fmt: skip
    parser.add_argument("--baseline", type=Path, help="another tree, measured alternately")
    parser.add_argument("--case", action="append", choices=CASES, help="(repeatable; default all)")
    parser.add_argument("--rounds", type=int, default=5, help="rounds of 'one' (default 5)")
    parser.add_argument("--db-rounds", type=int, default=1, help="database rounds (default 1)")
    parser.add_argument("--step", type=float, default=5.0, help="database grid step [deg]")
    parser.add_argument("--shading", default="raycast", choices=("raycast", "projection"),
                        help="this package's shading (default raycast)")  # fmt: skip
    args = parser.parse_args(argv)
    cases = args.case or list(CASES)
    trees = [("this tree", HERE)]
    if args.baseline:
        trees.append(("baseline", args.baseline.resolve()))
    octave = octave_command()
    adbsat = args.adbsat.resolve() if args.adbsat else None
    have_adbsat = bool(octave and adbsat and (adbsat / "ADBSatFcn.m").is_file())
    for name, tree in trees:
        print(f"{name}: {tree} at {commit_of(tree)}")
    if have_adbsat:
        version = subprocess.run(octave + ["--version"], capture_output=True, text=True)
        print(f"ADBSat: {adbsat} ({commit_of(adbsat)}), {version.stdout.splitlines()[0]}")
    else:
        print("ADBSat/Octave not installed: skipped (octave on PATH and --adbsat DIR needed)")
    print(f"command: {' '.join([os.path.basename(sys.executable)] + sys.argv)}")
    print(f"{os.cpu_count()} CPUs; load average at start {os.getloadavg()[0]:.2f}")

    with tempfile.TemporaryDirectory() as name:
        folder = Path(name)
        import trimesh

        sphere = folder / "icosphere_5120.obj"
        trimesh.creation.icosphere(subdivisions=4, radius=1.0).export(sphere)
        shell = {k: v for k, v in os.environ.items() if k not in UNSET}
        shell["PYTHONPYCACHEPREFIX"] = str(folder / "pycache")
        if "one" in cases:
            one_attitude(
                args, trees, octave if have_adbsat else None, adbsat, folder, sphere, shell
            )
        bodies = [(c, p) for c, p in (("sphere-db", sphere), ("tshape-db", None)) if c in cases]
        for case, path in bodies:
            path = path or write_t_shape(folder / "t_shape.obj")
            database(args, trees, octave if have_adbsat else None, adbsat, folder, path, shell)
    return 0


def one_attitude(args, trees, octave, adbsat, folder, sphere, shell) -> None:
    """Case ``one``: whole processes, interleaved."""
    tools = []
    if octave:
        for from_mat, label in ((False, "ADBSat, from OBJ"), (True, "ADBSat, from .mat")):
            tools.append((label, "adbsat", from_mat))
    for name, tree in trees:
        argv = [sys.executable, "-c", SCRIPT, "coeff", str(sphere), "--json", "--aoa", "10",
                "--aos", "5", "--shading", args.shading, *GAS]  # fmt: skip
        for label in ("first run", "later runs"):
            tools.append((f"{name}, {label}", (tree, argv), label == "first run"))
    times = {label: [] for label, _, _ in tools}
    loads = {label: [] for label, _, _ in tools}
    tables, fresh = {}, iter(range(10**6))
    for turn in range(-1, args.rounds):  # turn -1: untimed (files, modules, the store warm)
        order = tools[::-1] if turn % 2 == 1 and turn > 0 else tools
        for label, how, flag in order:
            if how == "adbsat":
                wall, cpu, _, rows = adbsat_run(octave, adbsat, folder, sphere, *ONE, flag, "one")
                tables["ADBSat"] = adbsat_table(rows)
            else:
                tree, argv = how
                # first run: a new, empty store; later runs: the tree's store, filled at turn -1
                store = folder / (f"store-{next(fresh)}" if flag else f"store-{tree.name}")
                env = dict(shell, **{CACHE_DIR_VARIABLE: str(store), "PYTHONPATH": str(tree)})
                wall, cpu, out = timed(argv, tree, env)
                (row,) = json.loads(out)
                tables[label] = {ONE: np.array(row["Cf_w"] + row["Cm_B"])}
            if turn >= 0:
                times[label].append((wall, cpu))
                loads[label].append(os.getloadavg()[0])
    print(f"\none attitude as a whole process, sphere 5,120 faces, {args.rounds} rounds [s]:")
    for label, _, _ in tools:
        print(summary(label, times[label], loads[label]))
    if not octave:
        print("  ADBSat/Octave not installed: skipped")
        return
    warm = statistics.median(w for w, _ in times["ADBSat, from OBJ"])
    warm_mat = statistics.median(w for w, _ in times["ADBSat, from .mat"])
    for label in times:
        if not label.startswith("ADBSat"):
            ours = statistics.median(w for w, _ in times[label])
            print(
                f"  ADBSat from OBJ / {label}: {warm / ours:.2f}; from .mat: {warm_mat / ours:.2f}"
            )
    for name, _ in trees:
        diff = max_difference(tables[f"{name}, later runs"], tables["ADBSat"])
        print(f"  {name} against ADBSat: {diff}")


def database(args, trees, octave, adbsat, folder, path, shell) -> None:
    """Cases ``sphere-db`` and ``tshape-db``: ADBSat's and this package's build, interleaved."""
    grid = f"-180:{args.step:g}:180", f"-90:{args.step:g}:90"
    tools = (["ADBSat"] if octave else []) + [name for name, _ in trees]
    times = {tool: [] for tool in tools}
    loads = {tool: [] for tool in tools}
    tables = {}
    for turn in range(args.db_rounds):
        for tool in tools if turn % 2 == 0 else tools[::-1]:
            if tool == "ADBSat":
                _, _, inner, rows = adbsat_run(octave, adbsat, folder, path, *grid, False, "db")
                tables[tool] = adbsat_table(rows)
            else:
                tree = dict(trees)[tool]
                out = folder / f"db_{tool.replace(' ', '_')}.npz"
                argv = [sys.executable, "-c", BUILD, str(path), str(out), str(args.step)]
                _, _, stdout = timed(argv + [args.shading], tree, dict(shell, PYTHONPATH=str(tree)))
                inner = tuple(json.loads(stdout.splitlines()[-1]))
                db = np.load(out)
                rows = np.concatenate([db["Cf_w"], db["Cm_B"]], axis=-1)
                tables[tool] = {
                    (round(float(a), 6), round(float(b), 6)): rows[i, j]
                    for i, a in enumerate(db["aoa"])
                    for j, b in enumerate(db["aos"])
                }
            times[tool].append(inner)
            loads[tool].append(os.getloadavg()[0])
    n = len(next(iter(tables.values())))
    print(f"\ndatabase, {path.name}, {n} attitudes, 1 worker, {args.db_rounds} rounds [s]:")
    for tool in tools:
        print(summary(tool, times[tool], loads[tool]))
    if not octave:
        print("  ADBSat/Octave not installed: skipped")
        return
    for tool in tools[1:]:
        ratio = [
            statistics.median(t[k] for t in times["ADBSat"])
            / statistics.median(t[k] for t in times[tool])
            for k in (0, 1)
        ]
        print(f"  ADBSat / {tool}: wall {ratio[0]:.1f}x, CPU {ratio[1]:.1f}x")
        print(f"  {tool} against ADBSat: {max_difference(tables[tool], tables['ADBSat'])}")


if __name__ == "__main__":
    sys.exit(main())
