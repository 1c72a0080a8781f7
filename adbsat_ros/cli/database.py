"""``adbsat-ros database MESH``: an aerodynamic database over aoa and sideslip (``.npz``, CSV)."""

from __future__ import annotations

import os
import time

from adbsat_ros.cli.common import add_setup_arguments, method_and_flow_from_args
from adbsat_ros.cli.options import (
    CommandFailed,
    CommandLineError,
    errors_as,
    option,
    parse_angle_list,
    positive_int,
    warn,
)
from adbsat_ros.database.build import build_database, check_angles
from adbsat_ros.database.format import is_database_csv, is_database_file
from adbsat_ros.processes import stop_on_signals, usable_cpus, worker_count
from adbsat_ros.tasks import TaskReport
from adbsat_ros.validation import foreign_file, not_an_output

#: Default angle-of-attack and sideslip grids [deg]: the whole sphere in 5 deg steps.
DEFAULT_AOA = "-180:5:180"
DEFAULT_AOS = "-90:5:90"


def configure(p) -> None:
    """Configure ``adbsat-ros database``."""
    p.description = (
        "Sweep the panel method over every pair of --aoa x --aos [deg] (ranges as "
        "start:step:stop; default the whole sphere in 5 deg steps) on --workers processes and "
        "write an .npz database (for the interpolating lookup and the ROS node) and a CSV file "
        "with ADBSat's column names. The stated interpolation error of the grid is computed and "
        "stored. Gas, model, reference and shading options are those of `coeff`."
    )
    add_setup_arguments(p, with_both=False, with_workers=False)
    g = p.add_argument_group("grid and output")
    help = f"angles of attack [deg], -360..360: list and/or start:step:stop (default {DEFAULT_AOA})"
    option(g, "--aoa", help, default=DEFAULT_AOA)
    option(
        g, "--aos", f"sideslip angles [deg], -90..90 (default {DEFAULT_AOS})", default=DEFAULT_AOS
    )
    help = (
        f"processes to use (at most every usable CPU, here {usable_cpus()}; default: this "
        "process, and every CPU for what is left once a build is timed long enough to gain)"
    )
    option(g, "--workers", help, positive_int, default=None)
    help = (
        "a running Dask scheduler (tcp://HOST:8786) whose workers compute the attitudes "
        "(default: processes on this machine)"
    )
    option(g, "--scheduler", help, metavar="ADDRESS")
    option(g, "--out", "database file to write (.npz)", required=True, metavar="FILE.npz")
    option(g, "--csv", "CSV file to write (default: --out with .csv)", metavar="FILE.csv")
    p.set_defaults(func=run)


def _check_output(path: str, option: str, own) -> None:
    """``path``'s directory is writable; a file there is replaced only if a build wrote it."""
    directory = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(directory):
        raise CommandLineError(f"{option}: directory {directory} does not exist")
    if not os.access(directory, os.W_OK):
        raise CommandLineError(f"{option}: directory {directory} is not writable")
    if os.path.lexists(path):
        entry = foreign_file(path, own)
        if entry is not None:
            raise CommandLineError(not_an_output(entry, "database", option))


