"""Moving obstacles: the motions, the scene's predictions, files, the CLI's form, the tracker."""

from __future__ import annotations

import argparse
import warnings

import numpy as np
import pytest

from lfdkit.io.scenes import load_scenes, save_scenes
from lfdkit.model.motion import (
    ConstantVelocity,
    ConstantVelocityKalman,
    Observations,
    Tracker,
    Trajectory,
)
from lfdkit.model.scene import Capsule, Obstacle, Scene


# ------------------------------------------------------------------ motions
def test_constant_velocity_moves_the_obstacle_and_its_shape():
    cup = Obstacle("cup", [0.1, 0.2], 0.03, motion=ConstantVelocity([0.05, -0.02]))
    means, covs = cup.predict([0.0, 2.0])
    np.testing.assert_allclose(means, [[0.1, 0.2], [0.2, 0.16]])
    assert np.all(covs == 0.0)
    moved = cup.at(2.0)
    assert not moved.moving and moved.radius == 0.03
    np.testing.assert_allclose(moved.position, [0.2, 0.16])
    rod = Capsule("marker", [0.0, 0.0], 0.01, [0.1, 0.0], motion=ConstantVelocity([0.0, 1.0]))
    np.testing.assert_allclose(rod.at(0.5).end, [0.1, 0.5])
    np.testing.assert_allclose(rod.at(0.5).position, [0.0, 0.5])


def test_trajectory_interpolates_and_holds_its_ends():
    path = Trajectory([1.0, 2.0, 4.0], [[0.0, 0.0], [1.0, 0.0], [1.0, 2.0]])
    cup = Obstacle("cup", [0.0, 0.0], motion=path)
    means, _ = cup.predict([0.0, 1.5, 3.0, 9.0])
    np.testing.assert_allclose(means, [[0, 0], [0.5, 0], [1, 1], [1, 2]])


def test_static_obstacles_are_unchanged():
    cup = Obstacle("cup", [0.1, 0.2], 0.03)
    assert repr(cup) == "Obstacle(label='cup', position=array([0.1, 0.2]), radius=0.03)"
    assert not cup.moving and cup.at(5.0) is cup
    scene = Scene((cup,))
    assert not scene.moving and scene.at(3.0) is scene
    means, covs = cup.predict([0.0, 1.0])
    np.testing.assert_array_equal(means, [[0.1, 0.2], [0.1, 0.2]])
    assert covs.shape == (2, 2, 2) and not covs.any()


def test_transforms_carry_the_motion():
    cup = Obstacle("cup", [0.1, 0.2], 0.03, motion=ConstantVelocity([0.05, -0.02]))
    np.testing.assert_allclose(cup.scaled(2.0).motion.velocity, [0.1, -0.04])
    np.testing.assert_allclose(cup.mirrored(1).at(1.0).position, [0.15, -0.18])


@pytest.mark.parametrize(
    ("motion", "message"),
    [
        (lambda: ConstantVelocity([0.1, 0.0, 0.0]), "3 components for a 2-D"),
        (lambda: "fast", "expected an lfdkit.model.motion.Motion"),
    ],
)
def test_bad_motions_are_refused(motion, message):
    with pytest.raises((ValueError, TypeError), match=message):
        Obstacle("cup", [0.0, 0.0], motion=motion())


def test_bad_tracks_are_refused():
    with pytest.raises(ValueError, match="strictly increasing"):
        Trajectory([0.0, 0.0], [[0, 0], [1, 1]])
    with pytest.raises(ValueError, match=r"expected shape \(2, 2 or 3\)"):
        Observations([0.0, 1.0], [[0, 0]], 0.01)
    with pytest.raises(ValueError, match="noise"):
        Observations([0.0], [[0, 0]], 0.0)


# ------------------------------------------------------------------ files
def test_csv_round_trip_of_velocities_and_static_files_stay_as_they_were(tmp_path):
    static = {0: Scene((Obstacle("cup", [0.1, 0.2], 0.03),))}
    save_scenes(tmp_path / "static.csv", static)
    assert (tmp_path / "static.csv").read_text() == "demo,class,x,y,radius\n0,cup,0.1,0.2,0.03\n"
    moving = {
        0: Scene(
            (
                Obstacle("cup", [0.1, 0.2], 0.03, motion=ConstantVelocity([0.05, -0.02])),
                Obstacle("marker", [0.3, 0.2], 0.01),
            )
        )
    }
    save_scenes(tmp_path / "moving.csv", moving)
    text = (tmp_path / "moving.csv").read_text()
    assert text.splitlines()[0] == "demo,class,x,y,radius,vx,vy"
    back = load_scenes(tmp_path / "moving.csv")[0]
    np.testing.assert_array_equal(back.obstacles[0].motion.velocity, [0.05, -0.02])
    assert back.obstacles[1].motion is None


