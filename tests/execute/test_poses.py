"""Tests for lfdkit.execute.poses: rotation vectors, UR pose vectors and sweeping poses.

Conversions are checked against ``scipy.spatial.transform.Rotation``; at exactly
π, where two rotation vectors are valid, against either one plus the documented
sign rule.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from lfdkit.core.geometry import point_tangents
from lfdkit.execute.poses import (
    matrix_from_rotvec,
    path_yaw,
    pose_matrix,
    pose_vector,
    rotvec_from_matrix,
    unwrap_rotvecs,
)
from lfdkit.tasks.sweeping.scenarios import sweeping_poses

SETTINGS = settings(max_examples=50, deadline=None)
TOL = 1e-12


def random_axes(n: int, seed: int = 0) -> np.ndarray:
    a = np.random.default_rng(seed).normal(size=(n, 3))
    return a / np.linalg.norm(a, axis=1, keepdims=True)


def angle_between(Ra: np.ndarray, Rb: np.ndarray) -> np.ndarray:
    """Rotation angle of ``Raᵀ Rb`` for stacks of matrices."""
    rel = np.swapaxes(Ra, -1, -2) @ Rb
    return np.linalg.norm(Rotation.from_matrix(rel).as_rotvec(), axis=-1)


def check_pi_sign(r: np.ndarray) -> None:
    """First axis component above 1e-9 is positive (the documented rule at θ = π)."""
    for row in np.atleast_2d(r):
        a = row / np.linalg.norm(row)
        first = int(np.argmax(np.abs(a) > 1e-9))
        assert a[first] > 0


# ------------------------------------------------------------------ rotation vectors
def test_random_rotations_match_scipy():
    rot = Rotation.random(2000, random_state=1)
    np.testing.assert_allclose(rotvec_from_matrix(rot.as_matrix()), rot.as_rotvec(), atol=TOL)
    np.testing.assert_allclose(matrix_from_rotvec(rot.as_rotvec()), rot.as_matrix(), atol=TOL)


@pytest.mark.parametrize("angle", [1e-12, 1e-8, 1e-4, 1.0, np.pi - 1e-6, np.pi - 1e-9])
def test_special_angles_match_scipy(angle):
    r = angle * random_axes(200, seed=2)
    R = Rotation.from_rotvec(r).as_matrix()
    np.testing.assert_allclose(matrix_from_rotvec(r), R, atol=TOL)
    np.testing.assert_allclose(rotvec_from_matrix(R), r, atol=TOL)
    np.testing.assert_allclose(rotvec_from_matrix(R), Rotation.from_matrix(R).as_rotvec(), atol=TOL)


def test_identity_and_zero():
    np.testing.assert_array_equal(rotvec_from_matrix(np.eye(3)), np.zeros(3))
    np.testing.assert_array_equal(matrix_from_rotvec(np.zeros(3)), np.eye(3))
    np.testing.assert_array_equal(
        matrix_from_rotvec(np.zeros((4, 3))), np.tile(np.eye(3), (4, 1, 1))
    )


@pytest.mark.parametrize(
    "axis",
    [[1, 0, 0], [0, 1, 0], [0, 0, 1], [-1, 0, 0], [0, -1, 0], [0, 0, -1], [1, -1, 0], [0, -3, 4]],
)
def test_exactly_pi_about_axes(axis):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    R = 2.0 * np.outer(a, a) - np.eye(3)  # rotation by π about a, exactly symmetric
    r = rotvec_from_matrix(R)
    assert np.linalg.norm(r) == pytest.approx(np.pi, abs=TOL)
    sign = 1.0 if np.allclose(r, np.pi * a, atol=TOL) else -1.0
    np.testing.assert_allclose(r, sign * np.pi * a, atol=TOL)
    check_pi_sign(r)
    np.testing.assert_allclose(matrix_from_rotvec(r), R, atol=TOL)


def test_exactly_pi_random_axes():
    a = random_axes(500, seed=3)
    for sign in (1.0, -1.0):
        R = Rotation.from_rotvec(sign * np.pi * a).as_matrix()
        r = rotvec_from_matrix(R)
        scipy_r = Rotation.from_matrix(R).as_rotvec()
        diff = np.minimum(np.abs(r - scipy_r).max(1), np.abs(r + scipy_r).max(1))
        assert diff.max() < TOL
        np.testing.assert_allclose(np.linalg.norm(r, axis=1), np.pi, atol=TOL)
        check_pi_sign(r)
        np.testing.assert_allclose(matrix_from_rotvec(r), R, atol=TOL)


def test_pi_sign_is_consistent_for_both_representations():
    a = random_axes(50, seed=4)
    r_plus = rotvec_from_matrix(matrix_from_rotvec(np.pi * a))
    r_minus = rotvec_from_matrix(matrix_from_rotvec(-np.pi * a))
    np.testing.assert_allclose(r_plus, r_minus, atol=TOL)


def test_single_and_stacked_shapes():
    assert rotvec_from_matrix(np.eye(3)).shape == (3,)
    assert rotvec_from_matrix(np.eye(3)[None]).shape == (1, 3)
    assert matrix_from_rotvec([0.1, 0.2, 0.3]).shape == (3, 3)
    assert matrix_from_rotvec(np.zeros((5, 3))).shape == (5, 3, 3)


def test_large_rotation_vectors_are_accepted():
    r = np.array([0.0, 0.0, 2.0 * np.pi + 0.5])
    np.testing.assert_allclose(matrix_from_rotvec(r), Rotation.from_rotvec(r).as_matrix(), atol=TOL)
    np.testing.assert_allclose(rotvec_from_matrix(matrix_from_rotvec(r)), [0, 0, 0.5], atol=TOL)


rotvecs = st.tuples(
    st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1), st.floats(0, np.pi - 1e-6)
).filter(lambda v: np.linalg.norm(v[:3]) > 1e-3)


@SETTINGS
@given(rotvecs)
def test_round_trip_property(v):
    axis = np.asarray(v[:3]) / np.linalg.norm(v[:3])
    r = v[3] * axis
    R = matrix_from_rotvec(r)
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=TOL)
    assert np.linalg.det(R) == pytest.approx(1.0, abs=TOL)
    np.testing.assert_allclose(rotvec_from_matrix(R), r, atol=1e-10)
    np.testing.assert_allclose(R, Rotation.from_rotvec(r).as_matrix(), atol=TOL)


@SETTINGS
@given(st.integers(0, 2**32 - 1))
def test_matrix_round_trip_property(seed):
    R = Rotation.random(random_state=seed).as_matrix()
    np.testing.assert_allclose(matrix_from_rotvec(rotvec_from_matrix(R)), R, atol=TOL)


@pytest.mark.parametrize(
    ("R", "message"),
    [
        (np.eye(2), r"R: expected shape \(3, 3\) or \(n, 3, 3\)"),
        (np.diag([1.0, 1.0, -1.0]), "R: not a rotation matrix .*determinant"),
        (np.eye(3) * 1.01, "R: not a rotation matrix .*orthonormal"),
        (np.full((3, 3), np.nan), "R: contains NaN"),
        ("abc", "R: expected a numeric array"),
    ],
)
def test_rotvec_from_matrix_errors(R, message):
    with pytest.raises((ValueError, TypeError), match=message):
        rotvec_from_matrix(R)


def test_rotvec_from_matrix_names_the_bad_matrix_in_a_stack():
    R = np.tile(np.eye(3), (3, 1, 1))
    R[2, 0, 0] = 2.0
    with pytest.raises(ValueError, match=r"R\[2\]: not a rotation"):
        rotvec_from_matrix(R)


def test_small_orthonormality_error_is_accepted():
    R = Rotation.from_rotvec([0.3, -0.2, 0.1]).as_matrix() + 1e-8
    r = rotvec_from_matrix(R)
    np.testing.assert_allclose(r, [0.3, -0.2, 0.1], atol=1e-7)


def test_matrix_from_rotvec_errors():
    with pytest.raises(ValueError, match=r"r: expected shape \(3,\)"):
        matrix_from_rotvec([1.0, 2.0])
    with pytest.raises(ValueError, match="r: contains an infinite value"):
        matrix_from_rotvec([1.0, np.inf, 0.0])


# ------------------------------------------------------------------ pose vectors
def test_pose_vector_round_trip():
    rot = Rotation.random(100, random_state=5)
    T = np.zeros((100, 4, 4))
    T[:, :3, :3] = rot.as_matrix()
    T[:, :3, 3] = np.random.default_rng(5).uniform(-0.8, 0.8, size=(100, 3))
    T[:, 3, 3] = 1.0
    p = pose_vector(T)
    assert p.shape == (100, 6)
    np.testing.assert_allclose(p[:, :3], T[:, :3, 3], atol=0)
    np.testing.assert_allclose(p[:, 3:], rot.as_rotvec(), atol=TOL)
    np.testing.assert_allclose(pose_matrix(p), T, atol=TOL)
    np.testing.assert_allclose(pose_vector(pose_matrix(p[0])), p[0], atol=TOL)
    assert pose_matrix(p[0]).shape == (4, 4)


def test_pose_errors():
    T = np.eye(4)
    T[3, 0] = 1.0
    with pytest.raises(ValueError, match=r"T: last row must be \[0, 0, 0, 1\]"):
        pose_vector(T)
    T = np.eye(4)
    T[0, 0] = -1.0
    with pytest.raises(ValueError, match="T rotation part: not a rotation matrix"):
        pose_vector(T)
    with pytest.raises(ValueError, match=r"p: expected shape \(6,\)"):
        pose_matrix(np.zeros(5))
    with pytest.raises(ValueError, match="p: contains NaN"):
        pose_matrix([0, 0, np.nan, 0, 0, 0])


# ------------------------------------------------------------------ unwrapping
def test_unwrap_removes_flip_near_pi():
    # Rotation by ~π about an axis sweeping through the horizontal plane: the
    # shortest rotation vectors flip sign where the angle crosses π.
    phi = np.linspace(0, np.pi, 50)
    axis = np.column_stack((np.cos(phi), np.sin(phi), np.zeros_like(phi)))
    angle = np.pi + 0.01 * np.sin(3 * phi)
    R = matrix_from_rotvec(angle[:, None] * axis)
    r = rotvec_from_matrix(R)
    assert np.linalg.norm(np.diff(r, axis=0), axis=1).max() > np.pi  # a jump
    u = unwrap_rotvecs(r)
    np.testing.assert_allclose(u[0], r[0])
    # Neighbouring axes are π/49 apart, so steps of about π · π/49 ≈ 0.2 remain.
    assert np.linalg.norm(np.diff(u, axis=0), axis=1).max() < 0.25
    np.testing.assert_allclose(matrix_from_rotvec(u), R, atol=1e-12)


def test_unwrap_rule_matches_brief_formula():
    r = np.array([[np.pi - 0.01, 0, 0], [-(np.pi - 0.01), 0, 0]])
    u = unwrap_rotvecs(r)
    # r (1 − 2π/|r|) for the second row.
    np.testing.assert_allclose(u[1], r[1] * (1 - 2 * np.pi / np.linalg.norm(r[1])), atol=TOL)


def test_unwrap_identity_after_full_turn():
    r = np.array([[0, 0, 2 * np.pi - 0.01], [0, 0, 0.0]])
    np.testing.assert_allclose(unwrap_rotvecs(r)[1], [0, 0, 2 * np.pi], atol=TOL)


def test_unwrap_leaves_continuous_sequence_alone():
    r = 0.5 * random_axes(1)[0] * np.linspace(0.1, 1, 20)[:, None]
    np.testing.assert_allclose(unwrap_rotvecs(r), r, atol=TOL)


def test_unwrap_errors():
    with pytest.raises(ValueError, match="r: expected 3 columns"):
        unwrap_rotvecs(np.zeros((3, 2)))
    with pytest.raises(ValueError, match="r: contains NaN"):
        unwrap_rotvecs([[0, 0, np.nan]])


# ------------------------------------------------------------------ sweeping
def circle(n: int = 73, radius: float = 0.2, centre=(0.4, -0.1)) -> np.ndarray:
    phi = np.linspace(0, 2 * np.pi, n)
    return np.column_stack((centre[0] + radius * np.cos(phi), centre[1] + radius * np.sin(phi)))


def wiggle() -> np.ndarray:
    x = np.linspace(0.3, 0.6, 40)
    return np.column_stack((x, 0.05 * np.sin(20 * x)))


@pytest.mark.parametrize("path", [circle(), wiggle()])
def test_sweeping_poses_geometry(path):
    T = sweeping_poses(path)
    R = T[:, :3, :3]
    assert T.shape == (len(path), 4, 4)
    np.testing.assert_allclose(
        np.swapaxes(R, 1, 2) @ R, np.tile(np.eye(3), (len(path), 1, 1)), atol=TOL
    )
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=TOL)
    np.testing.assert_array_equal(T[:, :2, 3], path)
    np.testing.assert_array_equal(T[:, 2, 3], 0.192)
    np.testing.assert_array_equal(T[:, 3], np.tile([0, 0, 0, 1.0], (len(path), 1)))
    np.testing.assert_allclose(R[:, :, 2], np.tile([0, 0, -1.0], (len(path), 1)), atol=0)  # z down
    tangent = point_tangents(path)
    np.testing.assert_allclose(R[:, :2, 0], tangent, atol=TOL)  # x along the path
    np.testing.assert_allclose(R[:, 2, 0], 0.0, atol=0)
    brush = R[:, :2, 1]
    np.testing.assert_allclose(np.einsum("ij,ij->i", brush, tangent), 0.0, atol=TOL)  # brush ⟂ path
    np.testing.assert_allclose(R[:, 2, 1], 0.0, atol=0)  # brush level


def test_sweeping_roll_pitch_zero_tool_down():
    # R = Rz(ψ) Rx(π): with the tool pointing down nothing tilts the brush.
    psi = path_yaw(wiggle())
    T = sweeping_poses(wiggle())
    rz = Rotation.from_euler("z", psi[:, None]).as_matrix()
    expected = rz @ Rotation.from_euler("x", np.pi).as_matrix()
    np.testing.assert_allclose(T[:, :3, :3], expected, atol=TOL)


def test_sweeping_options():
    path = wiggle()
    T = sweeping_poses(path, height=0.25, tool_down=False, yaw_offset=np.pi / 2)
    np.testing.assert_array_equal(T[:, 2, 3], 0.25)
    np.testing.assert_allclose(T[:, :3, 2], np.tile([0, 0, 1.0], (len(path), 1)), atol=0)
    np.testing.assert_allclose(np.linalg.det(T[:, :3, :3]), 1.0, atol=TOL)
    # Offset by 90°: the tool x axis is the path's left normal.
    t = point_tangents(path)
    np.testing.assert_allclose(T[:, :2, 0], np.column_stack((-t[:, 1], t[:, 0])), atol=TOL)


def test_yaw_is_continuous_on_a_full_circle():
    path = circle(n=73)
    psi = path_yaw(path)
    turning = 2 * np.pi / 72
    assert np.abs(np.diff(psi)).max() <= turning + 1e-9
    # End tangents are the end segments' directions, half a step off the circle's.
    assert psi[-1] - psi[0] == pytest.approx(2 * np.pi - turning, abs=1e-9)
    # Going round twice keeps unwinding.
    two_laps = np.vstack((path, path[1:]))
    lap_psi = path_yaw(two_laps)
    assert lap_psi[-1] - lap_psi[0] == pytest.approx(4 * np.pi - turning, abs=1e-9)
    # The frames turn by the turning angle between samples, never more.
    T = sweeping_poses(path)
    steps = angle_between(T[:-1, :3, :3], T[1:, :3, :3])
    assert steps.max() <= turning + 1e-9


def test_sweeping_rotvecs_unwrapped_are_continuous():
    p = pose_vector(sweeping_poses(circle(n=145)))
    r = unwrap_rotvecs(p[:, 3:])
    # Each pose is a rotation by π about a horizontal axis at half the yaw; the axis
    # turns by half the path's turning, so |Δr| ≈ π · (2π / 144) / 2.
    assert np.linalg.norm(np.diff(r, axis=0), axis=1).max() < np.pi * (2 * np.pi / 144)
    np.testing.assert_allclose(
        pose_matrix(np.column_stack((p[:, :3], r))), sweeping_poses(circle(n=145)), atol=TOL
    )


def test_sweeping_repeated_points_are_tolerated():
    path = np.array([[0.3, 0.0], [0.3, 0.0], [0.4, 0.0], [0.5, 0.1]])
    T = sweeping_poses(path)
    np.testing.assert_allclose(T[0, :2, 0], [1.0, 0.0], atol=TOL)


@pytest.mark.parametrize(
    ("path", "kwargs", "message"),
    [
        ([[0.3, 0.1]], {}, "path: needs at least 2 points"),
        ([[0.3, 0.1], [0.3, 0.1]], {}, "path: has zero length"),
        ([[0.3, 0.1], [np.nan, 0.2]], {}, "path: contains NaN"),
        ([[0.3, 0.1, 0.0], [0.4, 0.2, 0.0]], {}, "path: expected 2 columns"),
        ([0.3, 0.1], {}, "path: expected a 2-D array"),
        ([[0.3, 0.1], [0.4, 0.1]], {"height": np.nan}, "height: must be finite"),
        ([[0.3, 0.1], [0.4, 0.1]], {"yaw_offset": np.inf}, "yaw_offset: must be finite"),
        ([[0.3, 0.1], [0.4, 0.1], [0.3, 0.1]], {}, "path: turns back onto itself"),
    ],
)
def test_sweeping_errors(path, kwargs, message):
    with pytest.raises(ValueError, match=message):
        sweeping_poses(path, **kwargs)
