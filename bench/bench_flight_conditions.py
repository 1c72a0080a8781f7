"""Cost of one flight-conditions evaluation (Earth orientation, geodetic, NRLMSISE-00, alpha).

Usage: python bench/bench_flight_conditions.py [--number 2000] [--repeat 15] [--baseline REV]
       [--cold-calls 300]

Prints the median time per call in milliseconds (``--repeat`` rounds of ``--number`` calls) of:

* an exact evaluation as ``AeroWrenchEstimator`` makes one at a knot (or at every stamp with
  ``conditions_step`` 0): ``flight_conditions`` on an ECI state with an aware UTC time,
  ``precession_nutation_step=60`` s and a fixed alpha (the default), then ``free_stream()`` and
  ``dynamic_pressure()``, and the values the node then reads (relative velocity, speed, the free
  stream's mean mass three times and speed ratio as the Sentman model does, the diagnostics);
  messages 0.1 s apart (a 10 Hz attitude stream), the position propagated along the velocity;
  and the same with the Langmuir alpha;
* the per-message path at 1 kHz between knots (working tree only): ``KnotGrid.conditions`` (the
  conditions interpolated between the 10 ms knots, kept) and then the same reads;
* "cold": the same per-message step, each call timed alone right after ``time.sleep(0.01)``
  (median of ``--cold-calls`` calls): the cost when the process sleeps between messages, as it
  does on a 100 Hz stream, and finds its code and data out of the CPU caches;
* ``flight_conditions`` from an ECI state, IAU 2006/2000A (the default, full public call);
* the same with IAU 2000B precession-nutation;
* the same with a precomputed ``EarthOrientation`` (several states at one instant);
* ``flight_conditions_circular_orbit`` (ADBSat's environment.m recipe);
* ``evaluate_atmosphere`` alone (the NRLMSISE-00 call with its validation).

Outside the per-message cases the time advances by one second at every call, so nothing
time-dependent is reused between calls (only the per-day constants are memoised).

``--baseline REV`` also times the exact evaluations with the ``adbsat_ros`` package of git
revision REV of this repository (extracted with ``git archive`` into a temporary directory and
imported as ``adbsat_ros_baseline``: a revision of the flat layout, whose modules import each
other relatively), alternating rounds with the working tree so that both see the same machine
load, and prints the ratio. Example: ``--baseline 386e56c``. Trees of the subpackage layout are
compared in separate processes by ``bench/bench_estimator.py --tree``.
"""

from __future__ import annotations

import argparse
import datetime as dt
import importlib
import importlib.util
import io
import itertools
import math
import pathlib
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
import timeit

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))  # this tree first

from adbsat_ros.environment.atmosphere import SpaceWeather, evaluate_atmosphere
from adbsat_ros.environment.circular_orbit import flight_conditions_circular_orbit
from adbsat_ros.environment.earth_frames import earth_orientation
from adbsat_ros.environment.flight_conditions import flight_conditions
from adbsat_ros.environment.knots import KnotGrid

START = dt.datetime(2015, 1, 19)
WEATHER = SpaceWeather(f107=121.7, f107a=138.1, ap=4.0)
RADIUS = 6778137.0
POSITION = np.array([RADIUS * math.cos(0.3), RADIUS * math.sin(0.3), 1.0e5])
VELOCITY = np.array([-7668.0 * math.sin(0.3), 7668.0 * math.cos(0.3), 100.0])
MESSAGE_PERIOD_S = 0.1
KNOT_STEP_S = 0.01
ATTITUDE_PERIOD_S = 0.001
COLD_PAUSE_S = 0.01
REPOSITORY = pathlib.Path(__file__).resolve().parents[1]


def advancing_times():
    """An endless sequence of UTC times one second apart."""
    return (START + dt.timedelta(seconds=i) for i in itertools.count())


def median_ms(fn, number: int, repeat: int) -> float:
    fn()  # warm up (imports, caches)
    rounds = timeit.repeat(fn, number=number, repeat=repeat)
    return statistics.median(rounds) / number * 1e3


def message_stream(number: int):
    """``number`` (aware UTC time, ECI position) pairs of messages MESSAGE_PERIOD_S apart."""
    epoch = START.replace(tzinfo=dt.timezone.utc)
    return [
        (
            epoch + dt.timedelta(seconds=i * MESSAGE_PERIOD_S),
            POSITION + VELOCITY * (i * MESSAGE_PERIOD_S),
        )
        for i in range(number)
    ]


def module_of(package: str, name: str):
    """``package``'s module ``name`` in the subpackage layout (environment.name) or the flat one."""
    try:
        return importlib.import_module(f"{package}.environment.{name}")
    except ImportError:
        return importlib.import_module(f"{package}.{name}")


