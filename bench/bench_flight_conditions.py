"""Cost of one flight-conditions evaluation (Earth orientation, geodetic, NRLMSISE-00, alpha).

Usage: python bench/bench_flight_conditions.py [--number 2000] [--repeat 15]

Times with ``timeit`` (``--repeat`` rounds of ``--number`` calls each) and prints the median time
per call in milliseconds of:

* ``flight_conditions`` from an ECI state, IAU 2006/2000A (the default, full public call);
* the same with IAU 2000B precession-nutation;
* the same with a precomputed ``EarthOrientation`` (several states at one instant);
* ``flight_conditions_circular_orbit`` (ADBSat's environment.m recipe);
* ``evaluate_atmosphere`` alone (the NRLMSISE-00 call with its validation).

The time advances by one second at every call, so nothing time-dependent is reused between calls
(only the per-day TAI-UTC look-up is cached). Target: under 0.2 ms per flight-conditions call.
"""

from __future__ import annotations

import argparse
import datetime as dt
import itertools
import math
import statistics
import timeit

import numpy as np

from adbsat_ros.atmosphere import SpaceWeather, evaluate_atmosphere
from adbsat_ros.earth_frames import earth_orientation
from adbsat_ros.flight_conditions import flight_conditions, flight_conditions_circular_orbit

START = dt.datetime(2015, 1, 19)
WEATHER = SpaceWeather(f107=121.7, f107a=138.1, ap=4.0)
RADIUS = 6778137.0
POSITION = np.array([RADIUS * math.cos(0.3), RADIUS * math.sin(0.3), 1.0e5])
VELOCITY = np.array([-7668.0 * math.sin(0.3), 7668.0 * math.cos(0.3), 100.0])


def advancing_times():
    """An endless sequence of UTC times one second apart."""
    return (START + dt.timedelta(seconds=i) for i in itertools.count())


def median_ms(fn, number: int, repeat: int) -> float:
    fn()  # warm up (imports, caches)
    rounds = timeit.repeat(fn, number=number, repeat=repeat)
    return statistics.median(rounds) / number * 1e3


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--number", type=int, default=2000, help="calls per timing round")
    parser.add_argument("--repeat", type=int, default=15, help="timing rounds")
    args = parser.parse_args(argv)

    times = advancing_times()
    fixed_orientation = earth_orientation(START)
    cases = {
        "flight_conditions (ECI state, IAU 2006/2000A)":
            lambda: flight_conditions(next(times), POSITION, VELOCITY, WEATHER),
        "flight_conditions (ECI state, IAU 2000B)":
            lambda: flight_conditions(next(times), POSITION, VELOCITY, WEATHER,
                                      precession_nutation="iau2000b"),
        "flight_conditions (precomputed EarthOrientation)":
            lambda: flight_conditions(START, POSITION, VELOCITY, WEATHER,
                                      orientation=fixed_orientation),
        "flight_conditions_circular_orbit (ADBSat recipe)":
            lambda: flight_conditions_circular_orbit(next(times), 400e3, 0.1, 0.2, WEATHER),
        "evaluate_atmosphere (NRLMSISE-00 only)":
            lambda: evaluate_atmosphere(next(times), 400e3, 0.1, 0.2, WEATHER),
    }
    print(f"median per call over {args.repeat} rounds of {args.number} calls:")
    width = max(len(name) for name in cases)
    for name, fn in cases.items():
        print(f"  {name:<{width}}  {median_ms(fn, args.number, args.repeat):.4f} ms")


if __name__ == "__main__":
    main()
