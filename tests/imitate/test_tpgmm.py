"""Tests of the task-parameterised GMM/GMR (lfdkit.imitate.tpgmm) against known answers."""

from __future__ import annotations

import functools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lfdkit.core.rotations import matrix_from_quaternion
from lfdkit.imitate import TPGMM, TaskFrame, gaussian_product
from lfdkit.mimic import GMR
from lfdkit.model.demos import Demo


def _rotation(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s], [s, c]])


def _gaussian_log_density(x: np.ndarray, mean: np.ndarray, cov: np.ndarray) -> np.ndarray:
    diff = x - mean
    maha = np.einsum("ni,ij,nj->n", diff, np.linalg.inv(cov), diff)
    return -0.5 * (maha + np.linalg.slogdet(2 * np.pi * cov)[1])


# ------------------------------------------------------------ gaussian_product
def test_gaussian_product_1d_closed_form():
    mean, cov = gaussian_product([[1.0], [4.0]], [[[2.0]], [[0.5]]])
    # mu = (mu1 s2 + mu2 s1) / (s1 + s2), s = s1 s2 / (s1 + s2)
    assert mean[0] == pytest.approx((1.0 * 0.5 + 4.0 * 2.0) / 2.5)
    assert cov[0, 0] == pytest.approx(2.0 * 0.5 / 2.5)


def test_gaussian_product_is_the_product_of_densities_up_to_a_constant():
    rng = np.random.default_rng(3)
    means = rng.normal(size=(3, 2))
    factors = rng.normal(size=(3, 2, 2))
    covs = factors @ np.swapaxes(factors, 1, 2) + 0.1 * np.eye(2)
    mean, cov = gaussian_product(means, covs)
    x = rng.normal(size=(50, 2)) * 3
    product = sum(_gaussian_log_density(x, m, c) for m, c in zip(means, covs, strict=True))
    gap = product - _gaussian_log_density(x, mean, cov)
    np.testing.assert_allclose(gap, gap[0], atol=1e-9)
    np.testing.assert_array_equal(cov, cov.T)


def test_gaussian_product_batches_and_refuses_bad_covariances():
    means = np.zeros((4, 2, 3))
    covs = np.broadcast_to(np.eye(3), (4, 2, 3, 3))
    mean, cov = gaussian_product(means, covs)
    assert mean.shape == (4, 3) and cov.shape == (4, 3, 3)
    np.testing.assert_allclose(cov, np.broadcast_to(0.5 * np.eye(3), (4, 3, 3)))
    with pytest.raises(ValueError, match=r"^covariances: a covariance is not positive definite"):
        gaussian_product(np.zeros((2, 2)), np.zeros((2, 2, 2)))
    with pytest.raises(ValueError, match=r"^covariances: expected shape \(2, 2, 2\)"):
        gaussian_product(np.zeros((2, 2)), np.zeros((2, 3, 3)))


# ------------------------------------------------------------ data with known answers
def _local_shape(t: np.ndarray) -> np.ndarray:
    """A hook, in millimetres: the approach to an object along its -x axis, then up."""
    return np.column_stack((-80.0 * (1 - t) ** 2, 25.0 * np.sin(np.pi * t) * (1 - t)))


def _object_task(n_demos: int, seed: int, noise: float = 0.3):
    """Demonstrations that are one fixed shape in the object's frame; the start frame varies."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, 70)
    demos, frames = [], []
    for _ in range(n_demos):
        start = TaskFrame.from_angle(rng.uniform(-200, 200, 2), rng.uniform(-np.pi, np.pi))
        goal = TaskFrame.from_angle(rng.uniform(-200, 200, 2), rng.uniform(-np.pi, np.pi))
        demos.append(goal.to_world(_local_shape(t)) + noise * rng.normal(size=(len(t), 2)))
        frames.append([start, goal])
    return demos, frames


@functools.cache
def _fitted(product: str) -> TPGMM:
    demos, frames = _object_task(6, seed=0)
    return TPGMM(n_components=10, product=product, length_scale=100.0).fit(demos, frames)


@pytest.mark.parametrize("product", ["paths", "components"])
def test_a_shape_fixed_in_one_frame_is_reproduced_in_a_new_pose_of_it(product):
    model = _fitted(product)
    goal = TaskFrame.from_angle([500.0, -300.0], 2.5)  # far from every training pose
    start = TaskFrame.from_angle([-900.0, 40.0], -1.0)
    t = np.linspace(0.0, 1.0, 41)
    path = model.predict(t, [start, goal])
    error = np.linalg.norm(path - goal.to_world(_local_shape(t)), axis=1)
    # mm, on a hook 80 mm long recorded with 0.3 mm noise; the start frame alone
    # would put it hundreds of mm away
    assert error.max() < 1.5
    assert np.sqrt(np.mean(error**2)) < 0.6


def _leave_and_arrive(start: TaskFrame, goal: TaskFrame, n: int = 60) -> np.ndarray:
    """Leave the start along its x axis, arrive along the goal frame's x axis (metres)."""
    t = np.linspace(0.0, 1.0, n)[:, None]
    blend = t * t * (3 - 2 * t)
    leave = start.to_world(np.column_stack((0.4 * t, 0 * t)))
    arrive = goal.to_world(np.column_stack((-0.4 * (1 - t), 0 * t)))
    return (1 - blend) * leave + blend * arrive


