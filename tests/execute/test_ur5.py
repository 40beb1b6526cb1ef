"""Tests for lfdkit.execute.ur5: forward kinematics, Jacobian, analytic inverse, singularities.

Known answers: the flange pose at hand-computed configurations, an independent forward
kinematics built with pytransform3d, finite differences for the Jacobian and its
closed-form determinant, and inverse/forward round trips.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from lfdkit.execute.arm import UR5
from lfdkit.execute.ur5 import (
    JointLimitError,
    SingularityError,
    UnreachableError,
    branch,
    forward,
    inverse,
    inverse_path,
    jacobian,
    link_frames,
    nearest_solution,
    singularity,
)

D1, _, _, D4, D5, D6 = UR5.d
_, A2, A3, _, _, _ = UR5.a
JOINT_LIMITS = UR5.joint_limits
PI = np.pi

# A brush: tool centre 0.12 m along the flange z axis, bristles turned 0.3 rad about it.
BRUSH = np.eye(4)
BRUSH[:3, :3] = Rotation.from_rotvec([0.0, 0.0, 0.3]).as_matrix()
BRUSH[:3, 3] = [0.0, 0.01, 0.12]


def random_q(n: int, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-PI, PI, (n, 6))


def pose_errors(t1: np.ndarray, t2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position error (m) and rotation angle (rad) between poses (..., 4, 4)."""
    pos = np.linalg.norm(t1[..., :3, 3] - t2[..., :3, 3], axis=-1)
    rel = np.swapaxes(t1[..., :3, :3], -1, -2) @ t2[..., :3, :3]
    # Skew part of R1^T R2 is sin(angle) times the axis: well conditioned near 0.
    skew = rel - np.swapaxes(rel, -1, -2)
    ang = np.linalg.norm(skew, axis=(-2, -1)) / (2 * np.sqrt(2))
    return pos, np.arcsin(np.minimum(ang, 1.0))


def wrapped(x: np.ndarray) -> np.ndarray:
    return np.abs(np.angle(np.exp(1j * x)))


def shoulder_singular_q() -> np.ndarray:
    """q with a2 cos q2 + a3 cos(q2 + q3) + d5 sin(q2 + q3 + q4) = 0, elsewhere generic."""
    q2, q3 = -PI / 2 + 0.3, -0.6
    x = A2 * np.cos(q2) + A3 * np.cos(q2 + q3)
    q4 = np.arcsin(-x / D5) - q2 - q3
    return np.array([0.4, q2, q3, q4, 1.0, 0.2])


def brush_down_line(n: int = 61) -> np.ndarray:
    """Flange poses moving 0.3 m along y at x = 0.4, z = 0.2, tool axis pointing down."""
    poses = np.tile(np.eye(4), (n, 1, 1))
    poses[:, :3, :3] = np.diag([1.0, -1.0, -1.0])
    poses[:, :3, 3] = np.column_stack(
        (np.full(n, 0.4), np.linspace(-0.15, 0.15, n), np.full(n, 0.2))
    )
    return poses


# ---------------------------------------------------------------- constants
def test_constants():
    np.testing.assert_array_equal(UR5.d, (0.08916, 0.0, 0.0, 0.10915, 0.09465, 0.0823))
    np.testing.assert_array_equal(UR5.a, (0.0, -0.425, -0.39225, 0.0, 0.0, 0.0))
    np.testing.assert_allclose(UR5.alpha, [PI / 2, 0, 0, PI / 2, -PI / 2, 0])
    assert JOINT_LIMITS.shape == (6, 2)
    np.testing.assert_array_equal(JOINT_LIMITS, [[-2 * PI, 2 * PI]] * 6)
    with pytest.raises(ValueError):
        JOINT_LIMITS[0, 0] = 0.0  # read-only
    np.testing.assert_array_equal(UR5.max_joint_speed, [3.2] * 6)
    np.testing.assert_array_equal(UR5.max_joint_acceleration, [15.0] * 6)


