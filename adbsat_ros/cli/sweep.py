"""``adbsat-ros sweep SPEC.yaml --out RESULT.zarr``: an N-dimensional sweep on Dask."""

from __future__ import annotations

import sys

from adbsat_ros.cli.options import CommandLineError, errors_as, flag, is_terminal, option, warn


def configure(p) -> None:
    """Configure ``adbsat-ros sweep``."""
    p.description = (
        "Compute the coefficients over every point of the axes a YAML spec names (aoa, aos, "
        "speed, temperature, mean_mass_amu, alpha, wall_temperature, joint.NAME) on this "
        "machine's cores, or on any running Dask scheduler (--scheduler). The "
        "result is an xarray Dataset in a Zarr store, written chunk by chunk: run the same "
        "command again after an interruption and it computes only what is missing "
        "(docs/sweeps.md)."
    )
    p.add_argument("spec", metavar="SPEC.yaml", help="the sweep's spec (docs/sweeps.md)")
    option(p, "--out", "the Zarr store", required=True, metavar="RESULT.zarr")
    help = "a running Dask scheduler, e.g. tcp://10.0.0.5:8786 (default: this machine)"
    option(p, "--scheduler", help, metavar="ADDRESS")
    help = (
        "worker processes forked here (default: this process, and every usable CPU for "
        "what is left once the chunks, timed here, are worth them)"
    )
    option(p, "--workers", help, type=int, metavar="N")
    help = "replace a sweep store (of another spec) at --out; anything else there is refused"
    flag(p, "--overwrite", help)
    flag(p, "--no-progress", "no progress bar")
    p.set_defaults(func=run)


def run(args) -> int:
    """Run the sweep; 0 when every chunk is written, 1 if stopped early or it failed."""
    from adbsat_ros.geometry.loading import articulated_body, is_urdf
    from adbsat_ros.geometry.mesh import MeshError
    from adbsat_ros.processes import stop_on_signals
    from adbsat_ros.sweep.engine import run_sweep
    from adbsat_ros.sweep.spec import SpecError, load_spec, parse_spec
    from adbsat_ros.sweep.store import StoreError

    if args.workers is not None and args.workers < 1:
        raise CommandLineError(f"--workers must be >= 1, got {args.workers}")
    with errors_as(CommandLineError, (SpecError, StoreError, MeshError, ValueError)):
        text, data = load_spec(args.spec)
        joints = None
        if isinstance(data, dict) and is_urdf(str(data.get("mesh", ""))):
            joints = articulated_body(str(data["mesh"])).joints
        spec = parse_spec(data, text, joints)
        with stop_on_signals() as stop:
            report = run_sweep(
                spec,
                args.out,
                scheduler=args.scheduler,
                workers=args.workers,
                overwrite=args.overwrite,
                progress=not args.no_progress and is_terminal(),
                stop=stop,
            )
    for note in report.notes:
        warn("sweep", note)
    shape = " x ".join(f"{len(v)} {k}" for k, v in spec.axes.items())
    print(
        f"sweep {shape}: {report.chunks} chunks, {report.already_done} already in {args.out}, "
        f"{report.computed} computed ({report.points} points) "
        + ("in this process" if report.workers <= 1 else f"on {report.workers} workers")
        + f" in {report.seconds:.1f} s"
    )
    if report.stopped:
        print("stopped: run the same command again to compute the rest", file=sys.stderr)
        return 1
    return 0