def run(args) -> int:
    """Run ``adbsat-ros database``; the exit status."""
    with errors_as(CommandLineError, ValueError):  # (the build's checks, naming the option)
        aoa = check_angles(parse_angle_list(args.aoa, "--aoa"), "--aoa", -360.0, 360.0)
        aos = check_angles(parse_angle_list(args.aos, "--aos"), "--aos", -90.0, 90.0)
    out = args.out
    if not out.lower().endswith(".npz"):
        raise CommandLineError(f"--out: the database file must end in .npz, got {out!r}")
    csv_path = args.csv if args.csv is not None else out[: -len(".npz")] + ".csv"
    _check_output(out, "--out", is_database_file)
    _check_output(csv_path, "--csv", is_database_csv)
    _check_output(partial_path(csv_path), "--csv", is_database_csv)
    if args.samples < 1:
        raise CommandLineError(f"--samples must be >= 1, got {args.samples}")
    model, flow, conditions = method_and_flow_from_args(args)
    _, capped = worker_count(args.workers)
    if capped:
        warn("database", f"--workers: {capped}")
    report = TaskReport()
    start = time.perf_counter()
    with stop_on_signals() as stop:
        db = build_database(
            model.method,
            flow,
            aoa,
            aos,
            shading=args.shading,
            samples=args.samples,
            workers=args.workers,
            progress=None,
            mesh_spec=args.mesh,
            mesh_joints=model.positions,
            mesh_scale=args.scale,
            conditions=conditions,
            solver=args.method,
            particles=args.particles,
            tolerance=args.tolerance,
            seed=args.seed,
            stop=stop,
            scheduler=args.scheduler,
            report=report,
        )
    elapsed = time.perf_counter() - start
    partial = db.metadata.get("partial")
    if partial:
        path = partial_path(csv_path)
        db.save_csv(path)
        raise CommandFailed(
            f"stopped by a signal after {partial['attitudes_done']} of {partial['attitudes']} "
            f"attitudes; those are in {path} (PARTIAL), no database was written"
        )
    db.save(out)
    db.save_csv(csv_path)
    print(summary(db, elapsed, report.workers, [out, csv_path]))
    return 0


def partial_path(csv_path: str) -> str:
    """Where a stopped build's attitudes go: ``NAME.PARTIAL.csv`` beside ``NAME.csv``."""
    stem = csv_path[: -len(".csv")] if csv_path.lower().endswith(".csv") else csv_path
    return stem + ".PARTIAL.csv"


def summary(db, elapsed: float, workers: int, files) -> str:
    """The lines printed after a database build on ``workers`` (1: this process)."""
    m = db.metadata
    na, nb = db.shape
    err = m["interpolation_error"]
    lines = [
        f"mesh {m['mesh']['source']}: {m['mesh']['n_panels']} panels; model {m['model']['name']}; "
        + (
            "test particles (every reflection); "
            if m.get("solver", {}).get("method") == "tpmc"
            else f"shading {m['shading']['mode']}; "
        )
        + f"s = {m['flow']['speed_ratio']:.3f}; "
        f"Aref = {m['reference']['area']:.4g} m^2, Lref = {m['reference']['length']:.4g} m",
        f"attitudes: {na} aoa ({db.aoa_deg[0]:g}..{db.aoa_deg[-1]:g} deg) x {nb} aos "
        f"({db.aos_deg[0]:g}..{db.aos_deg[-1]:g} deg) = {db.n_attitudes}",
        f"time: {elapsed:.2f} s "
        + ("in this process " if workers <= 1 else f"on {workers} workers ")
        + f"({1e3 * elapsed / db.n_attitudes:.2f} ms per attitude)",
    ]
    if err.get("force_coefficient") is not None:
        f, mo = err["force_coefficient"], err["moment_coefficient"]
        fmax, mmax = err["max_force_coefficient"], err["max_moment_coefficient"]
        kind = "interpolation" if "statistical_force_coefficient" not in err else "total"
        lines.append(
            f"stated {kind} error (bilinear"
            + (", with 3 standard errors" if kind == "total" else "")
            + f"): |dCf_G| <= {f:.3g} "
            f"({100 * f / fmax if fmax else 0:.2g}% of max |Cf_G| {fmax:.3g}), |dCm_G| <= {mo:.3g} "
            f"({100 * mo / mmax if mmax else 0:.2g}% of max |Cm_G| {mmax:.3g})"
        )
    else:
        lines.append(f"stated interpolation error: {err['method']}")
        if "statistical_force_coefficient" in err:
            lines.append(
                f"statistical error (3 standard errors): |dCf_G| <= "
                f"{err['statistical_force_coefficient']:.3g}, |dCm_G| <= "
                f"{err['statistical_moment_coefficient']:.3g}"
            )
    lines += [f"wrote {path}" for path in files]
    return "\n".join(lines)