# ---------------------------------------------------------------- forward kinematics
def test_forward_at_zero_is_the_hand_computed_pose():
    # Frame 1 is Rot_x(90°) at height d1; a2, a3 run along x; d4 along -y; after a second
    # Rot_x(90°) d5 runs along -z; after Rot_x(-90°) d6 runs along -y.
    expected = np.array(
        [
            [1.0, 0.0, 0.0, A2 + A3],
            [0.0, 0.0, -1.0, -(D4 + D6)],
            [0.0, 1.0, 0.0, D1 - D5],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )
    np.testing.assert_allclose(forward(np.zeros(6)), expected, atol=1e-15)
    np.testing.assert_allclose(expected[:3, 3], [-0.81725, -0.19145, -0.00549], atol=1e-12)


@pytest.mark.parametrize(
    ("q", "rot", "pos"),
    [
        # Arm straight up: a2, a3 point along +z, d5 adds height, d4 + d6 along -y.
        (
            [0, -PI / 2, 0, -PI / 2, 0, 0],
            [[-1, 0, 0], [0, 0, -1], [0, -1, 0]],
            [0.0, -(D4 + D6), D1 - A2 - A3 + D5],
        ),
        # The zero pose turned 90° about the base axis.
        (
            [PI / 2, 0, 0, 0, 0, 0],
            [[0, 0, 1], [1, 0, 0], [0, 1, 0]],
            [D4 + D6, A2 + A3, D1 - D5],
        ),
        # Zero pose with the wrist turned 90°: d6 now points along -x.
        (
            [0, 0, 0, 0, PI / 2, 0],
            [[0, 0, -1], [-1, 0, 0], [0, 1, 0]],
            [A2 + A3 - D6, -D4, D1 - D5],
        ),
        # Last joint only spins the flange about its own z axis.
        (
            [0, 0, 0, 0, 0, PI / 2],
            [[0, -1, 0], [0, 0, -1], [1, 0, 0]],
            [A2 + A3, -(D4 + D6), D1 - D5],
        ),
    ],
)
def test_forward_hand_checked_configurations(q, rot, pos):
    t = forward(q)
    np.testing.assert_allclose(t[:3, :3], rot, atol=1e-15)
    np.testing.assert_allclose(t[:3, 3], pos, atol=1e-15)
    np.testing.assert_array_equal(t[3], [0, 0, 0, 1])


def test_forward_against_pytransform3d():
    pr = pytest.importorskip("pytransform3d.rotations")
    pt = pytest.importorskip("pytransform3d.transformations")
    qs = random_q(1000, seed=1)

    def concat(a2b, b2c):
        # concat(A2B, B2C) = B2C @ A2B; the inputs were checked where they were built.
        return pt.concat(a2b, b2c, check=False)

    tz = [pt.transform_from(np.eye(3), [0.0, 0.0, d]) for d in UR5.d]
    tx = [pt.transform_from(np.eye(3), [a, 0.0, 0.0]) for a in UR5.a]
    rx = [pt.transform_from(pr.active_matrix_from_angle(0, al), np.zeros(3)) for al in UR5.alpha]
    expected = np.empty((len(qs), 4, 4))
    for k, q in enumerate(qs):
        t = np.eye(4)
        for i in range(6):
            rz = pt.transform_from(pr.active_matrix_from_angle(2, q[i]), np.zeros(3))
            # Rot_z Trans_z Trans_x Rot_x, built from the right, applied after T_0^i.
            t = concat(concat(concat(concat(rx[i], tx[i]), tz[i]), rz), t)
        expected[k] = t
    got = forward(qs)
    assert np.abs(got[:, :3, 3] - expected[:, :3, 3]).max() < 1e-12
    assert np.abs(got[:, :3, :3] - expected[:, :3, :3]).max() < 1e-12


def test_forward_tool_and_batch():
    qs = random_q(20, seed=2)
    flange = forward(qs)
    np.testing.assert_allclose(forward(qs, tool=BRUSH), flange @ BRUSH, atol=1e-15)
    np.testing.assert_allclose(
        forward(qs, tool=BRUSH)[:, :3, 3],
        flange[:, :3, 3] + flange[:, :3, :3] @ BRUSH[:3, 3],
        atol=1e-15,
    )
    for q, t in zip(qs, flange, strict=True):
        np.testing.assert_array_equal(forward(q), t)
    assert forward(np.zeros((0, 6))).shape == (0, 4, 4)


def test_link_frames():
    qs = random_q(5, seed=3)
    frames = link_frames(qs)
    assert frames.shape == (5, 7, 4, 4)
    np.testing.assert_array_equal(frames[:, 0], np.broadcast_to(np.eye(4), (5, 4, 4)))
    np.testing.assert_allclose(frames[:, 6], forward(qs), atol=1e-15)
    # Joint 2 sits at height d1 above the base whatever q1 is.
    np.testing.assert_allclose(frames[:, 1, :3, 3], [[0.0, 0.0, D1]] * 5, atol=1e-15)
    np.testing.assert_array_equal(link_frames(qs[0]), frames[0])


# ---------------------------------------------------------------- Jacobian
@pytest.mark.parametrize("tool", [None, BRUSH])
def test_jacobian_matches_finite_differences(tool):
    qs = random_q(40, seed=4)
    h = 1e-6
    jac = jacobian(qs, tool=tool)
    assert jac.shape == (40, 6, 6)
    for q, j in zip(qs, jac, strict=True):
        fd = np.empty((6, 6))
        for i in range(6):
            dq = np.zeros(6)
            dq[i] = h
            tp, tm = forward(q + dq, tool=tool), forward(q - dq, tool=tool)
            fd[:3, i] = (tp[:3, 3] - tm[:3, 3]) / (2 * h)
            rel = tp[:3, :3] @ tm[:3, :3].T  # rotation over 2h, in the base frame
            fd[3:, i] = Rotation.from_matrix(rel).as_rotvec() / (2 * h)
        np.testing.assert_allclose(j, fd, atol=1e-6)
    np.testing.assert_array_equal(jacobian(qs[0], tool=tool), jac[0])


def test_jacobian_determinant_closed_form():
    # det J = a2 a3 s3 s5 (a2 c2 + a3 c23 + d5 s234): the three singularities.
    qs = random_q(200, seed=5)
    q2, q3 = qs[:, 1], qs[:, 2]
    expected = (
        A2
        * A3
        * np.sin(q3)
        * np.sin(qs[:, 4])
        * (A2 * np.cos(q2) + A3 * np.cos(q2 + q3) + D5 * np.sin(qs[:, 1:4].sum(axis=1)))
    )
    np.testing.assert_allclose(np.linalg.det(jacobian(qs)), expected, atol=1e-14)


# ---------------------------------------------------------------- inverse kinematics
def test_inverse_round_trip_2000_random_configurations():
    qs = random_q(2000, seed=6)
    poses = forward(qs)
    sols = inverse(poses)
    assert sols.shape == (2000, 8, 6)
    valid = ~np.isnan(sols[..., 0])
    assert np.array_equal(valid, ~np.isnan(sols).any(axis=-1))  # whole rows are NaN
    assert (sols[valid] > -PI).all() and (sols[valid] <= PI).all()
    # Every returned solution reproduces its pose.
    back = forward(np.where(valid[..., None], sols, 0.0).reshape(-1, 6)).reshape(2000, 8, 4, 4)
    pos, ang = pose_errors(back, poses[:, None])
    assert pos[valid].max() < 1e-9 and ang[valid].max() < 1e-9
    # Away from singularities the row branch(q) is q itself (modulo 2π) and the branches
    # come in elbow pairs.
    far = ~singularity(qs, tol=1e-3).any
    assert far.sum() > 1800
    own = sols[np.arange(2000), branch(qs)]
    assert wrapped(own[far] - qs[far]).max() < 1e-8
    counts = valid.sum(axis=1)
    assert (counts[far] % 2 == 0).all() and (counts >= 2).all()
    assert np.mean(counts[far] == 8) > 0.6  # most random poses: all eight branches
    # Each returned row belongs to the branch it is filed under.
    rows = np.broadcast_to(np.arange(8), (2000, 8))
    near = singularity(np.nan_to_num(sols).reshape(-1, 6), tol=1e-3).any.reshape(2000, 8)
    generic = valid & ~near
    assert np.array_equal(branch(sols[generic]), rows[generic])
    # Batch and single poses agree.
    for k in range(0, 2000, 250):
        np.testing.assert_array_equal(inverse(poses[k]), sols[k])


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-PI, PI), min_size=6, max_size=6))
def test_inverse_round_trip_hypothesis(q):
    q = np.array(q)
    assume(not singularity(q, tol=1e-3).any)
    pose = forward(q, tool=BRUSH)
    sols = inverse(pose, tool=BRUSH)
    valid = ~np.isnan(sols[:, 0])
    pos, ang = pose_errors(forward(sols[valid], tool=BRUSH), pose)
    assert pos.max() < 1e-9 and ang.max() < 1e-9
    assert wrapped(sols[branch(q)] - q).max() < 1e-8