def reads(conditions):
    """What the estimator reads of one message's conditions: the relative velocity and speed, the
    free stream and its dynamic pressure, the free-stream values the Sentman model reads (mean
    mass three times, speed ratio) and the diagnostics (density, temperature, altitude, speed
    ratio, alpha)."""
    conditions.relative_velocity_eci, conditions.speed
    flow = conditions.free_stream()
    flow.dynamic_pressure(), flow.mean_mass, flow.mean_mass, flow.mean_mass, flow.speed_ratio
    conditions.mass_density, conditions.temperature, conditions.altitude, conditions.speed_ratio
    return conditions.alpha


def per_message_step(package: str, model: str):
    """``step(utc, position)``: an exact evaluation of ``package``'s flight conditions and what
    the estimator reads of them (:func:`reads`)."""
    conditions_of = module_of(package, "flight_conditions").flight_conditions
    weather_type = module_of(package, "atmosphere").SpaceWeather
    weather = weather_type(WEATHER.f107, WEATHER.f107a, WEATHER.ap)

    def step(utc, position):
        conditions = conditions_of(
            utc,
            position,
            VELOCITY,
            weather,
            frame="eci",
            earth_rotation=True,
            wind=None,
            wind_frame="ecef",
            anomalous_oxygen=True,
            accommodation_model=model,
            accommodation_options={"alpha": 1.0} if model == "fixed" else None,
            precession_nutation_step=60.0,
        )
        return reads(conditions)

    return step


def knot_grid_ms(number: int, repeat: int) -> float:
    """Median time [ms] per 1 kHz message of ``KnotGrid.conditions`` and :func:`reads`, the
    knots 10 ms apart kept in the grid (one new knot every ten messages, as in the estimator)."""
    epoch = START.replace(tzinfo=dt.timezone.utc)

    def exact(_, stamp):
        return flight_conditions(
            epoch + dt.timedelta(seconds=stamp),
            POSITION + VELOCITY * stamp,
            VELOCITY,
            WEATHER,
            accommodation_model="fixed",
            accommodation_options={"alpha": 1.0},
            precession_nutation_step=60.0,
        )

    grid = KnotGrid(KNOT_STEP_S, exact)
    key = object()  # one orbital state
    stamps = [0.0005 + ATTITUDE_PERIOD_S * i for i in range(number)]
    times = [epoch + dt.timedelta(seconds=stamp) for stamp in stamps]

    def run() -> float:
        start = time.perf_counter()
        for stamp, utc in zip(stamps, times):
            reads(grid.conditions(key, stamp, utc))
        return (time.perf_counter() - start) / number

    run()
    return statistics.median(run() for _ in range(repeat)) * 1e3


def per_message_round(package: str, model: str):
    """A function timing one pass over a message stream with ``package``'s per-message step."""
    step = per_message_step(package, model)

    def run(messages) -> float:
        start = time.perf_counter()
        for utc, position in messages:
            step(utc, position)
        return (time.perf_counter() - start) / len(messages)

    return run


def cold_medians(packages: dict, model: str, calls: int, pause: float) -> dict:
    """Median time [s] of one per-message step right after ``time.sleep(pause)`` (the CPU and
    its caches idle, as between the messages of a 100 Hz stream), per package; the packages take
    turns, message by message."""
    steps = {label: per_message_step(package, model) for label, package in packages.items()}
    messages = message_stream(calls)
    for step in steps.values():
        for utc, position in messages[:50]:
            step(utc, position)  # warm up (imports, memoised terms)
    times = {label: [] for label in steps}
    for utc, position in messages:
        for label, step in steps.items():
            time.sleep(pause)
            start = time.perf_counter()
            step(utc, position)
            times[label].append(time.perf_counter() - start)
    return {label: statistics.median(values) for label, values in times.items()}


def extract_package(revision: str, directory: str) -> pathlib.Path:
    """Extract ``adbsat_ros`` as it was at git ``revision`` into ``directory``; its folder."""
    archive = subprocess.run(
        ["git", "-C", str(REPOSITORY), "archive", "--format=tar", revision, "adbsat_ros"],
        check=True,
        capture_output=True,
    ).stdout
    with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
        tar.extractall(directory, filter="data")
    return pathlib.Path(directory) / "adbsat_ros"


