"""Frames: the quaternion rotation matrix on the node's hot path against scipy's Rotation."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from adbsat_ros.geometry.frames import quaternion_matrix

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
