"""Quaternion math checked against pytransform3d, and the orientation columns of demos files."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.core import rotations as rot
from lfdkit.io import load_demos, save_demos

pr = pytest.importorskip("pytransform3d.rotations", reason="pip install pytransform3d")


def _wxyz(q):
    return np.r_[q[3], q[:3]]


def _random(n, seed):
    q = np.random.default_rng(seed).normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def test_products_maps_and_matrices_match_pytransform3d() -> None:
    a, b = _random(20, 0), _random(20, 1)
    for qa, qb, ab in zip(a, b, rot.multiply(a, b), strict=True):
        np.testing.assert_allclose(
            _wxyz(ab), pr.concatenate_quaternions(_wxyz(qa), _wxyz(qb)), atol=1e-14
        )
    R = rot.matrix_from_quaternion(a)
    for q, m in zip(a, R, strict=True):
        np.testing.assert_allclose(m, pr.matrix_from_quaternion(_wxyz(q)), atol=1e-14)
    back = rot.quaternion_from_matrix(R)
    assert np.all(back[:, 3] >= 0)
    np.testing.assert_allclose(np.abs(np.einsum("ij,ij->i", back, a)), 1.0, atol=1e-14)
    # rotations by pi (w = 0): the hard case of the trace formula
    flips = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0], [0, 0, 1.0, 0], [0.6, 0.8, 0, 0]])
    np.testing.assert_allclose(
        np.abs(
            np.einsum(
                "ij,ij->i", rot.quaternion_from_matrix(rot.matrix_from_quaternion(flips)), flips
            )
        ),
        1.0,
        atol=1e-14,
    )
    v = rot.log(a)
    np.testing.assert_allclose(np.abs(np.einsum("ij,ij->i", rot.exp(v), a)), 1.0, atol=1e-14)
    for q, lv in zip(a, v, strict=True):  # 2 log(q) is the rotation vector (compact axis-angle)
        np.testing.assert_allclose(
            rot.matrix_from_quaternion(q),
            pr.matrix_from_compact_axis_angle(2 * lv),
            atol=1e-12,
        )
    np.testing.assert_allclose(rot.log(np.array([0, 0, 0, 1.0])), 0.0)
    np.testing.assert_allclose(rot.exp(np.zeros(3)), [0, 0, 0, 1.0])


def test_slerp_and_distance_match_pytransform3d() -> None:
    a, b = _random(10, 2), _random(10, 3)
    for qa, qb in zip(a, b, strict=True):
        for t in (0.0, 0.3, 1.0):
            want = pr.quaternion_slerp(_wxyz(qa), _wxyz(qb), t, shortest_path=True)
            got = rot.slerp(qa, qb, t)
            assert min(np.abs(_wxyz(got) - want).max(), np.abs(_wxyz(got) + want).max()) < 1e-12
        assert abs(rot.angle_between(qa, qb) - pr.quaternion_dist(_wxyz(qa), _wxyz(qb))) < 1e-12


def test_heading_is_the_yaw_of_a_zyx_decomposition_and_nan_where_x_is_vertical() -> None:
    q = _random(50, 7)
    R = rot.matrix_from_quaternion(q)
    want = [pr.euler_from_matrix(m, 2, 1, 0, extrinsic=False)[0] for m in R]
    np.testing.assert_allclose(rot.heading(q), want, atol=1e-12)
    np.testing.assert_array_equal(rot.heading(-q), rot.heading(q))  # q and -q: one rotation
    angles = np.linspace(-3.1, 3.1, 9)  # about z alone: its own angle
    about_z = np.c_[np.zeros((9, 2)), np.sin(angles / 2), np.cos(angles / 2)]
    np.testing.assert_allclose(rot.heading(about_z), angles, atol=1e-14)
    assert rot.heading(about_z.reshape(3, 3, 4)).shape == (3, 3)
    pitched = np.array([0.0, np.sin(np.pi / 4), 0.0, np.cos(np.pi / 4)])  # x axis straight down
    assert np.isnan(rot.heading(pitched)) and rot.heading(pitched).shape == ()


def test_means_markley_and_robust() -> None:
    rng = np.random.default_rng(4)
    centre = _random(1, 5)[0]
    spread = rot.multiply(centre, rot.exp(rng.normal(0, 0.05, (30, 3))))
    signs = rng.choice([-1.0, 1.0], size=(30, 1))
    mean = rot.mean_quaternion(spread * signs)  # independent of the signs
    assert rot.angle_between(mean, rot.mean_quaternion(spread)) < 1e-12
    assert rot.angle_between(mean, centre) < 0.05
    # the Markley mean minimises the summed squared chordal distances (pytransform3d's matrices)
    mats = np.array([pr.matrix_from_quaternion(_wxyz(q)) for q in spread])

    def cost(q):
        return float(np.sum((pr.matrix_from_quaternion(_wxyz(q)) - mats) ** 2))

    nearby = rot.multiply(mean, rot.exp(rng.normal(0, 1e-3, (50, 3))))
    assert cost(mean) <= min(cost(q) for q in nearby)
    outliers = rot.multiply(centre, rot.exp(np.tile([1.2, 0.0, 0.0], (5, 1))))
    both = np.vstack((spread, outliers))
    plain = rot.mean_quaternion(both)
    robust, weights = rot.robust_mean_quaternion(both)
    assert rot.angle_between(plain, centre) > 0.1  # pulled towards the outliers
    assert rot.angle_between(robust, mean) < 1e-9  # the outliers get no weight
    assert np.all(weights[30:] == 0) and np.all(weights[:30] == 1)
    clean, w = rot.robust_mean_quaternion(spread)
    assert np.all(w == 1) and rot.angle_between(clean, mean) < 1e-12


def test_check_quaternions_normalises_and_refuses() -> None:
    q = rot.check_quaternions([[0, 0, 0, 1.0005]], "q")
    np.testing.assert_array_equal(q, [[0, 0, 0, 1.0]])
    with pytest.raises(ValueError, match=r"q: row 1 has norm 2; a unit quaternion"):
        rot.check_quaternions([[0, 0, 0, 1.0], [0, 0, 0, 2.0]], "q")
    with pytest.raises(ValueError, match="q: row 0 is not finite"):
        rot.check_quaternions([[np.nan, 0, 0, 1.0]], "q")
    with pytest.raises(ValueError, match=r"expected shape \(n, 4\)"):
        rot.check_quaternions([[0, 0, 1.0]], "q")


def test_orientation_columns_round_trip(tmp_path) -> None:
    demos = [np.random.default_rng(k).normal(size=(5 + k, 3)) for k in range(2)]
    quats = [_random(len(d), 10 + k) for k, d in enumerate(demos)]
    times = [np.arange(len(d)) * 0.1 for d in demos]
    path = save_demos(tmp_path / "d.csv", demos, times=times, orientations=quats)
    assert path.read_text().splitlines()[0] == "demo,t,x,y,z,qx,qy,qz,qw"
    got, got_q = load_demos(path, return_orientations=True)
    for a, b, qa, qb in zip(demos, got, quats, got_q, strict=True):
        np.testing.assert_array_equal(a, b)
        np.testing.assert_allclose(qa, qb, rtol=0, atol=1e-15)
    # files without the columns, and the old callers, are unchanged
    plain = save_demos(tmp_path / "p.csv", demos, times=times)
    assert load_demos(plain, return_orientations=True)[1] == [None, None]
    assert len(load_demos(path)) == 2
    for suffix in (".npz", ".json"):  # per demonstration there: one may have none
        f = save_demos(tmp_path / f"d{suffix}", demos, times=times, orientations=[None, quats[1]])
        back = load_demos(f, return_orientations=True)[1]
        assert back[0] is None
        np.testing.assert_allclose(back[1], quats[1], rtol=0, atol=1e-15)
    with pytest.raises(ValueError, match="all demonstrations or none"):
        save_demos(tmp_path / "some.csv", demos, orientations=[None, quats[1]])
    bad = [quats[0], quats[1] * 3.0]
    with pytest.raises(ValueError, match=r"orientations\[1\]: row 0 has norm 3"):
        save_demos(tmp_path / "bad.csv", demos, orientations=bad)


def test_bad_orientation_cells_name_the_line(tmp_path) -> None:
    f = tmp_path / "d.csv"
    f.write_text("demo,x,y,qx,qy,qz,qw\n0,0,0,0,0,0,1\n0,1,0,0,0,0,2\n")
    with pytest.raises(
        ValueError,
        match=r"d\.csv line 3, columns qx, qy, qz, qw: the "
        r"orientation of demo '0' has norm 2",
    ):
        load_demos(f, return_orientations=True)
    f.write_text("demo,x,y,qx,qy,qw\n0,0,0,0,0,1\n0,1,0,0,0,1\n")
    with pytest.raises(ValueError, match="need all of qx, qy, qz, qw; missing qz"):
        load_demos(f)
    f.write_text("demo,x,y,qx,qy,qz,qw\n0,0,0,0,0,0,nan\n0,1,0,0,0,0,1\n")
    with pytest.raises(ValueError, match="line 2"):
        load_demos(f)


def test_bad_orientations_in_npz_and_json(tmp_path) -> None:
    f = tmp_path / "d.npz"
    np.savez(f, demo_0=np.array([[0.0, 0], [1, 0], [2, 0]]), quat_0=np.ones((3, 4)))
    with pytest.raises(ValueError, match=r"array 'quat_0': row 0 has norm 2"):
        load_demos(f)
    np.savez(f, demo_0=np.array([[0.0, 0], [1, 0]]), quat_1=np.array([[0, 0, 0, 1.0]] * 2))
    with pytest.raises(ValueError, match="'quat_1' has no matching 'demo_1'"):
        load_demos(f)
    j = tmp_path / "d.json"
    j.write_text(
        '{"format": "lfdkit-demos", "version": 1, "n_dims": 2, "demos": '
        '[{"points": [[0, 0], [1, 0]], "q": [[0, 0, 0, 1]]}]}'
    )
    with pytest.raises(ValueError, match=r"demos\[0\] \(id 0\) field 'q': expected 2 quaternions"):
        load_demos(j)


def test_normalisation_neither_overflows_nor_underflows() -> None:
    from lfdkit.execute.poses import matrix_from_rotvec

    big = np.array([1e200, 0.0, 0.0, 1e200])
    assert rot.stable_norm(big) == pytest.approx(np.sqrt(2.0) * 1e200)
    assert rot.stable_norm(np.full(4, 1e-200)) == pytest.approx(2e-200)
    assert rot.stable_norm(np.zeros(4)) == 0.0
    with pytest.raises(ValueError, match=r"q: row 0 has norm 1.41421e\+200; a unit quaternion"):
        rot.check_quaternions(big, "q")
    # Huge angles: one line naming r, never NaN; big but resolvable angles give rotations.
    with pytest.raises(ValueError, match=r"r: a rotation vector of norm 1.73e\+300 rad; beyond"):
        matrix_from_rotvec([1e300, 1e300, 1e300])
    R = matrix_from_rotvec([1e8, 0.0, 0.0])
    assert np.allclose(R @ R.T, np.eye(3)) and np.isclose(np.linalg.det(R), 1.0)
    np.testing.assert_allclose(R, matrix_from_rotvec([np.mod(1e8, 2 * np.pi), 0, 0]), atol=1e-6)


def test_the_cli_normalises_a_huge_quaternion(capsys) -> None:
    from lfdkit.app.cli.common import _quaternion

    q = _quaternion("1e200,0,0,1e200", "--goal-orientation")
    np.testing.assert_allclose(q, [np.sqrt(0.5), 0.0, 0.0, np.sqrt(0.5)])