def _start_goal_task(n_demos: int, seed: int):
    rng = np.random.default_rng(seed)
    demos, frames = [], []
    for _ in range(n_demos):
        start = TaskFrame.from_angle(rng.normal(0, 0.1, 2), rng.uniform(-0.4, 0.4))
        goal = TaskFrame.from_angle(
            np.array([0.6, 0.0]) + rng.normal(0, 0.15, 2), rng.uniform(-1, 1)
        )
        demos.append(_leave_and_arrive(start, goal) + rng.normal(0, 1e-3, (60, 2)))
        frames.append([start, goal])
    return demos, frames


@pytest.mark.parametrize("goal_angle", [0.0, 1.4])  # 1.4: beyond the demonstrated ±1 rad
def test_start_and_goal_frames_give_the_new_start_goal_and_approach_direction(goal_angle):
    demos, frames = _start_goal_task(8, seed=1)
    model = TPGMM().fit(demos, frames)
    start = TaskFrame.from_angle([0.1, -0.2], 0.3)
    goal = TaskFrame.from_angle([0.5, 0.35], goal_angle)
    path = model.path([start, goal], 200)
    # metres, on a path about 0.6 m long
    assert np.linalg.norm(path[0] - start.origin) < 5e-3
    assert np.linalg.norm(path[-1] - goal.origin) < 5e-3
    arrival = path[-1] - path[-20]
    # Turns with the goal frame (a goal point alone would keep the demonstrations' mean
    # approach, about 0 rad); GMR's piecewise-linear ends cost up to 0.3 rad here.
    assert abs(np.arctan2(arrival[1], arrival[0]) - goal_angle) < 0.35
    departure = path[19] - path[0]
    assert abs(np.arctan2(departure[1], departure[0]) - 0.3) < 0.1
    error = np.linalg.norm(path - _leave_and_arrive(start, goal, 200), axis=1)
    # The product of the frames is not the generator's blend: 5-8 cm RMS at 10 components.
    assert np.sqrt(np.mean(error**2)) < 0.08


def _conditional(mean: np.ndarray, cov: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
    """The Gaussian of x given the phase t, of a Gaussian over (t, x)."""
    gain = cov[1:, 0] / cov[0, 0]
    return mean[1:] + gain * (t - mean[0]), cov[1:, 1:] - np.outer(gain, cov[0, 1:])


def test_each_component_is_the_product_of_its_frames_given_the_phase():
    model = _fitted("components")
    frames = [TaskFrame.from_angle([10.0, 20.0], 0.5), TaskFrame.from_angle([-40.0, 5.0], 2.0)]
    weights, means, covs = model.mixture(frames)
    np.testing.assert_array_equal(weights, model.weights_)
    np.testing.assert_allclose(means[:, 0], model.means_[:, 0, 0])  # the shared phase
    np.testing.assert_allclose(covs[:, 0, 0], model.covariances_[:, 0, 0, 0])
    for k in range(len(weights)):
        for t in (0.0, model.means_[k, 0, 0], 0.9):
            local = [_conditional(model.means_[k, j], model.covariances_[k, j], t) for j in (0, 1)]
            world_means = [f.to_world(m[None])[0] for f, (m, _) in zip(frames, local, strict=True)]
            world_covs = [
                f.matrix @ c @ f.matrix.T for f, (_, c) in zip(frames, local, strict=True)
            ]
            expected = gaussian_product(world_means, world_covs)
            got = _conditional(means[k], covs[k], t)
            np.testing.assert_allclose(got[0], expected[0], atol=1e-8)
            np.testing.assert_allclose(got[1], expected[1], rtol=1e-7, atol=1e-12)


# ------------------------------------------------------------ reductions and invariance
def _noisy_sine(seed: int = 0):
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, 60)
    return [
        np.column_stack((t, np.sin(3 * t) + 0.05 * rng.normal())) + 0.01 * rng.normal(size=(60, 2))
        for _ in range(5)
    ]