def test_inverse_eight_solutions_in_the_workspace():
    poses = brush_down_line(11)
    sols = inverse(poses)
    assert not np.isnan(sols).any()
    np.testing.assert_array_equal(branch(sols.reshape(-1, 6)), np.tile(np.arange(8), 11))
    pos, ang = pose_errors(forward(sols.reshape(-1, 6)).reshape(11, 8, 4, 4), poses[:, None])
    assert pos.max() < 1e-12 and ang.max() < 1e-12


def test_inverse_unreachable():
    far = np.eye(4)
    far[:3, 3] = [2.0, 0.0, 0.3]
    with pytest.raises(UnreachableError, match=r"pose: unreachable.*too far") as info:
        inverse(far)
    assert info.value.index is None
    assert "(2, 0, 0.3)" in str(info.value)
    # Wrist point on the base axis: inside the shoulder offset d4.
    axis = np.eye(4)
    axis[:3, 3] = [0.0, 0.0, 0.5 - D6]
    axis[:3, :3] = np.diag([1.0, -1.0, -1.0])  # tool pointing down: wrist point at (0, 0, 0.5)
    with pytest.raises(UnreachableError, match="too close to the base axis"):
        inverse(axis)
    batch = np.stack([forward(np.full(6, 0.3)), far, far])
    with pytest.raises(UnreachableError, match=r"pose\[1\]") as info:
        inverse(batch)
    assert info.value.index == 1
    lenient = inverse(batch, strict=False)
    assert np.isnan(lenient[1:]).all() and not np.isnan(lenient[0]).all()


