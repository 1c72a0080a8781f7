"""Values at the edges of a valid range and just beyond, for the tests of every door an input
comes through (command line, settings, params files, run-time parameters, messages)."""

from __future__ import annotations

import math

import numpy as np

from adbsat_ros.estimator.parameters import (
    PARAMETER_DEFAULTS,
    PARAMETER_RANGES,
    WHOLE_NUMBER_PARAMETERS,
)


def edges(bound):
    """(values inside, values just outside) of a Bound."""
    low_in = np.nextafter(bound.low, math.inf) if bound.low_open else bound.low
    high_in = np.nextafter(bound.high, -math.inf) if bound.high_open else bound.high
    inside = [low_in, high_in, 0.5 * (bound.low + bound.high)]
    outside = [
        bound.low if bound.low_open else np.nextafter(bound.low, -math.inf),
        bound.high if bound.high_open else np.nextafter(bound.high, math.inf),
        math.nan,
        math.inf,
    ]
    return [float(x) for x in inside], [float(x) for x in outside]


def is_number_parameter(default) -> bool:
    if isinstance(default, list):
        return all(is_number_parameter(x) for x in default)
    return isinstance(default, (int, float)) and not isinstance(default, bool)


#: Parameters whose numbers must also fit together (the inertia tensor: symmetric, positive
#: definite), so that a number inside its range is not always a valid value: tested on their own.
TENSOR_PARAMETERS = ("inertia",)
NUMBER_PARAMETERS = sorted(
    n
    for n, d in PARAMETER_DEFAULTS.items()
    if is_number_parameter(d) and n not in TENSOR_PARAMETERS
)


def parameter_edges(name):
    """(values inside, values just outside) of a number parameter's range. A whole-number
    parameter (an integer ROS parameter) gets integers, one beyond each end, and also a
    fraction, NaN and infinity, which it refuses."""
    inside, outside = edges(PARAMETER_RANGES[name])
    if name in WHOLE_NUMBER_PARAMETERS:
        low, high = int(inside[0]), int(inside[1])
        inside = [low, high, (low + high) // 2]
        outside = [low - 1, high + 1, low + 0.5, math.nan, math.inf]
    return inside, outside


def as_parameter(name, x):
    """A parameter value with ``x`` in it: the number itself, or the last element of a list."""
    if name == "ap_history":
        return [4.0] * 6 + [x]
    return [0.0, 0.0, x] if isinstance(PARAMETER_DEFAULTS[name], list) else x
