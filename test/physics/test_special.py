"""erf and erfc by the math module against scipy.special's, and the gas-surface models alike."""

import math

import numpy as np
import pytest
import scipy.special

from adbsat_ros import FreeStream
from adbsat_ros.physics import special
from adbsat_ros.physics.gsi_models import ModelOptions, get_model
from adbsat_ros.physics.surface import MaterialTable, SurfaceProperties


def test_the_math_module_agrees_with_scipy_to_a_few_ulp():
    rng = np.random.default_rng(7)
    x = np.concatenate(
        [rng.normal(scale=3.0, size=(400, 5)).ravel(), [0.0, -0.0, 1e-300, -6.0, 6.0, 26.0]]
    ).reshape(-1, 2)
    with special.standard_library():
        erf, erfc = special.erf(x), special.erfc(x)
    assert erf.shape == erfc.shape == x.shape and erf.dtype == np.float64
    np.testing.assert_allclose(erf, scipy.special.erf(x), rtol=4 * np.finfo(float).eps, atol=0)
    # erfc: relative to its own size while it is above 1e-12 (x < 5), absolutely below
    np.testing.assert_allclose(erfc, scipy.special.erfc(x), rtol=1e-14, atol=1e-27)
    assert special.erfc(np.array([-np.inf, np.inf, np.nan])).tolist()[:2] == [2.0, 0.0]
    with special.standard_library():
        ends = special.erfc(np.array([-np.inf, np.inf, np.nan]))
    assert ends[:2].tolist() == [2.0, 0.0] and math.isnan(ends[2])


def test_the_context_chooses_the_math_module_and_restores_scipy_after():
    x = np.array([0.7, -1.7, 2.9])  # (where the two differ in the last bit)
    by_scipy = special.erfc(x)
    with special.standard_library():
        by_math = special.erfc(x)
    assert by_math.tolist() == [math.erfc(v) for v in x.tolist()] != by_scipy.tolist()
    assert special.erfc(x).tolist() == by_scipy.tolist() == scipy.special.erfc(x).tolist()
    with pytest.raises(RuntimeError), special.standard_library():
        raise RuntimeError("leaves the context")
    assert special.erf(x).tolist() == scipy.special.erf(x).tolist()


@pytest.mark.parametrize("model", ["sentman", "schaaf", "maxwell", "cll", "dria"])
def test_every_model_using_erf_gives_the_same_coefficients_by_either(model):
    flow = FreeStream(7500.0, 900.0, {"O": 8e14, "N2": 2e14, "He": 3e13, "O2": 1e13})
    c = np.cos(np.radians(np.linspace(0.0, 180.0, 91)))
    sigma = np.sqrt(1.0 - c * c)
    properties = SurfaceProperties(alpha=0.9, alpha_n=0.8, sigma_n=0.9, sigma_t=0.7)
    surface = MaterialTable(properties).expand(("default",), np.zeros(c.size, dtype=int))
    function, options = get_model(model), ModelOptions()
    by_scipy = function(c, sigma, surface, flow, options)
    with special.standard_library():
        by_math = function(c, sigma, surface, flow, options)
    for a, b in zip(by_math, by_scipy):
        np.testing.assert_allclose(a, b, rtol=1e-13, atol=1e-15)