def import_baseline(revision: str, directory: str) -> str:
    """Extract ``adbsat_ros`` at git ``revision`` into ``directory``; import it as
    adbsat_ros_baseline.

    Only a package whose modules import each other relatively (the flat layout) can be imported
    under another name beside this one: a revision with absolute ``adbsat_ros.`` imports would
    run this tree's modules for the baseline's, so it is refused (SystemExit); compare such trees
    in separate processes with ``bench/bench_estimator.py --tree``.
    """
    package_dir = extract_package(revision, directory)
    for path in package_dir.rglob("*.py"):
        text = path.read_text(encoding="utf-8")
        if "\nfrom adbsat_ros." in text or "\nimport adbsat_ros." in text:
            raise SystemExit(
                f"--baseline {revision}: its modules import adbsat_ros absolutely, so it cannot be "
                "imported beside this tree; use bench/bench_estimator.py --tree for such trees"
            )
    name = "adbsat_ros_baseline"
    spec = importlib.util.spec_from_file_location(
        name, package_dir / "__init__.py", submodule_search_locations=[str(package_dir)]
    )
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return name


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--number", type=int, default=2000, help="calls per timing round")
    parser.add_argument("--repeat", type=int, default=15, help="timing rounds")
    parser.add_argument(
        "--baseline", metavar="REV", help="also time the per-message path at git revision REV"
    )
    parser.add_argument(
        "--cold-calls",
        type=int,
        default=300,
        help="calls of the cold per-message case (each after a 10 ms sleep); 0 skips it",
    )
    args = parser.parse_args(argv)

    with tempfile.TemporaryDirectory() as directory:
        packages = {"working tree": "adbsat_ros"}
        if args.baseline:
            packages[f"baseline {args.baseline}"] = import_baseline(args.baseline, directory)
        messages = message_stream(args.number)
        print(
            "exact evaluation (flight_conditions + free_stream + dynamic_pressure, as at a knot), "
            f"median over {args.repeat} rounds of {args.number} messages {MESSAGE_PERIOD_S} s "
            "apart:"
        )
        for model in ("fixed", "langmuir"):
            runs = {label: per_message_round(package, model) for label, package in packages.items()}
            for run in runs.values():
                run(messages[:200])  # warm up
            rounds = {label: [] for label in runs}
            for _ in range(args.repeat):  # alternate, so both see the same machine load
                for label, run in runs.items():
                    rounds[label].append(run(messages))
            medians = {label: statistics.median(values) * 1e3 for label, values in rounds.items()}
            for label, value in medians.items():
                print(f"  {model:<8} accommodation, {label:<24} {value:.4f} ms")
            if len(medians) == 2:
                current, baseline = medians.values()
                ratio = baseline / current
                print(f"  {model:<8} accommodation, baseline / working tree   {ratio:.2f}x")
        print(
            "per-message path at 1 kHz between 10 ms knots (KnotGrid.conditions + the same reads), "
            f"working tree: {knot_grid_ms(args.number, args.repeat):.4f} ms"
        )
        if args.cold_calls > 0:
            print(
                f"cold per-message path (the same, each call after time.sleep({COLD_PAUSE_S})), "
                f"median of {args.cold_calls} calls:"
            )
            for model in ("fixed", "langmuir"):
                medians = cold_medians(packages, model, args.cold_calls, COLD_PAUSE_S)
                for label, value in medians.items():
                    print(f"  {model:<8} accommodation, {label:<24} {value * 1e3:.4f} ms")
                if len(medians) == 2:
                    current, baseline = medians.values()
                    ratio = baseline / current
                    print(f"  {model:<8} accommodation, baseline / working tree   {ratio:.2f}x")

    times = advancing_times()
    fixed_orientation = earth_orientation(START)
    cases = {
        "flight_conditions (ECI state, IAU 2006/2000A)": lambda: flight_conditions(
            next(times), POSITION, VELOCITY, WEATHER
        ),
        "flight_conditions (ECI state, IAU 2000B)": lambda: flight_conditions(
            next(times), POSITION, VELOCITY, WEATHER, precession_nutation="iau2000b"
        ),
        "flight_conditions (precomputed EarthOrientation)": lambda: flight_conditions(
            START, POSITION, VELOCITY, WEATHER, orientation=fixed_orientation
        ),
        "flight_conditions_circular_orbit (ADBSat recipe)": lambda: (
            flight_conditions_circular_orbit(next(times), 400e3, 0.1, 0.2, WEATHER)
        ),
        "evaluate_atmosphere (NRLMSISE-00 only)": lambda: evaluate_atmosphere(
            next(times), 400e3, 0.1, 0.2, WEATHER
        ),
    }
    print(f"median per call over {args.repeat} rounds of {args.number} calls:")
    width = max(len(name) for name in cases)
    for name, fn in cases.items():
        print(f"  {name:<{width}}  {median_ms(fn, args.number, args.repeat):.4f} ms")


if __name__ == "__main__":
    main()