def test_inverse_at_singular_poses():
    # Wrist (q5 = 0): q6 takes the hint and q4 the rest of the rotation.
    q = np.array([0.4, -1.0, 1.2, -0.5, 0.0, 0.2])
    pose = forward(q)
    for hint in (0.0, 0.2, -2.5):
        sols = inverse(pose, q6_hint=hint)
        near = sols[branch(q)]
        assert near[5] == pytest.approx(hint)
        pos, ang = pose_errors(forward(sols[~np.isnan(sols[:, 0])]), pose)
        assert pos.max() < 1e-12 and ang.max() < 1e-12
    np.testing.assert_allclose(inverse(pose, q6_hint=0.2)[branch(q)], q, atol=1e-12)
    # Shoulder: both shoulder branches coincide.
    qs = shoulder_singular_q()
    sols = inverse(forward(qs))
    np.testing.assert_allclose(sols[:4], sols[4:], atol=1e-7)
    assert wrapped(sols[branch(qs)] - qs).max() < 1e-7
    # Elbow stretched: both elbow branches coincide.
    qe = np.array([0.4, -1.0, 0.0, -0.5, 1.0, 0.2])
    sols = inverse(forward(qe))
    np.testing.assert_allclose(sols[branch(qe)], qe, atol=1e-7)
    np.testing.assert_allclose(sols[branch(qe) ^ 1], qe, atol=1e-7)