@pytest.mark.parametrize("product", ["paths", "components"])
def test_one_identity_frame_reduces_to_gmr(product):
    demos = _noisy_sine()
    identity = (np.eye(2), np.zeros(2))
    model = TPGMM(n_components=5, random_state=0, em="joint", init="kmeans", product=product)
    model.fit(demos, [[identity]] * len(demos))
    gmr = GMR(n_components=5, random_state=0, cov_mode="law_of_total_covariance").fit(demos)
    t = np.linspace(0.0, 1.0, 30)
    mean, cov = model.predict(t, [identity], return_cov=True)
    expected_mean, expected_cov = gmr.predict(t, return_cov=True)
    np.testing.assert_allclose(mean, expected_mean, atol=1e-10)
    np.testing.assert_allclose(cov, expected_cov, atol=1e-12)


def test_one_frame_carries_the_gmr_path_rigidly():
    local = _noisy_sine(1)
    rng = np.random.default_rng(2)
    frames = [TaskFrame.from_angle(rng.normal(size=2), rng.uniform(-3, 3)) for _ in local]
    demos = [f.to_world(d) for f, d in zip(frames, local, strict=True)]
    model = TPGMM(n_components=4, random_state=0, em="joint", init="kmeans")
    model.fit(demos, [[f] for f in frames])
    gmr = GMR(n_components=4, random_state=0, cov_mode="law_of_total_covariance").fit(local)
    new = TaskFrame.from_angle([3.0, -1.0], 0.7)
    t = np.linspace(0.0, 1.0, 25)
    np.testing.assert_allclose(model.predict(t, [new]), new.to_world(gmr.predict(t)), atol=1e-9)


@settings(max_examples=25, deadline=None)
@given(
    angle=st.floats(-np.pi, np.pi),
    shift=st.tuples(st.floats(-1e3, 1e3), st.floats(-1e3, 1e3)),
    scale=st.floats(0.1, 10.0),
    product=st.sampled_from(["paths", "components"]),
)
def test_moving_every_frame_by_one_map_moves_the_path_by_it(angle, shift, scale, product):
    model = _fitted(product)
    frames = [TaskFrame.from_angle([-100.0, 20.0], 0.3), TaskFrame.from_angle([50.0, 80.0], -2.0)]
    moved_by = scale * _rotation(angle)
    moved = [TaskFrame(moved_by @ f.matrix, moved_by @ f.origin + shift) for f in frames]
    t = np.linspace(0.0, 1.0, 15)
    mean, cov = model.predict(t, frames, return_cov=True)
    moved_mean, moved_cov = model.predict(t, moved, return_cov=True)
    np.testing.assert_allclose(moved_mean, mean @ moved_by.T + shift, atol=1e-6 * (1 + scale))
    np.testing.assert_allclose(
        moved_cov, moved_by @ cov @ moved_by.T, atol=1e-8 * scale**2 * np.abs(cov).max()
    )


def test_moving_the_recorded_world_changes_nothing_learned():
    demos, frames = _object_task(5, seed=4)
    rotation, shift = _rotation(1.1), np.array([300.0, -50.0])
    moved_demos = [d @ rotation.T + shift for d in demos]
    moved_frames = [
        [TaskFrame(rotation @ f.matrix, rotation @ f.origin + shift) for f in pair]
        for pair in frames
    ]
    a = TPGMM(n_components=4, random_state=0).fit(demos, frames)
    b = TPGMM(n_components=4, random_state=0).fit(moved_demos, moved_frames)
    np.testing.assert_allclose(b.means_, a.means_, atol=1e-8)
    np.testing.assert_allclose(b.covariances_, a.covariances_, atol=1e-8)


