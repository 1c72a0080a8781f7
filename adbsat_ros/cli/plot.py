"""``adbsat-ros plot DATABASE.npz``: figures of an aerodynamic database (PNG files)."""

from __future__ import annotations

import functools
from pathlib import Path

from adbsat_ros.cli.options import CommandLineError, errors_as, flag, number, option
from adbsat_ros.database.format import DatabaseError, load_database
from adbsat_ros.database.metadata import model_from_metadata
from adbsat_ros.plotting import coefficients, panels


def configure(p) -> None:
    """Configure ``adbsat-ros plot``."""
    p.description = (
        "Draw the coefficients of a database written by `adbsat-ros database` against angle of "
        "attack, one line per sideslip angle (database_coefficients.png: CD, CL, CY; "
        "database_moments.png: Cm_B x, y, z), and a 3-D picture of the mesh coloured by "
        "per-panel pressure coefficient at one attitude, with the panels shaded from the flow "
        "marked (panel_pressure.png; the mesh is reloaded and must be unchanged). Prints the "
        "paths written."
    )
    p.add_argument(
        "database", metavar="DATABASE", help="database file (.npz) from `adbsat-ros database`"
    )
    help = "folder for the PNGs (default: DATABASE without .npz plus '_plots')"
    option(p, "--out-dir", help, metavar="DIR")
    angle = functools.partial(number, what="a finite angle in degrees")
    help = (
        "angle of attack of the pressure picture [deg] (default 0 if the database covers it, "
        "else its first)"
    )
    option(p, "--aoa", help, angle, default=None)
    help = "sideslip of the pressure picture [deg] (default 0 if covered, else the first)"
    option(p, "--aos", help, angle, default=None)
    help = "coefficient plots only: do not reload the mesh or draw the pressure picture"
    flag(p, "--no-mesh", help)
    help = "most sideslip lines per plot, evenly spaced if the database has more (default 7)"
    option(p, "--max-lines", help, type=int, default=7)
    p.set_defaults(func=run)


def default_angle(grid) -> float:
    """Angle of the pressure picture on one grid axis [deg]: 0 if covered, else the first."""
    return 0.0 if grid[0] <= 0.0 <= grid[-1] else float(grid[0])


def run(args) -> int:
    """Run ``adbsat-ros plot``; the exit status."""
    path = Path(args.database)
    if not path.exists():
        raise CommandLineError(f"DATABASE: no such file {str(path)!r}")
    if path.is_dir():
        raise CommandLineError(f"DATABASE: {str(path)!r} is a folder, not a database file")
    if args.max_lines < 2:
        raise CommandLineError(f"--max-lines must be >= 2, got {args.max_lines}")
    if args.aos is not None and not -90.0 <= args.aos <= 90.0:
        raise CommandLineError(f"--aos must be in [-90, 90] degrees, got {args.aos:g}")
    with errors_as(CommandLineError, DatabaseError, "DATABASE: "):
        db = load_database(path)
    out_dir = Path(args.out_dir) if args.out_dir else path.with_name(path.stem + "_plots")
    if out_dir.exists() and not out_dir.is_dir():
        raise CommandLineError(f"--out-dir: {str(out_dir)!r} exists and is not a folder")

    written = coefficients.plot_database(db, out_dir, max_lines=args.max_lines)
    if not args.no_mesh:
        try:
            model, flow = model_from_metadata(db.metadata, path=str(path))
        except DatabaseError as exc:
            raise CommandLineError(
                f"DATABASE: {exc} (use --no-mesh to draw the coefficient plots only)"
            ) from None
        aoa = args.aoa if args.aoa is not None else default_angle(db.aoa_deg)
        aos = args.aos if args.aos is not None else default_angle(db.aos_deg)
        written.append(
            panels.plot_panel_pressure(
                model,
                flow,
                aoa,
                aos,
                out_dir / "panel_pressure.png",
                title=coefficients.database_title(db.metadata),
            )
        )
    for p in written:
        print(p)
    return 0