def test_csv_refuses_a_partial_velocity_and_a_trajectory(tmp_path):
    (tmp_path / "bad.csv").write_text("class,x,y,vx,vy\ncup,0,0,0.1,\n")
    with pytest.raises(ValueError, match="'vx', 'vy'"):
        load_scenes(tmp_path / "bad.csv")
    track = Obstacle("cup", [0, 0], motion=Trajectory([0, 1], [[0, 0], [1, 1]]))
    with pytest.raises(ValueError, match=r"use a \.json file"):
        save_scenes(tmp_path / "track.csv", {0: Scene((track,))})


def test_json_round_trip_of_every_motion(tmp_path):
    scene = Scene(
        (
            Obstacle("cup", [0.1, 0.2], 0.03, motion=ConstantVelocity([0.05, -0.02])),
            Obstacle("cup", [0.0, 0.0], motion=Trajectory([0.0, 1.0], [[0, 0], [0.3, 0.1]])),
            Capsule(
                "marker",
                [0.0, 0.0],
                0.01,
                [0.1, 0.0],
                motion=Observations([0.0, 0.1], [[0.0, 0.0], [0.01, 0.0]], 0.002),
            ),
            Obstacle("marker", [0.4, 0.4], 0.01),
        )
    )
    save_scenes(tmp_path / "s.json", {7: scene})
    back = load_scenes(tmp_path / "s.json")[7]
    times = np.linspace(-1.0, 3.0, 9)
    for a, b in zip(scene.obstacles, back.obstacles, strict=True):
        assert type(a.motion) is type(b.motion)
        for x, y in zip(a.predict(times), b.predict(times), strict=True):
            np.testing.assert_array_equal(x, y)


def test_json_refuses_two_motions(tmp_path):
    (tmp_path / "bad.json").write_text(
        '{"format": "lfdkit-scenes", "version": 1, "scenes": [{"obstacles": ['
        '{"class": "cup", "position": [0, 0], "velocity": [1, 0], '
        '"trajectory": {"times": [0], "positions": [[0, 0]]}}]}]}'
    )
    with pytest.raises(ValueError, match="give one of velocity, trajectory"):
        load_scenes(tmp_path / "bad.json")


# ------------------------------------------------------------------ the CLI's form
def test_cli_obstacle_with_a_velocity():
    from lfdkit.app.cli.common import _obstacle

    assert _obstacle("cup:0.1,0.2,r=0.03,vx=0.05,vy=-0.02") == (
        "cup",
        [0.1, 0.2],
        0.03,
        [0.05, -0.02],
        None,  # no box sizes: a round obstacle
        None,  # no normal: not a half-space
    )
    assert _obstacle("cup:0.1,0.2")[3] is None
    with pytest.raises(argparse.ArgumentTypeError, match="give vx=, vy="):
        _obstacle("cup:0.1,0.2,vx=0.05")
    with pytest.raises(argparse.ArgumentTypeError, match="vy in"):
        _obstacle("cup:0.1,0.2,vx=0.05,vy=fast")


# ------------------------------------------------------------------ the tracker
def _track(seed: int, n: int, noise: float, dt: float = 0.02):
    rng = np.random.default_rng(seed)
    start = rng.uniform(-1.0, 1.0, 2)
    velocity = rng.uniform(-0.1, 0.1, 2)
    times = dt * np.arange(n)
    truth = start + times[:, None] * velocity
    return times, truth, truth + noise * rng.standard_normal(truth.shape), velocity


def test_kalman_is_the_least_squares_line_without_process_noise():
    # With no process noise and a broad prior the filter's estimate is the line fit's.
    times, _, observed, _ = _track(0, 60, 0.005)
    kf = ConstantVelocityKalman(0.005, acceleration=0.0, velocity_std=1e4)
    for t, z in zip(times, observed, strict=True):
        kf.update(t, z)
    design = np.column_stack([np.ones_like(times), times - times[-1]])
    fit, *_ = np.linalg.lstsq(design, observed, rcond=None)
    np.testing.assert_allclose(kf.mean, fit, atol=1e-8)
    covariance = 0.005**2 * np.linalg.inv(design.T @ design)
    np.testing.assert_allclose(kf.cov, covariance, rtol=1e-5)


