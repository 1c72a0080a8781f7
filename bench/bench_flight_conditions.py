"""Cost of one flight-conditions evaluation (Earth orientation, geodetic, NRLMSISE-00, alpha).

Usage: python bench/bench_flight_conditions.py [--number 2000] [--repeat 15] [--baseline REV]
       [--cold-calls 300]

Prints the median time per call in milliseconds (``--repeat`` rounds of ``--number`` calls) of:

* the per-message path of the node and the bag analysis, as
  ``AeroWrenchEstimator.on_attitude`` calls it: ``flight_conditions`` on an ECI state with an aware
  UTC time, ``precession_nutation_step=60`` s and a fixed alpha (the default), then
  ``free_stream()`` and ``dynamic_pressure()``, and the values the node then reads (relative
  velocity, speed, the free stream's mean mass three times and speed ratio as the Sentman model
  does, the diagnostics); messages 0.1 s apart (a 10 Hz attitude stream), the position propagated
  along the velocity; and the same with the Langmuir alpha;
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

``--baseline REV`` also times the per-message cases with the ``adbsat_ros`` package of git
revision REV of this repository (extracted with ``git archive`` into a temporary directory and
imported as ``adbsat_ros_baseline``), alternating rounds with the working tree so that both see the
same machine load, and prints the ratio. Example: ``--baseline HEAD`` to measure uncommitted work.
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

from adbsat_ros.environment.atmosphere import SpaceWeather, evaluate_atmosphere
from adbsat_ros.environment.earth_frames import earth_orientation
from adbsat_ros.environment.flight_conditions import (
    flight_conditions,
    flight_conditions_circular_orbit,
)

START = dt.datetime(2015, 1, 19)
WEATHER = SpaceWeather(f107=121.7, f107a=138.1, ap=4.0)
RADIUS = 6778137.0
POSITION = np.array([RADIUS * math.cos(0.3), RADIUS * math.sin(0.3), 1.0e5])
VELOCITY = np.array([-7668.0 * math.sin(0.3), 7668.0 * math.cos(0.3), 100.0])
MESSAGE_PERIOD_S = 0.1
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


def per_message_step(package: str, model: str):
    """``step(utc, position)``: what ``AeroWrenchEstimator.on_attitude`` does with ``package``'s
    flight conditions for one message: the call, the free stream and its dynamic pressure, the
    relative velocity and speed, the free-stream values the Sentman model reads (mean mass three
    times, speed ratio) and the diagnostics (density, temperature, altitude, speed ratio, alpha)."""
    conditions_of = importlib.import_module(f"{package}.flight_conditions").flight_conditions
    weather_type = importlib.import_module(f"{package}.atmosphere").SpaceWeather
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
        conditions.relative_velocity_eci, conditions.speed
        flow = conditions.free_stream()
        flow.dynamic_pressure(), flow.mean_mass, flow.mean_mass, flow.mean_mass, flow.speed_ratio
        conditions.mass_density, conditions.temperature, conditions.altitude, conditions.speed_ratio
        return conditions.alpha

    return step


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
    """Extract ``adbsat_ros`` as it was at git ``revision`` into ``directory``; return its folder."""
    archive = subprocess.run(
        ["git", "-C", str(REPOSITORY), "archive", "--format=tar", revision, "adbsat_ros"],
        check=True,
        capture_output=True,
    ).stdout
    with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
        tar.extractall(directory, filter="data")
    return pathlib.Path(directory) / "adbsat_ros"


def import_baseline(revision: str, directory: str) -> str:
    """Extract ``adbsat_ros`` at git ``revision`` into ``directory``; import it as adbsat_ros_baseline."""
    package_dir = extract_package(revision, directory)
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
            f"per-message path (flight_conditions + free_stream + dynamic_pressure, as on_attitude), "
            f"median over {args.repeat} rounds of {args.number} messages {MESSAGE_PERIOD_S} s apart:"
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
                print(
                    f"  {model:<8} accommodation, baseline / working tree   {baseline / current:.2f}x"
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
                    print(
                        f"  {model:<8} accommodation, baseline / working tree   {baseline / current:.2f}x"
                    )

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
