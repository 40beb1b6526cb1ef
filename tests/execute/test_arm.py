"""Tests for lfdkit.execute.arm: the arm descriptions, and the UR10 as a second arm.

The description checks itself (every error names its field); the UR5 carries the
thesis's numbers; the kinematics of :mod:`lfdkit.execute.ur5` work for the UR10 from its
description alone: forward kinematics against DH matrices composed here by hand and
against MuJoCo's model of the same description, inverse/forward round trips on random
configurations, the Jacobian determinant's closed form. An arm without the UR
structure gets forward kinematics but no analytic inverse.
"""

from __future__ import annotations

import dataclasses
import pickle
from copy import deepcopy

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from lfdkit.execute import ur5
from lfdkit.execute.arm import UR5, UR10, Arm
from lfdkit.execute.mujoco import flange_poses
from tests.execute.arms import PLANAR

PI = np.pi


def dh_chain(arm: Arm, q: np.ndarray) -> np.ndarray:
    """Flange poses (n, 4, 4) as the product of Rz(θ) Tz(d) Tx(a) Rx(α), built here."""

    def rz(t):
        c, s = np.cos(t), np.sin(t)
        return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])

    def rx(t):
        c, s = np.cos(t), np.sin(t)
        return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])

    def trans(x, z):
        t = np.eye(4)
        t[0, 3], t[2, 3] = x, z
        return t

    out = np.empty((len(q), 4, 4))
    for k, qk in enumerate(q):
        t = np.eye(4)
        for i in range(arm.n_joints):
            t = t @ rz(qk[i]) @ trans(arm.a[i], arm.d[i]) @ rx(arm.alpha[i])
        out[k] = t
    return out


# ---------------------------------------------------------------- descriptions
def test_ur5_and_ur10_descriptions():
    assert (UR5.name, UR5.n_joints, UR10.name, UR10.n_joints) == ("UR5", 6, "UR10", 6)
    np.testing.assert_array_equal(UR10.d, [0.1273, 0, 0, 0.163941, 0.1157, 0.0922])
    np.testing.assert_array_equal(UR10.a, [0, -0.612, -0.5723, 0, 0, 0])
    np.testing.assert_allclose(UR10.alpha, [PI / 2, 0, 0, PI / 2, -PI / 2, 0])
    np.testing.assert_array_equal(UR10.link_masses, [7.1, 12.7, 4.27, 2.0, 2.0, 0.365])
    np.testing.assert_allclose(UR10.max_joint_speed, np.radians([120, 120, 180, 180, 180, 180]))
    np.testing.assert_allclose(UR10.joint_limits, [[-2 * PI, 2 * PI]] * 6)
    np.testing.assert_array_equal(UR5.max_joint_speed, [3.2] * 6)  # a number is repeated
    assert UR5.ur_type and UR10.ur_type and not PLANAR.ur_type
    # Exact zeros where the twist is a multiple of π/2.
    np.testing.assert_array_equal(UR10.cos_alpha, [0, 1, 1, 0, 0, 1])
    np.testing.assert_array_equal(UR10.sin_alpha, [1, 0, 0, 1, -1, 0])
    assert repr(UR10) == "Arm('UR10', 6 joints)"


def test_descriptions_are_immutable():
    with pytest.raises(dataclasses.FrozenInstanceError):
        UR5.name = "UR3"  # type: ignore[misc]
    for name in ("d", "joint_limits", "max_joint_speed", "link_masses", "kp"):
        with pytest.raises(ValueError, match="read-only"):
            getattr(UR5, name)[0] = 1.0
    # Inputs are copied: changing the caller's array later changes nothing.
    d = np.array(PLANAR.d)
    arm = dataclasses.replace(PLANAR, d=d)
    d[0] = 5.0
    assert arm.d[0] == 0.1


def test_pickled_and_copied_arms_stay_read_only():
    for copy in (pickle.loads(pickle.dumps(UR10)), deepcopy(UR10)):
        assert copy is not UR10 and repr(copy) == repr(UR10) and copy.ur_type
        np.testing.assert_array_equal(copy.max_joint_speed, UR10.max_joint_speed)
        with pytest.raises(ValueError, match="read-only"):
            copy.kp[0] = 1.0


def test_replace_makes_a_checked_variant():
    slow = dataclasses.replace(UR5, name="UR5 slow", max_joint_speed=1.0)
    np.testing.assert_array_equal(slow.max_joint_speed, [1.0] * 6)
    assert slow.ur_type
    np.testing.assert_array_equal(slow.d, UR5.d)


