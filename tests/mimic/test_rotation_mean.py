"""The mean orientation along a generalized path: known answers, robustness, pytransform3d."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.core import rotations as rot
from lfdkit.core.geometry import point_tangents
from lfdkit.mimic.rotation_mean import mean_orientations

pr = pytest.importorskip("pytransform3d.rotations", reason="pip install pytransform3d")


def _truth(u: np.ndarray) -> np.ndarray:
    """The orientation the task asks for at path parameter u in [0, 1]."""
    return rot.multiply(rot.exp(np.c_[0.3 * u, -0.2 * u, 0.8 * u]), rot.exp([0.0, 0.9, 0.0]))


def _demos(n_demos: int = 6, noise: float = 0.02, seed: int = 0):
    rng = np.random.default_rng(seed)
    demos, quats = [], []
    for j in range(n_demos):
        n = 80 + 7 * j
        u = np.linspace(0, 1, n)
        offset = 0.01 * (j - n_demos / 2)
        demos.append(np.c_[u, 0.3 * np.sin(np.pi * u) + offset, 0.1 * u])
        q = rot.multiply(_truth(u), rot.exp(rng.normal(0, noise, (n, 3))))
        quats.append(q * rng.choice([-1.0, 1.0], (n, 1)))  # signs as a recorder may give them
    u = np.linspace(0, 1, 50)
    return np.c_[u, 0.3 * np.sin(np.pi * u), 0.1 * u], demos, quats


def test_the_mean_follows_the_demonstrated_orientation() -> None:
    path, demos, quats = _demos()
    res = mean_orientations(path, demos, quats)
    err = rot.angle_between(res.orientations, _truth(np.linspace(0, 1, 50)))
    # noise ~0.07 rad per sample (0.02 per axis of θ/2), six demonstrations: ~0.03 at a point
    assert err.max() < 0.06 and err.mean() < 0.03
    np.testing.assert_allclose(np.linalg.norm(res.orientations, axis=1), 1.0, atol=1e-14)
    assert np.all(np.einsum("ij,ij->i", res.orientations[1:], res.orientations[:-1]) > 0)
    assert res.crossed[1:-1].all() and np.all(res.weights > 0)


def test_a_demonstration_reversed_or_held_wrong_is_handled() -> None:
    path, demos, quats = _demos(noise=0.005)
    demos[1], quats[1] = demos[1][::-1], quats[1][::-1]  # recorded the other way round
    quats[2] = rot.multiply(quats[2], rot.exp([1.2, 0.0, 0.0]))  # tool held wrongly
    with pytest.warns(UserWarning, match="reversed"):
        robust = mean_orientations(path, demos, quats)
    with pytest.warns(UserWarning, match="reversed"):
        plain = mean_orientations(path, demos, quats, robust=False)
    truth = _truth(np.linspace(0, 1, 50))
    assert rot.angle_between(robust.orientations, truth).max() < 0.03
    assert rot.angle_between(plain.orientations, truth).min() > 0.1  # pulled (2.4 rad, 1 of 6)
    assert np.all(robust.weights[:, 2] == 0) and np.all(robust.weights[:, [0, 1, 3, 4, 5]] == 1)


def test_the_orientation_at_a_crossing_is_pytransform3ds_slerp() -> None:
    path, demos, quats = _demos(n_demos=3, noise=0.05)
    res = mean_orientations(path, demos, quats)
    demo, q = demos[1], rot.continuous(quats[1])
    for i in (10, 25, 40):
        # the crossing of the normal at path[i] with the demo, by brute force
        t = point_tangents(path)[i]
        side = (demo - path[i]) @ t
        k = int(np.flatnonzero(np.diff(np.sign(side)) != 0)[0])
        f = side[k] / (side[k] - side[k + 1])
        want = pr.quaternion_slerp(q[k, [3, 0, 1, 2]], q[k + 1, [3, 0, 1, 2]], f)
        got = res.samples[i, 1]
        assert (
            min(np.abs(got[[3, 0, 1, 2]] - want).max(), np.abs(got[[3, 0, 1, 2]] + want).max())
            < 1e-6
        )


def test_bad_input() -> None:
    path, demos, quats = _demos(n_demos=3)
    with pytest.raises(ValueError, match="one array per demonstration"):
        mean_orientations(path, demos, quats[:2])
    with pytest.raises(ValueError, match=r"orientations\[0\]: expected 80 quaternions"):
        mean_orientations(path, demos, [quats[0][:-1], *quats[1:]])