def test_kalman_velocity_error_shrinks_as_theory_says():
    # RMS velocity error over seeds against the line fit's σ √(12 / (Δt² n (n² − 1))).
    noise, dt = 0.004, 0.02
    for n in (20, 80):
        errors = []
        for seed in range(300):
            times, _, observed, velocity = _track(seed, n, noise, dt)
            kf = ConstantVelocityKalman(noise, acceleration=0.0)
            for t, z in zip(times, observed, strict=True):
                kf.update(t, z)
            errors.append(kf.velocity - velocity)
        rms = np.sqrt(np.mean(np.square(errors)))
        theory = noise * np.sqrt(12.0 / (dt**2 * n * (n * n - 1.0)))
        assert rms == pytest.approx(theory, rel=0.15)


def test_kalman_covariance_is_calibrated():
    # NEES of the state (dof 4) and of a prediction 0.5 s ahead (dof 2), over seeds.
    noise, acceleration = 0.005, 0.02
    state_nees, predicted_nees = [], []
    for seed in range(400):
        rng = np.random.default_rng(1000 + seed)
        kf = ConstantVelocityKalman(noise, acceleration=acceleration, velocity_std=0.2)
        position = rng.uniform(-1, 1, 2)
        velocity = rng.normal(0.0, 0.2, 2)  # drawn from the filter's prior
        dt = 0.02
        for k in range(40):
            if k:  # the process the filter assumes: white-noise acceleration, exactly
                q = acceleration**2 * np.array([[dt**3 / 3, dt**2 / 2], [dt**2 / 2, dt]])
                kick = rng.multivariate_normal(np.zeros(2), q, size=2)  # (coord, [p, v])
                position = position + dt * velocity + kick[:, 0]
                velocity = velocity + kick[:, 1]
            kf.update(k * dt, position + noise * rng.standard_normal(2))
        error = np.concatenate([kf.mean[0] - position, kf.mean[1] - velocity])
        order = [0, 2, 1, 3]  # [px, py, vx, vy] → [px, vx, py, vy]: blocks per coordinate
        full = np.kron(np.eye(2), kf.cov)
        e = error[order]
        state_nees.append(e @ np.linalg.solve(full, e))
        # future truth 0.5 s ahead (no further kicks: compare with the mean's part only)
        future = position + 0.5 * velocity
        mean, cov = kf.predict([kf.time + 0.5])
        without_process = kf.cov[0, 0] + 2 * 0.5 * kf.cov[0, 1] + 0.25 * kf.cov[1, 1]
        d = mean[0] - future
        predicted_nees.append(d @ d / without_process)
        assert cov[0, 0, 0] > without_process  # the process noise widens it
    assert np.mean(state_nees) == pytest.approx(4.0, abs=0.45)
    assert np.mean(predicted_nees) == pytest.approx(2.0, abs=0.3)