@pytest.mark.parametrize(
    ("changes", "error", "message"),
    [
        ({"name": " "}, ValueError, r"Arm\.name: must not be empty"),
        ({"name": 5}, TypeError, r"Arm\.name: expected a str"),
        ({"d": []}, ValueError, r"Arm\.d: expected one value per joint"),
        ({"d": [[0.1, 0.2, 0.3]]}, ValueError, r"Arm\.d"),
        ({"d": "abc"}, TypeError, r"Arm\.d: expected numbers"),
        ({"a": (0.3, 0.25)}, ValueError, r"Arm\.a: expected one value per joint \(3 joints\)"),
        ({"alpha": (0.0, np.nan, 0.0)}, ValueError, r"Arm\.alpha: must be finite.* joint 2"),
        ({"d": (0.1, np.inf, 0.0)}, ValueError, r"Arm\.d: must be finite"),
        ({"joint_limits": [[-1, 1]] * 2}, ValueError, r"Arm\.joint_limits: expected .*\(3, 2\)"),
        ({"joint_limits": [[-1, 1], [1, -1], [0, 1]]}, ValueError, r"joint 2 has lower"),
        ({"joint_limits": [[-1, 1], [0, 0], [0, 1]]}, ValueError, r"Arm\.joint_limits: joint 2"),
        ({"joint_limits": [[-np.inf, 1]] * 3}, ValueError, r"Arm\.joint_limits: contains NaN"),
        ({"max_joint_speed": 0.0}, ValueError, r"Arm\.max_joint_speed: must be finite and > 0"),
        ({"max_joint_speed": (1, -2, 3)}, ValueError, r"max_joint_speed: .*-2.0 for joint 2"),
        ({"max_joint_speed": (1, 2)}, ValueError, r"Arm\.max_joint_speed: expected a number"),
        ({"max_joint_acceleration": np.nan}, ValueError, r"Arm\.max_joint_acceleration"),
        ({"link_masses": (1, 0, 1)}, ValueError, r"Arm\.link_masses: must be finite and > 0"),
        ({"link_masses": 1.0}, ValueError, r"Arm\.link_masses: expected one value per joint"),
        ({"link_radii": (0.1, 0.1, -0.1)}, ValueError, r"Arm\.link_radii: .* joint 3"),
        ({"kp": (1, 1, np.inf)}, ValueError, r"Arm\.kp"),
        ({"kv": (1, 1)}, ValueError, r"Arm\.kv"),
        ({"kv": [None, 1, 1]}, ValueError, r"Arm\.kv"),  # None reads as NaN
    ],
)
def test_arm_errors_name_the_field(changes, error, message):
    with pytest.raises(error, match=message):
        dataclasses.replace(PLANAR, **changes)


def test_ur_type_needs_the_whole_structure():
    assert not dataclasses.replace(UR10, a=(0.01, -0.612, -0.5723, 0, 0, 0)).ur_type
    assert not dataclasses.replace(UR10, d=(0.1273, 0.05, 0, 0.163941, 0.1157, 0.0922)).ur_type
    assert not dataclasses.replace(UR10, alpha=(PI / 2, 0, 0, PI / 2, PI / 2, 0)).ur_type
    assert not dataclasses.replace(UR10, d=(0.1273, 0, 0, 0.0, 0.1157, 0.0922)).ur_type
    assert not dataclasses.replace(UR10, a=(0, -0.612, 0.0, 0, 0, 0)).ur_type


# ---------------------------------------------------------------- kinematics of any arm
def test_forward_of_a_planar_arm_and_no_analytic_inverse():
    q = np.random.default_rng(3).uniform(-PI, PI, (50, 3))
    t = ur5.forward(q, arm=PLANAR)
    phi = np.cumsum(q, axis=1)
    x = (PLANAR.a * np.cos(phi)).sum(axis=1)
    y = (PLANAR.a * np.sin(phi)).sum(axis=1)
    np.testing.assert_allclose(t[:, :3, 3], np.column_stack((x, y, np.full(50, 0.1))), atol=1e-15)
    assert ur5.link_frames(q[0], arm=PLANAR).shape == (4, 4, 4)
    assert ur5.jacobian(q, arm=PLANAR).shape == (50, 6, 3)
    np.testing.assert_allclose(t, dh_chain(PLANAR, q), atol=1e-15)
    with pytest.raises(ValueError, match=r"q: expected shape \(3,\) or \(n, 3\)"):
        ur5.forward(np.zeros(6), arm=PLANAR)
    with pytest.raises(ValueError, match="arm: the analytic inverse kinematics needs a UR-type"):
        ur5.inverse(t[0], arm=PLANAR)
    with pytest.raises(ValueError, match="planar 3R is not one"):
        ur5.singularity(q[0], arm=PLANAR)
    with pytest.raises(TypeError, match="arm: expected an Arm"):
        ur5.forward(np.zeros(6), arm="UR10")


