"""Bag analysis throughput: attitude messages analysed per second, with the time split by phase.

Usage:
    python bench/bench_bag_analysis.py [--duration 60] [--rate 100] [--max-edge 0.064]
        [--shading raycast] [--storage mcap] [--plots] [--workers 1,2] [--param NAME=VALUE ...]

Simulates a nadir-pointing flight (state at 10 Hz, attitude at --rate) into a bag, then runs
``analyze_bag`` on it with the example satellite refined to --max-edge (0.064 m: 9,600 faces)
and the cached shading, writing the output bag and the CSV (plots only with --plots), once per
--workers value (default 1 and os.cpu_count(), in the same run: the machine may be shared, so
compare them with each other; the load average is printed). Reports messages per second for
the whole analysis and for the estimator alone (the same AeroWrenchEstimator fed directly, no
bag), and the analysis time by phase: read (bag reading, chunk planning), estimate (computing
chunks or waiting for the workers: CDR decoding + estimator), write (output bag), csv.
Target: over 2,000 attitude messages per second on ~10k faces. ``--param NAME=VALUE`` (a YAML
value) sets another node parameter, e.g. ``shading_interpolation=false`` to compare with a tree
whose shading had no interpolation.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import yaml

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # this tree's adbsat_ros first

from meshes import write_obj  # noqa: E402

from adbsat_ros.bags import io as bag_io  # noqa: E402
from adbsat_ros.bags import scenario  # noqa: E402
from adbsat_ros.bags.analysis import analyze_bag  # noqa: E402
from adbsat_ros.estimator.estimator import AeroWrenchEstimator  # noqa: E402
from adbsat_ros.estimator.settings import WrenchSettings  # noqa: E402
from adbsat_ros.geometry.example_satellite import example_satellite  # noqa: E402


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--duration", type=float, default=60.0)
    p.add_argument("--rate", type=float, default=100.0)
    p.add_argument("--max-edge", type=float, default=0.064)
    p.add_argument("--shading", default="raycast")
    p.add_argument("--storage", default="mcap")
    p.add_argument("--plots", action="store_true")
    p.add_argument(
        "--workers", default=f"1,{os.cpu_count() or 1}", help="comma-separated worker counts to run"
    )
    p.add_argument(
        "--param",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="another node parameter (a YAML value), e.g. shading_interpolation=false",
    )
    args = p.parse_args(argv)
    parameters = {}
    for item in args.param:
        name, _, value = item.partition("=")
        parameters[name] = yaml.safe_load(value)
    worker_counts = [int(w) for w in args.workers.split(",")]
    load_before = os.getloadavg()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        mesh = example_satellite(max_edge=args.max_edge)
        write_obj(mesh, tmp / "sat.obj")
        sc = scenario.Scenario(duration_s=args.duration, rate_hz=args.rate, state_rate_hz=10.0)
        messages = scenario.generate(sc)
        bag_io.write_scenario_bag(messages, tmp / "in", storage=args.storage)
        settings = WrenchSettings.from_parameters(
            {"mesh": str(tmp / "sat.obj"), "shading": args.shading, **parameters}
        )
        n_att = len(messages.attitudes.stamps_ns)

        reports = []
        for run, workers in enumerate(worker_counts):
            reports.append(
                analyze_bag(
                    tmp / "in",
                    models=[("bench", settings)],
                    out_bag=tmp / f"out{run}",
                    out_csv=tmp / f"out{run}.csv",
                    plots_dir=tmp / f"plots{run}" if args.plots else None,
                    storage=args.storage,
                    workers=workers,
                )
            )
        same_csv = (
            len({(tmp / f"out{run}.csv").read_bytes() for run in range(len(worker_counts))}) == 1
        )

        est = AeroWrenchEstimator(settings)  # the estimator alone, same inputs, fresh caches
        st, att = messages.states, messages.attitudes
        events = sorted(
            [(t, 0, i) for i, t in enumerate(st.stamps_ns)]
            + [(t, 1, i) for i, t in enumerate(att.stamps_ns)]
        )
        t0 = time.perf_counter()
        for _, kind, i in events:
            if kind == 0:
                est.on_state(st.stamps[i], st.position_eci[i], st.velocity_eci[i])
            else:
                est.on_attitude(att.stamps[i], att.quaternion_xyzw[i])
        direct = time.perf_counter() - t0

    print(f"command: {' '.join([Path(sys.executable).name, *sys.argv])}")
    print(
        f"mesh: example satellite max_edge {args.max_edge} m, {mesh.n_panels} faces; "
        f"shading {args.shading} (cached); storage {args.storage}"
        + "".join(f"; {item}" for item in args.param)
    )
    print(
        f"input: {n_att} attitude + {len(messages.states.stamps_ns)} state messages "
        f"({args.duration:g} s at {args.rate:g} Hz)"
    )
    print(
        f"load average (1 min) before {load_before[0]:.2f}, after {os.getloadavg()[0]:.2f} "
        f"on {os.cpu_count()} cores"
    )
    for report in reports:
        total = report.seconds["total"]
        print(
            f"analyze_bag, {report.workers} worker(s), {report.chunks} chunk(s): "
            f"{report.models[0].wrenches} wrenches in {total:.2f} s = "
            f"{n_att / total:,.0f} attitude messages/s (target > 2,000)"
        )
        parts = ", ".join(
            f"{k} {v:.2f} s ({100 * v / total:.0f} %)"
            for k, v in report.seconds.items()
            if k != "total"
        )
        other = total - sum(v for k, v in report.seconds.items() if k != "total")
        print(f"  phases: {parts}; other {other:.2f} s")
    print(f"CSV identical for all worker counts: {same_csv}")
    print(f"estimator alone: {n_att / direct:,.0f} attitude messages/s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