def test_three_dimensional_frames_from_poses():
    rng = np.random.default_rng(5)
    t = np.linspace(0.0, 1.0, 40)
    local = np.column_stack((-0.2 * (1 - t), 0.05 * np.sin(np.pi * t), 0.1 * (1 - t) ** 2))
    demos, frames = [], []
    for _ in range(5):
        q = rng.normal(size=4)
        frame = TaskFrame.from_pose(rng.normal(size=3), q / np.linalg.norm(q))
        demos.append(frame.to_world(local) + 1e-4 * rng.normal(size=local.shape))
        frames.append([frame])
    model = TPGMM().fit(demos, frames)
    q = np.array([0.2, -0.5, 0.1, 0.8])
    q /= np.linalg.norm(q)
    new = TaskFrame.from_pose([1.0, 2.0, 3.0], q)
    np.testing.assert_allclose(new.matrix, matrix_from_quaternion(q))
    path = model.predict(t, [new])
    assert np.abs(path - new.to_world(local)).max() < 2e-3


# ------------------------------------------------------------ inputs
def test_demo_records_bring_their_times():
    demos = _noisy_sine(2)
    times = [np.sort(np.random.default_rng(j).uniform(0, 5, len(d))) for j, d in enumerate(demos)]
    frames = [[(np.eye(2), np.zeros(2))]] * len(demos)
    records = [Demo(points=d, times=tj) for d, tj in zip(demos, times, strict=True)]
    a = TPGMM(n_components=3, random_state=0).fit(records, frames)
    b = TPGMM(n_components=3, random_state=0).fit(demos, frames, times=times)
    np.testing.assert_array_equal(a.means_, b.means_)
    c = TPGMM(n_components=3, random_state=0).fit(demos, frames)
    assert not np.allclose(a.means_, c.means_)  # the times changed the phases


def test_frames_recorded_in_a_demonstrations_file_fit_the_same_model(tmp_path):
    # The object's pose written as frame_<name>_x, _y, _angle columns: the records read
    # back carry the frames, and the model is the one fitted on the frames themselves.
    from lfdkit.io import load_demos, save_demos

    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 1.0, 70)
    demos, poses, frames = [], [], []
    for _ in range(6):
        pose = {"start": np.r_[rng.uniform(-200, 200, 2), rng.uniform(-3, 3)]}
        pose["object"] = np.r_[rng.uniform(-200, 200, 2), rng.uniform(-3, 3)]
        goal = TaskFrame.from_vector(pose["object"])
        demos.append(goal.to_world(_local_shape(t)) + 0.3 * rng.normal(size=(len(t), 2)))
        poses.append(pose)
        frames.append([TaskFrame.from_vector(pose["start"]), goal])
    path = save_demos(tmp_path / "hooks.csv", demos, frames=poses)
    records = load_demos(path, as_records=True)
    model = TPGMM(n_components=8, length_scale=100.0, random_state=0)
    from_file = model.fit(records)
    assert from_file.frame_names_ == ["start", "object"]
    given = TPGMM(n_components=8, length_scale=100.0, random_state=0).fit(demos, frames)
    np.testing.assert_array_equal(from_file.means_, given.means_)
    assert given.frame_names_ is None
    with pytest.raises(ValueError, match=r"^frames: the Demo records carry their own task"):
        TPGMM(n_components=8).fit(records, frames)
    with pytest.raises(ValueError, match=r"^frames: give one list of task frames per demo"):
        TPGMM(n_components=8).fit(demos)
    renamed = [records[0], Demo(records[1].points, frames={"lid": poses[1]["object"]})]
    with pytest.raises(ValueError, match=r"^demos\[1\]: task frames lid, but demos\[0\] has"):
        TPGMM(n_components=2).fit(renamed)


def test_a_pose_vector_is_a_frame():
    np.testing.assert_array_equal(
        TaskFrame.from_vector([1.0, 2.0, 0.5]).matrix, TaskFrame.from_angle([1, 2], 0.5).matrix
    )
    q = [0.0, 0.0, np.sin(0.4), np.cos(0.4)]
    frame = TaskFrame.from_vector([1.0, 2.0, 3.0, *q])
    np.testing.assert_allclose(frame.matrix, matrix_from_quaternion(np.array(q)))
    with pytest.raises(ValueError, match=r"^pose: expected \[x, y, angle\] \(2-D\) or"):
        TaskFrame.from_vector([1.0, 2.0])


def test_length_scale_makes_the_path_independent_of_the_unit():
    demos, frames = _start_goal_task(5, seed=6)
    in_mm = [d * 1000.0 for d in demos]
    frames_mm = [[TaskFrame(f.matrix, f.origin * 1000.0) for f in pair] for pair in frames]
    new = [TaskFrame.from_angle([0.0, 0.1], 0.2), TaskFrame.from_angle([0.5, 0.3], 0.5)]
    new_mm = [TaskFrame(f.matrix, f.origin * 1000.0) for f in new]
    metres = TPGMM(n_components=4, random_state=0).fit(demos, frames).path(new, 30)
    millimetres = TPGMM(n_components=4, random_state=0, length_scale=1000.0)
    millimetres.fit(in_mm, frames_mm)
    np.testing.assert_allclose(millimetres.path(new_mm, 30), metres * 1000.0, atol=1e-6)