# ---------------------------------------------------------------- the UR10
def test_ur10_forward_against_hand_composed_dh_matrices_and_mujoco():
    q = np.random.default_rng(0).uniform(-2 * PI, 2 * PI, (300, 6))
    t = ur5.forward(q, arm=UR10)
    np.testing.assert_allclose(t, dh_chain(UR10, q), rtol=0, atol=1e-14)
    np.testing.assert_allclose(flange_poses(q, arm=UR10), t, rtol=0, atol=1e-12)
    # Zero pose by hand: a2 + a3 along x, d4 + d6 along -y, d1 - d5 up.
    np.testing.assert_allclose(
        ur5.forward(np.zeros(6), arm=UR10)[:3, 3], [-1.1843, -0.256141, 0.0116], atol=1e-15
    )
    # A different arm gives a different pose.
    assert np.abs(ur5.forward(q, arm=UR5) - t).max() > 0.1


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-PI, PI), min_size=6, max_size=6))
def test_ur10_inverse_forward_round_trip(angles):
    q = np.array(angles)
    # As for the UR5: at a wrist singularity q6 is set to a hint, which on a stretched
    # elbow can leave no branch; the round trip is a property of regular poses.
    assume(not ur5.singularity(q, tol=1e-3, arm=UR10).any)
    pose = ur5.forward(q, arm=UR10)
    sols = ur5.inverse(pose, arm=UR10)
    valid = sols[~np.isnan(sols).any(axis=1)]
    fk = ur5.forward(valid, arm=UR10)
    np.testing.assert_allclose(fk, np.broadcast_to(pose, fk.shape), rtol=0, atol=1e-9)
    back = sols[ur5.branch(q, arm=UR10)]
    assert np.abs(np.angle(np.exp(1j * (back - q)))).max() < 1e-8


def test_ur10_round_trip_on_a_random_batch():
    q = np.random.default_rng(1).uniform(-PI, PI, (2000, 6))
    poses = ur5.forward(q, arm=UR10)
    sols = ur5.inverse(poses, arm=UR10, strict=False)
    ok = ~np.isnan(sols).any(axis=-1)  # (2000, 8)
    assert ok.any(axis=1).all()
    fk = ur5.forward(sols[ok], arm=UR10)
    np.testing.assert_allclose(fk, poses[np.nonzero(ok)[0]], rtol=0, atol=1e-9)
    back = sols[np.arange(len(q)), ur5.branch(q, arm=UR10)]
    assert np.abs(np.angle(np.exp(1j * (back - q)))).max() < 1e-6


def test_ur10_jacobian_determinant_has_the_closed_form():
    q = np.random.default_rng(2).uniform(-PI, PI, (200, 6))
    d5, a2, a3 = UR10.d[4], UR10.a[1], UR10.a[2]
    x = a2 * np.cos(q[:, 1]) + a3 * np.cos(q[:, 1] + q[:, 2]) + d5 * np.sin(q[:, 1:4].sum(1))
    expected = a2 * a3 * np.sin(q[:, 2]) * np.sin(q[:, 4]) * x
    np.testing.assert_allclose(
        np.abs(np.linalg.det(ur5.jacobian(q, arm=UR10))), np.abs(expected), atol=1e-12
    )


def test_ur10_reaches_where_the_ur5_cannot():
    """A tool-down line 0.95 m out: beyond the UR5's elbow span, inside the UR10's."""
    n = 41
    poses = np.tile(np.eye(4), (n, 1, 1))
    poses[:, :3, :3] = np.diag([1.0, -1.0, -1.0])
    poses[:, :3, 3] = np.column_stack(
        (np.linspace(-0.2, 0.2, n), np.full(n, 0.95), np.full(n, 0.2))
    )
    with pytest.raises(ur5.UnreachableError, match="too far"):
        ur5.inverse(poses[0], arm=UR5)
    q_home = np.array([PI / 2, -0.6, 1.0, -1.97, -PI / 2, 0.0])
    start = ur5.nearest_solution(poses[0], q_home, arm=UR10)
    path = ur5.inverse_path(poses, start, arm=UR10)
    np.testing.assert_allclose(ur5.forward(path, arm=UR10), poses, atol=1e-9)
    assert np.abs(np.diff(path, axis=0)).max() < 0.1
    limits = UR10.joint_limits
    assert np.all((path >= limits[:, 0]) & (path <= limits[:, 1]))
