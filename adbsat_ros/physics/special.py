"""erf and erfc of float arrays, for the gas-surface models.

scipy.special's ufuncs, imported when first called; within :func:`standard_library`, the math
module's instead, value by value: slower per value, but a command of a few attitudes then never
imports scipy.special, the larger part of its whole run (docs/benchmarks.md, "Against ADBSat").
The two agree to a few ulp (test/physics/test_special.py).
"""

from __future__ import annotations

import contextlib
import math

import numpy as np

_by_math = False
_scipy = None  # scipy.special, once imported


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
    return _by_value(math.erf, x) if _by_math else (_scipy or _import_scipy()).erf(x)


def erfc(x) -> np.ndarray:
    """erfc(x) = 1 - erf(x), elementwise, of a float array."""
    return _by_value(math.erfc, x) if _by_math else (_scipy or _import_scipy()).erfc(x)


def _by_value(function, x) -> np.ndarray:
    x = np.asarray(x, dtype=float)
    return np.fromiter(map(function, x.ravel().tolist()), float, x.size).reshape(x.shape)


def _import_scipy():
    global _scipy
    import scipy.special

    _scipy = scipy.special
    return _scipy