# ---------------------------------------------------------------- nearest solution
def test_nearest_solution_keeps_the_branch_and_uses_2pi_equivalents():
    q = np.array([-0.5, -1.0, 1.2, -1.5, 1.0, -0.7])
    pose = forward(q)
    np.testing.assert_allclose(nearest_solution(pose, q + 0.01), q, atol=1e-12)
    # A reference one turn up on joints 1 and 6 gets the equivalent within ±2π.
    ref = q + np.array([2 * PI, 0, 0, 0, 0, 2 * PI])
    np.testing.assert_allclose(nearest_solution(pose, ref), ref, atol=1e-12)
    # Tight limits that exclude the +2π equivalent of joint 1 fall back to q1 itself.
    limits = np.array(JOINT_LIMITS)
    limits[0] = [-1.0, 1.0]
    np.testing.assert_allclose(nearest_solution(pose, ref, limits=limits)[0], q[0])
    # Batch agrees with single poses.
    qs = random_q(30, seed=7)
    poses = forward(qs)
    batch = nearest_solution(poses, qs)
    np.testing.assert_allclose(batch, qs, atol=1e-8)
    np.testing.assert_array_equal(nearest_solution(poses[3], qs[3]), batch[3])


def test_nearest_solution_joint_limits():
    q = np.array([2.5, -1.0, 1.2, -1.5, 1.0, 0.7])
    pose = forward(q)
    sols = inverse(pose)
    valid = sols[~np.isnan(sols[:, 0])]
    np.testing.assert_allclose(np.unique(valid[:, 0].round(6)), [-0.334498, 2.5], atol=1e-6)
    # Neither shoulder angle nor any ±2π equivalent lies in [-0.2, 0.2].
    limits = np.array(JOINT_LIMITS)
    limits[0] = [-0.2, 0.2]
    with pytest.raises(JointLimitError, match=r"pose: none of the 4 .* within limits") as info:
        nearest_solution(pose, q, limits=limits)
    assert info.value.index is None
    q_ok = np.full(6, 0.1)
    poses = np.stack([forward(q_ok), pose])
    with pytest.raises(JointLimitError, match=r"pose\[1\]") as info:
        nearest_solution(poses, [q_ok, q], limits=limits)
    assert info.value.index == 1


# ---------------------------------------------------------------- singularities
def test_singularity_reports_each_kind():
    cases = {
        ("wrist",): np.array([0.4, -1.0, 1.2, -0.5, 0.0, 0.2]),
        ("shoulder",): shoulder_singular_q(),
        ("elbow",): np.array([0.4, -1.0, 0.0, -0.5, 1.0, 0.2]),
        ("wrist", "shoulder", "elbow"): np.array([0, -PI / 2, 0, -PI / 2, 0, 0]),
        (): np.array([0.4, -1.0, 1.2, -1.5, 1.0, 0.2]),
    }
    for kinds, q in cases.items():
        report = singularity(q)
        assert report.kinds == kinds
        assert report.any == bool(kinds)
        if kinds:
            assert report.sigma_min < 1e-12
        else:
            assert report.sigma_min > 1e-2
    batch = singularity(np.stack(list(cases.values())))
    assert batch.kinds == list(cases)
    np.testing.assert_array_equal(batch.any, [True, True, True, True, False])
    # Measures are the documented ones.
    q = np.array([0.4, -1.0, 0.3, -0.5, 0.02, 0.2])
    report = singularity(q, tol=0.05)
    assert report.wrist_measure == pytest.approx(np.sin(0.02))
    assert report.elbow_measure == pytest.approx(np.sin(0.3))
    assert report.kinds == ("wrist",)
    assert singularity(q, tol=0.01).kinds == ()
    # The shoulder measure is |x| / r with r the wrist point's distance from z0.
    p5 = link_frames(q)[5, :3, 3]
    r = np.hypot(p5[0], p5[1])
    assert report.shoulder_measure == pytest.approx(np.sqrt(r**2 - D4**2) / r)


