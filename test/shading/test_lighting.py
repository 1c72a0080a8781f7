"""PanelLighting: its sparse form keeps every lit fraction and shift; bad input is named."""

import numpy as np
import pytest

from adbsat_ros.shading.lighting import PanelLighting


def test_the_sparse_form_keeps_the_lit_fractions_and_shifts():
    f = np.array([1.0, 0.0, 0.25, 1.0, 0.5, 1.0])
    shift = np.array([[0.1, 0.0, 0.0], [0.0, -0.2, 0.05]])
    lighting = PanelLighting(f, [2, 4], shift)
    assert lighting.n_panels == 6
    np.testing.assert_array_equal(lighting.lit_fraction, f)
    np.testing.assert_array_equal(lighting.shaded_index, [1, 2, 4])
    np.testing.assert_array_equal(lighting.shaded_fraction, [0.0, 0.25, 0.5])
    np.testing.assert_array_equal(lighting.shift_index, [2, 4])
    np.testing.assert_array_equal(lighting.shift, shift)
    np.testing.assert_array_equal(lighting.shift_fraction, [0.25, 0.5])
    np.testing.assert_array_equal(lighting.shaded, f == 0.0)
    np.testing.assert_array_equal(lighting.partly_lit, (f > 0.0) & (f < 1.0))
    # the caller's arrays are copied: changing them later changes nothing
    f[:] = 0.0
    shift[:] = 9.0
    assert lighting.lit_fraction[0] == 1.0 and lighting.shift[0, 0] == 0.1
    for array in (lighting.lit_fraction, lighting.shaded_fraction, lighting.shift):
        with pytest.raises(ValueError):
            array[0] = 0.5
    everything = PanelLighting.all_lit(4)
    assert everything.shaded_index.size == 0 and everything.shift.shape == (0, 3)
    np.testing.assert_array_equal(everything.lit_fraction, np.ones(4))


@pytest.mark.parametrize(
    "f, index, shift, message",
    [
        ([1.0, 1.2], None, None, r"lit_fraction must be a 1-D array of numbers in \[0, 1\]"),
        ([1.0, np.nan], None, None, "lit_fraction must be"),
        ([[1.0]], None, None, "lit_fraction must be a 1-D"),
        ([1.0, 0.5], [1], np.zeros((2, 3)), r"shift must have shape \(1, 3\)"),
        ([1.0, 0.5], [2], np.zeros((1, 3)), r"shift_index must be panel indices in \[0, 1\]"),
    ],
)
def test_bad_lightings_are_named(f, index, shift, message):
    with pytest.raises(ValueError, match=message):
        PanelLighting(f, index, shift)


def test_many_lightings_at_once_equal_one_at_a_time():
    f = np.array([[1.0, 0.0, 0.25, 1.0], [1.0, 1.0, 1.0, 1.0], [0.5, 1.0, 1.0, 0.75]])
    rows, index = np.array([0, 2, 2]), np.array([2, 0, 3])
    shift = np.array([[0.1, 0.0, 0.0], [0.0, -0.2, 0.05], [0.3, 0.0, 0.1]])
    for k, lighting in enumerate(PanelLighting.many(f, rows, index, shift)):
        one = PanelLighting(f[k], index[rows == k], shift[rows == k])
        for name in PanelLighting.__slots__:
            np.testing.assert_array_equal(getattr(lighting, name), getattr(one, name))
        with pytest.raises(ValueError):
            lighting.shaded_fraction[:1] = 0.5
    with pytest.raises(ValueError, match=r"lit_fraction must be numbers in \[0, 1\]"):
        PanelLighting.many(f + 0.5, rows, index, shift)
