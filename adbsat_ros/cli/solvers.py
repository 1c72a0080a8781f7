"""``--method panel|tpmc|both``, the test-particle options, and running that solver."""

from __future__ import annotations

import functools
import math
import sys

from adbsat_ros.cli.options import is_terminal, non_negative_int, number, option, positive_int

METHODS = ("panel", "tpmc", "both")


def add_solver_arguments(parser, with_both: bool = True, with_workers: bool = True) -> None:
    """Add ``--method`` and the test-particle options (``workers`` unless the command has one)."""
    g = parser.add_argument_group("solver")
    help = (
        "panel: the panel method (one reflection); tpmc: test-particle Monte Carlo (every "
        "reflection, with standard errors)"
        + ("; both: each, and their difference" if with_both else "")
        + " (default panel)"
    )
    option(g, "--method", help, default="panel", choices=METHODS if with_both else METHODS[:2])
    help = "tpmc: most molecules per attitude (default 1e6, or 1e8 with --tolerance)"
    option(g, "--particles", help, positive_int)
    help = "tpmc: stop once the standard error of C_D is at most this fraction of C_D"
    below_one = functools.partial(
        number, low=0.0, high=math.nextafter(1.0, 0.0), low_open=True, what="a number in (0, 1)"
    )
    option(g, "--tolerance", help, below_one)
    option(g, "--seed", "tpmc: random seed", non_negative_int, default=0)
    if with_workers:
        help = "tpmc: processes (default 1; at most the usable CPUs)"
        option(g, "--workers", help, positive_int, default=1)


def run_tpmc(args, model, flow, aoa, aos):
    """Test-particle coefficients of ``model`` at one attitude [rad], with a bar on a terminal.

    A signal stops the run after its current block: the result so far is kept, marked partial.
    """
    from tqdm import tqdm

    from adbsat_ros.processes import stop_on_signals, worker_count

    workers, note = worker_count(args.workers)
    if note:
        print(f"adbsat-ros: {note}", file=sys.stderr)
    bar = None
    if is_terminal():
        bar = tqdm(unit="molecule", unit_scale=True, desc="tpmc", file=sys.stderr, leave=False)

    def progress(done):
        if bar is not None:
            bar.update(done - bar.n)

    try:
        with stop_on_signals() as stop:
            result = model.evaluate(
                flow,
                angles=(aoa, aos),
                solver="tpmc",
                workers=workers,
                progress=progress,
                stop=stop,
            )
    finally:
        if bar is not None:
            bar.close()
    if result.stopped:
        print(
            f"adbsat-ros: interrupted: the results are those of the {result.particles:,} "
            "molecules traced (with their standard errors)",
            file=sys.stderr,
        )
    return result