def test_estimator_conventions():
    model = TPGMM(n_components=3, product="paths")
    assert model.get_params()["n_components"] == 3
    assert repr(model) == "TPGMM(n_components=3, product='paths')"
    from sklearn.base import clone

    assert clone(model).get_params() == model.get_params()
    from sklearn.exceptions import NotFittedError

    with pytest.raises(NotFittedError):
        model.path([(np.eye(2), np.zeros(2))])
    demos, frames = _object_task(4, seed=7)
    one = TPGMM(n_components=3, em="joint", init="kmeans", random_state=1).fit(demos, frames)
    two = TPGMM(n_components=3, em="joint", init="kmeans", random_state=1).fit(demos, frames)
    np.testing.assert_array_equal(one.means_, two.means_)
    assert one.means_.shape == (3, 2, 3) and one.covariances_.shape == (3, 2, 3, 3)
    assert (one.n_frames_, one.n_dims_, one.n_samples_) == (2, 2, 4 * 70)


def _fit_with(frames):
    TPGMM(n_components=2).fit([np.c_[np.arange(5.0), np.ones(5)]] * 2, frames)


_I = np.eye(2)
_O = np.zeros(2)


_TWO = [(_I, _O), (_I, _O)]
_BAD_FRAMES = {
    "too few lists": ([[(_I, _O)]], r"^frames: got 1 lists of frames for 2 demonstrations"),
    "counts differ": ([[(_I, _O)], _TWO], r"^frames\[1\]: 2 frame\(s\), but frames\[0\] has 1"),
    "matrix shape": (
        [[(np.eye(3), _O)]] * 2,
        r"^frames\[0\]\[0\]\.matrix: expected shape \(2, 2\)",
    ),
    "origin shape": (
        [[(_I, np.zeros(3))]] * 2,
        r"^frames\[0\]\[0\]\.origin: expected shape \(2,\)",
    ),
    "singular": (
        [[([[1, 2], [2, 4]], _O)]] * 2,
        r"^frames\[0\]\[0\]\.matrix: singular \(condition",
    ),
    "nan": ([[(_I, [np.nan, 0])]] * 2, r"^frames\[0\]\[0\]: contains NaN"),
    "no frames": ([[]] * 2, r"^frames\[0\]: needs at least one task frame"),
    "not a pair": ([[_I]] * 2, r"^frames\[0\]\[0\]: expected a TaskFrame or a \(matrix, origin\)"),
    "array": (np.zeros((2, 1, 2, 2)), r"^frames: expected one list of task frames per"),
    "one level": ([(_I, _O)] * 2, r"^frames\[0\]\[0\]: expected a TaskFrame"),
}


@pytest.mark.parametrize("case", list(_BAD_FRAMES))
def test_bad_frames_get_one_line_errors(case):
    frames, message = _BAD_FRAMES[case]
    with pytest.raises((ValueError, TypeError), match=message) as info:
        _fit_with(frames)
    assert "\n" not in str(info.value)


def test_frames_round_trip_points_and_refuse_a_wrong_shape():
    frame = TaskFrame(np.array([[2.0, 1.0], [0.0, 3.0]]), np.array([1.0, -2.0]))
    points = np.random.default_rng(8).normal(size=(5, 2))
    np.testing.assert_allclose(frame.to_local(frame.to_world(points)), points, atol=1e-12)
    with pytest.raises(ValueError, match=r"^points: expected shape \(n, 2\) for a 2-D frame"):
        frame.to_world(np.zeros(2))


def test_new_frames_must_match_the_fitted_ones():
    model = _fitted("paths")
    with pytest.raises(
        ValueError, match=r"^frames: got 1 frame\(s\), but the model was fitted with 2"
    ):
        model.path([(_I, _O)])
    with pytest.raises(ValueError, match=r"^frames\[1\]\.matrix: singular"):
        model.path([(_I, _O), (np.zeros((2, 2)), _O)])
    with pytest.raises(ValueError, match=r"^init: "):
        TPGMM(init="random").fit(*_object_task(2, seed=0))
