"""The orientation DMP: reproduces, reaches a new goal orientation exactly, stays unit."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.core import rotations as rot
from lfdkit.imitate.orientation_dmp import QuaternionDMP


def _demo(amplitude: float = 0.25, n: int = 200, duration: float = 2.0):
    """A rest-to-rest turn about a changing axis (minimum-jerk in the phase)."""
    t = np.linspace(0.0, duration, n)
    u = t / duration
    w = 2.0 * (10 * u**3 - 15 * u**4 + 6 * u**5)
    v = amplitude * np.c_[np.sin(w), np.cos(2 * w), 0.5 + 0 * w] * w[:, None]
    q = rot.multiply(rot.exp(v), rot.exp(np.array([0.1, 0.2, -0.3])))
    return t, q


def test_reproduces_and_reaches_new_goals_exactly() -> None:
    t, q = _demo()
    dmp = QuaternionDMP().fit(q * np.where(np.arange(len(q)) % 7 == 3, -1.0, 1.0)[:, None], t)
    run = dmp.rollout()
    times, r = run.times, run.orientations
    np.testing.assert_allclose(times, t, atol=1e-12)
    assert rot.angle_between(r, q).max() < 0.01  # the basis tolerance: 1 % of the extent
    assert rot.angle_between(r[-1], q[-1]) < 1e-9
    rng = np.random.default_rng(0)
    for _ in range(5):
        start = rot.multiply(rot.exp(rng.normal(0, 0.2, 3)), q[0])
        goal = rot.multiply(rot.exp(rng.normal(0, 0.4, 3)), q[-1])
        run = dmp.rollout(start=start, goal=goal, tau=1.5, n_steps=120)
        times, r = run.times, run.orientations
        assert len(r) == 120 and abs(times[-1] - 1.5 * t[-1]) < 1e-9
        assert rot.angle_between(r[0], start) < 1e-9
        assert rot.angle_between(r[-1], goal) < 1e-9  # exactly, not approximately
        np.testing.assert_allclose(np.linalg.norm(r, axis=1), 1.0, atol=1e-14)
        assert np.all(np.einsum("ij,ij->i", r[1:], r[:-1]) > 0)  # continuous signs


def test_a_common_body_rotation_carries_the_whole_movement() -> None:
    """start·h and goal·h: the rollout is the reproduction·h, exactly (goal frame)."""
    t, q = _demo()
    dmp = QuaternionDMP().fit(q, t)
    rep = dmp.rollout().orientations
    h = rot.exp(np.array([0.4, -0.9, 0.3]))
    moved = dmp.rollout(start=rot.multiply(q[0], h), goal=rot.multiply(q[-1], h)).orientations
    assert rot.angle_between(moved, rot.multiply(rep, h)).max() < 1e-9


def test_matches_movement_primitives_on_the_reproduction() -> None:
    mp = pytest.importorskip("movement_primitives.dmp", reason="pip install movement_primitives")
    t, q = _demo()
    wxyz = q[:, [3, 0, 1, 2]]
    theirs = mp.CartesianDMP(execution_time=t[-1], dt=t[1] - t[0], n_weights_per_dim=30)
    theirs.imitate(t, np.hstack([np.zeros((len(t), 3)), wxyz]))
    theirs.configure(start_y=np.r_[0, 0, 0, wxyz[0]], goal_y=np.r_[0, 0, 0, wxyz[-1]])
    _, y = theirs.open_loop()
    their_q = y[:, [4, 5, 6, 3]]
    ours = QuaternionDMP().fit(q, t).rollout(n_steps=len(their_q)).orientations
    assert rot.angle_between(their_q, q[: len(their_q)]).max() < 0.01
    assert rot.angle_between(ours, their_q).max() < 0.01
    # theirs converges to the goal; ours ends on it
    assert rot.angle_between(ours[-1], q[-1]) <= rot.angle_between(their_q[-1], q[-1])


def test_bad_input() -> None:
    t, q = _demo()
    with pytest.raises(ValueError, match="row 3 has norm 2"):
        QuaternionDMP().fit(np.vstack([q[:3], 2 * q[3:4], q[4:]]), t)
    _, far = _demo(amplitude=0.9)  # turns more than π away from its goal
    with pytest.raises(ValueError, match="π or more away from the goal"):
        QuaternionDMP().fit(far, t)
    with pytest.raises(ValueError, match="call fit before rollout"):
        QuaternionDMP().rollout()
