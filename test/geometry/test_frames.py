"""Frames: the quaternion rotation matrix on the node's hot path against scipy's Rotation."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from adbsat_ros.geometry.frames import (
    cross,
    direction_components,
    quaternion_matrix_floats,
    unit_vector,
)


def quaternion_matrix(x, y, z, w):
    return np.array(quaternion_matrix_floats(x, y, z, w)).reshape(3, 3)


components = st.floats(-1.0, 1.0, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(components, components, components, components)
def test_quaternion_matrix_equals_scipy(x, y, z, w):
    q = np.array([x, y, z, w])
    norm = np.linalg.norm(q)
    if norm < 1e-3:
        return
    q /= norm
    R = quaternion_matrix(*q)
    np.testing.assert_allclose(R, Rotation.from_quat(q).as_matrix(), atol=1e-14)
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-14)
    assert abs(np.linalg.det(R) - 1.0) < 1e-13


def test_quaternion_matrix_turns_x_to_y_for_90_degrees_about_z():
    h = np.sqrt(0.5)
    np.testing.assert_allclose(
        quaternion_matrix(0.0, 0.0, h, h) @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], atol=1e-15
    )


def test_direction_components_and_unit_vector_check_the_same_inputs():
    """A direction's components come back as floats, unscaled; unit_vector scales them to length
    1; both refuse what is no finite non-zero 3-vector, naming the input."""
    assert direction_components(np.array([3.0, 0.0, -4.0])) == (3.0, 0.0, -4.0)
    assert direction_components([[1, 2, 2]], "wind") == (1.0, 2.0, 2.0)
    np.testing.assert_array_equal(unit_vector([3.0, 0.0, -4.0]), [0.6, 0.0, -0.8])
    for bad in ([0.0, 0.0, 0.0], [1.0, np.nan, 0.0], [np.inf, 0.0, 0.0], [1.0, 2.0], "abc"):
        for check in (direction_components, unit_vector):
            with pytest.raises(ValueError, match="^wind must be a finite non-zero 3-vector"):
                check(bad, "wind")


@given(
    st.lists(st.floats(-1e3, 1e3), min_size=3, max_size=3),
    st.lists(st.floats(-1e3, 1e3), min_size=3, max_size=3),
)
@settings(max_examples=200)
def test_cross_equals_numpy_cross(a, b):
    """The cross product of single vectors and of stacks is numpy's, to the last bit."""
    a, b = np.array(a), np.array(b)
    np.testing.assert_array_equal(cross(a, b), np.cross(a, b))
    stack_a, stack_b = np.stack([a, b, a]), np.stack([b, a, b])
    np.testing.assert_array_equal(cross(stack_a, stack_b), np.cross(stack_a, stack_b))
