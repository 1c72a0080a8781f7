"""erf and erfc of float arrays, for the gas-surface models: scipy.special's ufuncs, or within
:func:`standard_library` the math module's, value by value. Slower per value, the latter spares a
command of a few attitudes the import of scipy.special, the larger part of its whole run
(docs/benchmarks.md, "Against ADBSat"); the two agree to a few ulp (test/physics/test_special.py).
"""

from __future__ import annotations

import contextlib
import math

import numpy as np

_by_math = False


@contextlib.contextmanager
def standard_library():
    """Within this context :func:`erf` and :func:`erfc` compute with :mod:`math`."""
    global _by_math
    saved, _by_math = _by_math, True
    try:
        yield
    finally:
        _by_math = saved


def erf(x) -> np.ndarray:
    """erf(x), elementwise, of a float array."""
    if _by_math:
        return _by_value(math.erf, x)
    import scipy.special  # (imported once, at the first call)

    return scipy.special.erf(x)


def erfc(x) -> np.ndarray:
    """erfc(x) = 1 - erf(x), elementwise, of a float array."""
    if _by_math:
        return _by_value(math.erfc, x)
    import scipy.special

    return scipy.special.erfc(x)


def _by_value(function, x) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    return np.fromiter(map(function, x.ravel().tolist()), float, x.size).reshape(x.shape)