def test_kalman_matches_filterpy():
    filterpy = pytest.importorskip("filterpy.kalman", reason="pip install filterpy")
    from filterpy.common import Q_continuous_white_noise

    noise, acceleration, prior = 0.005, 0.05, 0.5
    times, _, observed, _ = _track(3, 50, noise)
    ours = ConstantVelocityKalman(noise, acceleration, prior)
    ref = filterpy.KalmanFilter(dim_x=4, dim_z=2)
    ref.H = np.array([[1.0, 0, 0, 0], [0, 0, 1.0, 0]])
    ref.R = noise**2 * np.eye(2)
    ref.x = np.array([observed[0, 0], 0.0, observed[0, 1], 0.0])
    ref.P = np.diag([noise**2, prior**2, noise**2, prior**2])
    ours.update(times[0], observed[0])
    for k in range(1, len(times)):
        dt = times[k] - times[k - 1]
        one = np.array([[1.0, dt], [0.0, 1.0]])
        ref.F = np.kron(np.eye(2), one)
        ref.Q = np.kron(np.eye(2), Q_continuous_white_noise(2, dt, acceleration**2))
        ref.predict()
        ref.update(observed[k])
        ours.update(times[k], observed[k])
    np.testing.assert_allclose(ours.mean.T.reshape(-1), ref.x, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(np.kron(np.eye(2), ours.cov), ref.P, rtol=1e-9, atol=1e-15)


def test_observations_predict_with_the_tracker_and_a_plugged_model():
    times, truth, observed, velocity = _track(5, 50, 0.003)
    motion = Observations(times, observed, 0.003)
    assert isinstance(motion.tracker(), Tracker)
    cup = Obstacle("cup", observed[0], motion=motion)
    ahead = times[-1] + 1.0
    mean, cov = cup.predict([ahead])
    np.testing.assert_allclose(mean[0], truth[-1] + velocity, atol=0.03)
    assert cov[0, 0, 0] > 0

    class Still:  # a plug-in model: the last observation, with its noise
        def __init__(self, noise):
            self.noise, self.last = noise, None

        def update(self, t, z):
            self.last = np.asarray(z, float)

        def predict(self, times):
            n = np.size(times)
            return np.repeat(self.last[None], n, 0), np.repeat(
                self.noise**2 * np.eye(2)[None], n, 0
            )

    still = Obstacle("cup", observed[0], motion=Observations(times, observed, 0.003, Still))
    np.testing.assert_array_equal(still.predict([ahead])[0][0], observed[-1])


def test_a_single_observation_is_an_obstacle_standing_where_it_was_seen():
    """One snapshot: no velocity to track; planned as standing (noise as its σ), with a warning."""
    with pytest.warns(UserWarning, match="single observation shows no velocity"):
        motion = Observations([0.2], [[0.1, 0.55]], 0.004)
    cup = Obstacle("cup", [0.1, 0.55], 0.03, motion=motion)
    means, covs = cup.predict([0.0, 1.0, 6.0])
    np.testing.assert_array_equal(means, np.tile([0.1, 0.55], (3, 1)))
    np.testing.assert_allclose(covs, np.tile(0.004**2 * np.eye(2), (3, 1, 1)))
    # Scaled (the IOC's normalisation) it stays standing, without a second warning.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        scaled = motion.transformed(2.0, np.array([1.0, -1.0]))
    np.testing.assert_allclose(scaled.predict(None, [3.0])[0], [[0.2, -1.1]])
    # The default tracker alone would allow ±1 m/s: a plan past it 15 cm away was refused.
    kf = ConstantVelocityKalman(0.004)
    kf.update(0.2, [0.1, 0.55])
    assert 2.0 * np.sqrt(kf.predict([3.0])[1][0, 0, 0]) > 2.0
    # Two observations are tracked as before.
    assert not Observations([0.0, 0.1], [[0, 0], [0.01, 0]], 0.004).standing


def test_kalman_refuses_bad_input():
    with pytest.raises(ValueError, match="noise"):
        ConstantVelocityKalman(-1.0)
    kf = ConstantVelocityKalman(0.01)
    with pytest.raises(ValueError, match="no observation"):
        kf.predict([0.0])
    kf.update(1.0, [0.0, 0.0])
    with pytest.raises(ValueError, match="time order"):
        kf.update(0.5, [0.0, 0.0])


# ------------------------------------------------------- manoeuvres: the acceleration bound
def _manoeuvre(seed: int, a_max: float, dt: float = 0.06, n: int = 60):
    """Times (n,) and positions (n, 2) of a point whose acceleration changes at random.

    Piecewise-constant accelerations of magnitude up to ``a_max`` (new ones every
    0.3–1 s: speeding up, braking, turning), from a random velocity.
    """
    rng = np.random.default_rng(seed)
    fine = 0.002
    steps = int(n * dt / fine) + 1
    p, v = np.zeros(2), rng.uniform(-0.1, 0.1, 2)
    out, a, until = [], np.zeros(2), 0.0
    for i in range(steps):
        t = i * fine
        if t >= until:
            angle = rng.uniform(0.0, 2.0 * np.pi)
            a = rng.uniform(0.3, 1.0) * a_max * np.array([np.cos(angle), np.sin(angle)])
            until = t + rng.uniform(0.3, 1.0)
        out.append(p.copy())
        p, v = p + fine * v + 0.5 * fine * fine * a, v + fine * a
    track = np.array(out)
    times = fine * np.arange(steps)
    pick = np.round(np.arange(n) * dt / fine).astype(int)
    return times, track, pick


def test_acceleration_bound_leaves_the_filter_as_it_was():
    # The estimate and the state covariance are the plain filter's (so filterpy's, above);
    # only the prediction's spread grows, by exactly σ → σ + b/2.
    times, _, observed, _ = _track(3, 50, 0.005)
    plain = ConstantVelocityKalman(0.005, 0.05, 0.5)
    bounded = ConstantVelocityKalman(0.005, 0.05, 0.5, max_acceleration=0.3)
    for t, z in zip(times, observed, strict=True):
        plain.update(t, z)
        bounded.update(t, z)
    np.testing.assert_array_equal(bounded.mean, plain.mean)
    np.testing.assert_array_equal(bounded.cov, plain.cov)
    ahead = plain.time + np.array([0.0, 0.1, 0.5])
    (m0, c0), (m1, c1) = plain.predict(ahead), bounded.predict(ahead)
    np.testing.assert_array_equal(m0, m1)
    b = bounded.bias_bound(ahead - bounded.time)
    np.testing.assert_allclose(np.sqrt(c1[:, 0, 0]), np.sqrt(c0[:, 0, 0]) + 0.5 * b, rtol=1e-12)
    # The future part alone is A τ²/2 (a filter with no observation history to lag on).
    fresh = ConstantVelocityKalman(0.005, max_acceleration=0.3)
    fresh.update(0.0, [0.0, 0.0])
    np.testing.assert_allclose(fresh.bias_bound([0.0, 0.2, 1.0]), 0.15 * np.array([0, 0.04, 1]))


def test_acceleration_bound_covers_a_constant_acceleration_exactly():
    # Noise-free observations of p = a t²/2: the filter's whole error is the lag the
    # bound describes; it is within the bound at every lead time, and the bound is
    # tight to within a factor of 3 (so the test would catch a bound that is zero).
    a = 0.3
    kf = ConstantVelocityKalman(1e-6, acceleration=0.05, velocity_std=0.2, max_acceleration=a)
    dt = 0.06
    for k in range(80):
        t = k * dt
        kf.update(t, [0.5 * a * t * t, 0.0])
    ahead = np.linspace(0.0, 0.6, 13)
    mean, _ = kf.predict(kf.time + ahead)
    error = np.abs(mean[:, 0] - 0.5 * a * (kf.time + ahead) ** 2)
    bound = kf.bias_bound(ahead)
    assert np.all(error <= bound + 1e-9)
    assert np.all(error[1:] >= bound[1:] / 3.0)
    # an acceleration twice the stated one leaves it
    kf2 = ConstantVelocityKalman(1e-6, acceleration=0.05, velocity_std=0.2, max_acceleration=a)
    for k in range(80):
        t = k * dt
        kf2.update(t, [a * t * t, 0.0])
    mean2, _ = kf2.predict(kf2.time + ahead)
    assert np.any(np.abs(mean2[:, 0] - a * (kf2.time + ahead) ** 2) > kf2.bias_bound(ahead))


def test_acceleration_bound_covers_manoeuvres_where_the_plain_filter_does_not():
    # Over seeds, random manoeuvres up to A: the 2σ allowance (A included) holds the true
    # position at >= 99 % of predictions 0.06–0.72 s ahead; the plain filter's misses often.
    a_max, noise, dt = 0.3, 0.003, 0.06
    inside = {True: [], False: []}
    for seed in range(40):
        times, track, pick = _manoeuvre(seed, a_max, dt)
        rng = np.random.default_rng(seed + 500)
        filters = {
            bounded: ConstantVelocityKalman(
                noise, 0.05, 0.2, max_acceleration=a_max if bounded else 0.0
            )
            for bounded in (True, False)
        }
        for j, i in enumerate(pick):
            z = track[i] + noise * rng.standard_normal(2)
            for bounded, kf in filters.items():
                kf.update(times[i], z)
                if j < 10 or i + 12 * 30 >= len(times):
                    continue
                future = i + 30 * np.arange(1, 13)  # 0.06 … 0.72 s ahead
                mean, cov = kf.predict(times[future])
                error = np.linalg.norm(mean - track[future], axis=1)
                inside[bounded].extend(error <= 2.0 * np.sqrt(cov[:, 0, 0]))
    assert np.mean(inside[True]) >= 0.99
    assert np.mean(inside[False]) < 0.9


def test_acceleration_bound_refuses_bad_input():
    with pytest.raises(ValueError, match="max_acceleration: must be >= 0"):
        ConstantVelocityKalman(0.01, max_acceleration=-1.0)
    with pytest.raises(ValueError, match="bound_horizon: must be > 0"):
        ConstantVelocityKalman(0.01, max_acceleration=1.0, bound_horizon=0.0)