# ---------------------------------------------------------------- joint paths
@pytest.mark.parametrize("tool", [None, BRUSH])
def test_inverse_path_along_a_line_is_continuous(tool):
    poses = brush_down_line(61)
    if tool is not None:
        poses = poses @ tool
    starts = inverse(poses[0], tool=tool)
    for b in (0, 3, 6):
        path = inverse_path(poses, starts[b], tool=tool)
        assert path.shape == (61, 6)
        assert np.abs(np.diff(path, axis=0)).max() < 0.02  # 5 mm steps, no flips
        assert (branch(path) == b).all()
        pos, ang = pose_errors(forward(path, tool=tool), poses)
        assert pos.max() < 1e-12 and ang.max() < 1e-12


def test_inverse_path_unwraps_across_pi():
    # Joint 1 passes through ±π: the path stays continuous (beyond π, inside ±2π).
    qs = np.column_stack((np.linspace(3.0, 3.3, 31), np.tile([-1.0, 1.2, -1.5, 1.0, 0.7], (31, 1))))
    path = inverse_path(forward(qs), qs[0])
    np.testing.assert_allclose(path, qs, atol=1e-9)


def test_inverse_path_through_the_wrist_singularity():
    q5 = np.linspace(0.2, -0.2, 21)  # sample 10 is q5 = 0
    qs = np.tile([0.4, -1.0, 1.2, -0.5, 0.0, 0.2], (21, 1))
    qs[:, 4] = q5
    with pytest.raises(SingularityError, match=r"poses\[10\].*wrist") as info:
        inverse_path(forward(qs), qs[0])
    assert (info.value.index, info.value.kinds) == (10, ("wrist",))


def test_inverse_path_flip_near_the_wrist_singularity():
    # Constant orientation, flange moving sideways past a wrist singularity that it misses
    # by 0.015 rad: joints 4 and 6 swing through about π around sample 10.
    q_near = np.array([0.3, -1.2, 1.4, -1.9, 0.015, 0.4])
    t0 = forward(q_near)
    radial = np.array([t0[0, 3], t0[1, 3], 0.0])
    side = np.cross([0.0, 0.0, 1.0], radial / np.linalg.norm(radial))
    poses = np.tile(t0, (21, 1, 1))
    poses[:, :3, 3] += np.linspace(-0.1, 0.1, 21)[:, None] * side
    q0 = nearest_solution(poses[0], q_near)
    with pytest.raises(SingularityError, match=r"poses\[10\]: joint 4 jumps") as info:
        inverse_path(poses, q0, max_step=0.5)
    assert info.value.kinds == ()
    # With a loose max_step it goes through, never within tol of the singularity.
    path = inverse_path(poses, q0, max_step=2.0)
    assert singularity(path).wrist_measure.min() > 0.01
    assert np.abs(np.diff(path[:, 3])).max() > 0.5


def test_inverse_path_coarse_jump_unreachable_and_limits():
    poses = brush_down_line(8)
    q0 = inverse(poses[0])[0]
    turned = poses.copy()
    turned[5:, :3, :3] = turned[5:, :3, :3] @ Rotation.from_rotvec([0, 0, 1.0]).as_matrix()
    with pytest.raises(SingularityError, match=r"poses\[5\]: joint 6 jumps by 1\.\d rad"):
        inverse_path(turned, q0)
    far = poses.copy()
    far[6, :3, 3] = [2.0, 0.0, 0.2]
    with pytest.raises(UnreachableError, match=r"poses\[6\]: unreachable.*too far") as info:
        inverse_path(far, q0)
    assert info.value.index == 6
    limits = np.array(JOINT_LIMITS)
    limits[1] = [-7.0, q0[1] + 1e-3]  # the path's shoulder angle soon leaves this range
    path = inverse_path(poses, q0)
    bad = int(np.argmax(path[:, 1] > q0[1] + 1e-3))
    assert bad > 0
    with pytest.raises(JointLimitError, match=rf"poses\[{bad}\]: .*leaves .*joint 2") as info:
        inverse_path(poses, q0, limits=limits)
    assert info.value.index == bad
    limits[1] = JOINT_LIMITS[1]
    limits[0] = [1.0, 1.2]  # no shoulder angle of this path
    with pytest.raises(JointLimitError, match=r"poses\[0\]: no inverse .* within limits"):
        inverse_path(poses, q0, limits=limits)


# ---------------------------------------------------------------- input checks
def bad_rotation() -> np.ndarray:
    t = np.eye(4)
    t[0, 1] = 1e-3
    return t


def reflection() -> np.ndarray:
    return np.diag([1.0, 1.0, -1.0, 1.0])


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: forward(np.zeros(5)), r"q: expected shape \(6,\) or \(n, 6\)"),
        (lambda: forward(np.zeros((2, 3, 6))), r"q: expected shape"),
        (lambda: forward([0, 0, np.nan, 0, 0, 0]), "q: contains NaN"),
        (lambda: forward(np.full((3, 6), np.inf)), r"q\[0\]: contains NaN or an infinite"),
        (lambda: forward(np.zeros(6), tool=np.eye(3)), r"tool: expected shape \(4, 4\)"),
        (lambda: forward(np.zeros(6), tool=bad_rotation()), "tool: rotation part is not orth"),
        (lambda: jacobian("abc"), "q: expected a numeric array"),
        (lambda: inverse(np.eye(3)), r"pose: expected shape \(4, 4\) or \(n, 4, 4\)"),
        (lambda: inverse(bad_rotation()), "pose: rotation part is not orthonormal"),
        (lambda: inverse(np.stack([np.eye(4), bad_rotation()])), r"pose\[1\]: rotation"),
        (lambda: inverse(reflection()), "pose: rotation part is a reflection"),
        (lambda: inverse(np.eye(4) + np.diag([0, 0, 0, 1.0])), "pose: bottom row"),
        (lambda: inverse(np.full((4, 4), np.nan)), "pose: contains NaN"),
        (lambda: inverse(forward(np.ones(6)), q6_hint=[1.0, 2.0]), "q6_hint: expected"),
        (lambda: nearest_solution(forward(np.ones(6)), np.ones((2, 6))), "q_ref: expected"),
        (lambda: nearest_solution(forward(np.ones(6)), np.ones(6), limits=np.ones(6)), "limits"),
        (
            lambda: nearest_solution(forward(np.ones(6)), np.ones(6), limits=[[1, -1]] * 6),
            "limits: joint 1 has lower",
        ),
        (lambda: inverse_path(forward(np.ones(6)), np.ones(6)), r"poses: expected shape \(n"),
        (lambda: inverse_path(forward(np.ones((2, 6))), np.ones((2, 6))), "q_start: expected"),
        (lambda: inverse_path(forward(np.ones((2, 6))), np.ones(6), max_step=0), "max_step"),
        (lambda: inverse_path(forward(np.ones((2, 6))), np.ones(6), tol=np.nan), "tol"),
        (lambda: singularity(np.ones(6), tol=-1.0), "tol: must be"),
    ],
)
def test_input_errors_name_the_argument(call, message):
    with pytest.raises((ValueError, TypeError), match=message):
        call()
