"""ProMP: known weight distributions recovered, closed-form conditioning, seeded samples, a peer."""

from __future__ import annotations

import pickle
import warnings
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lfdkit.imitate import ProMP


def reference_features(phase: np.ndarray, n_basis: int, width: float | None = None) -> np.ndarray:
    """The documented basis, written out independently: normalised Gaussians, even centres."""
    width = 1.0 / (n_basis - 1) if width is None else width
    centres = np.linspace(0.0, 1.0, n_basis)
    bumps = np.exp(-0.5 * ((phase[:, None] - centres) / width) ** 2)
    return bumps / bumps.sum(axis=1, keepdims=True)


def demos_from_weights(weights: np.ndarray, phases: list[np.ndarray], n_basis: int) -> list:
    """Paths y(s) = Ψ(s) w for each weight vector (dimension-major) at its own phases."""
    out = []
    for w, s in zip(weights, phases, strict=True):
        out.append(reference_features(s, n_basis) @ w.reshape(-1, n_basis).T)
    return out


def known_distribution(rng: np.random.Generator, n_basis: int, n_dims: int):
    size = n_basis * n_dims
    mean = rng.normal(0.0, 2.0, size)
    root = rng.normal(0.0, 0.3, (size, size))
    return mean, root @ root.T + 0.05 * np.eye(size)


@pytest.fixture(scope="module")
def full_rank_model() -> ProMP:
    """40 demonstrations of 2-D paths from a known full-rank weight distribution."""
    rng = np.random.default_rng(7)
    mean, cov = known_distribution(rng, 6, 2)
    weights = rng.multivariate_normal(mean, cov, 40)
    phases = [np.linspace(0.0, 1.0, n) for n in rng.integers(30, 70, 40)]
    return ProMP(n_basis=6, regularization=0.0).fit(demos_from_weights(weights, phases, 6))


def test_fit_recovers_the_demonstrations_weights_exactly_at_any_lengths_and_times():
    rng = np.random.default_rng(0)
    n_basis, n_dims = 7, 3
    mean, cov = known_distribution(rng, n_basis, n_dims)
    weights = rng.multivariate_normal(mean, cov, 5)
    # Uneven, different-length sampling in seconds (start 2 s, durations 1.5–4 s).
    phases, times = [], []
    for n, duration in zip((25, 40, 61, 33, 90), (1.5, 2.0, 4.0, 3.0, 2.5), strict=True):
        s = np.r_[0.0, np.sort(rng.uniform(0.0, 1.0, n - 2)), 1.0]
        phases.append(s)
        times.append(2.0 + duration * s)
    demos = demos_from_weights(weights, phases, n_basis)
    model = ProMP(n_basis=n_basis, regularization=0.0).fit(demos, times=times)
    np.testing.assert_allclose(model.weights_mean_, weights.mean(axis=0), atol=1e-8)
    np.testing.assert_allclose(model.weights_cov_, np.cov(weights.T), atol=1e-8)
    assert model.residual_rms_ < 1e-9
    assert model.n_dims_ == n_dims and model.n_demos_ == 5


def test_fit_recovers_a_known_distribution_within_sampling_error():
    rng = np.random.default_rng(1)
    n_basis, n_dims, n_demos = 5, 2, 600
    mean, cov = known_distribution(rng, n_basis, n_dims)
    weights = rng.multivariate_normal(mean, cov, n_demos)
    phases = [np.linspace(0.0, 1.0, n) for n in rng.integers(20, 50, n_demos)]
    # Measurement noise 1 mm on paths of metres: the ridge and noise must not bias the moments.
    demos = [d + rng.normal(0.0, 1e-3, d.shape) for d in demos_from_weights(weights, phases, 5)]
    model = ProMP(n_basis=n_basis).fit(demos)
    variances = np.diag(cov)
    assert np.all(np.abs(model.weights_mean_ - mean) < 4.5 * np.sqrt(variances / n_demos))
    # Standard error of a sample covariance entry: sqrt((Σij² + Σii Σjj) / n).
    cov_se = np.sqrt((cov**2 + np.outer(variances, variances)) / n_demos)
    assert np.all(np.abs(model.weights_cov_ - cov) < 5.0 * cov_se)


def test_mean_path_and_std_follow_the_demonstrations():
    s = np.linspace(0.0, 1.0, 80)
    amplitudes = np.array([0.6, 0.8, 1.0, 1.2, 1.4])
    demos = [np.c_[s, a * np.sin(np.pi * s)] for a in amplitudes]
    model = ProMP(n_basis=20).fit(demos)
    path, std = model.mean_path(81), model.std(81)
    u = np.linspace(0.0, 1.0, 81)
    # 20 bumps fit a half sine to 0.9e-3 rms, 2e-3 at the ends (measured).
    assert model.residual_rms_ < 1.5e-3
    np.testing.assert_allclose(path[:, 1], np.sin(np.pi * u), atol=3e-3)
    np.testing.assert_allclose(path[:, 0], u, atol=3e-3)
    # The spread of y is std(amplitudes) · sin(πs); x never varies.
    np.testing.assert_allclose(std[:, 1], amplitudes.std(ddof=1) * np.sin(np.pi * u), atol=3e-3)
    assert np.all(std[:, 0] < 1e-6)


def test_the_timed_mean_is_the_mean_path_in_seconds_with_its_exact_velocities():
    s = np.linspace(0.0, 1.0, 60)
    demos = [np.c_[2.0 * s, a * np.sin(np.pi * s)] for a in (0.5, 0.7, 0.9)]
    model = ProMP(n_basis=15).fit(demos)
    path = model.timed_mean(2.5, n_points=41)
    np.testing.assert_array_equal(path.positions, model.mean_path(41))
    np.testing.assert_allclose(path.times, np.linspace(0.0, 2.5, 41), rtol=0, atol=1e-15)
    # Velocities: the derivative of mean_at in time, against central differences (step 1e-6).
    h, u = 1e-6, np.linspace(1e-5, 1.0 - 1e-5, 41)
    slope = (model.mean_at(u + h) - model.mean_at(u - h)) / (2 * h) / 2.5
    inner = model.timed_mean(2.5, 41).sample(u * 2.5)  # between the samples: Hermite
    np.testing.assert_allclose(path.velocities[1:-1], slope[1:-1], atol=1e-4)
    np.testing.assert_allclose(inner.positions, model.mean_at(u), atol=1e-6)
    # And the movement itself: x goes 2 units in 2.5 s.
    np.testing.assert_allclose(path.velocities[5:-5, 0], 2.0 / 2.5, atol=0.03)
    with pytest.raises(ValueError, match=r"^duration: .*-1"):
        model.timed_mean(-1.0)


def test_a_via_point_with_zero_covariance_is_passed_exactly(full_rank_model):
    point, phase = np.array([1.5, -2.0]), 0.37
    via = full_rank_model.condition(point, [phase])
    np.testing.assert_allclose(via.mean_at([phase])[0], point, atol=1e-9)
    assert np.all(np.abs(via.covariance_at([phase])) < 1e-9)
    # Elsewhere the band stays open and the source model is unchanged.
    assert np.all(via.std(11)[[0, -1]] > 0.05)
    assert not np.allclose(full_rank_model.mean_at([phase])[0], point)


def test_a_via_point_with_a_covariance_follows_the_scalar_closed_form(full_rank_model):
    """Per coordinate, with independent dimensions: m' = m + v/(v+c) (y − m), v' = v c/(v+c)."""
    rng = np.random.default_rng(3)
    n_basis = 6
    mean, cov = known_distribution(rng, n_basis, 1)
    weights = rng.multivariate_normal(mean, cov, 30)
    phases = [np.linspace(0.0, 1.0, 50)] * 30
    model = ProMP(n_basis=n_basis, regularization=0.0).fit(
        demos_from_weights(weights, phases, n_basis)
    )
    phase, y, c = 0.62, 3.0, 0.04
    m, v = model.mean_at([phase])[0, 0], model.covariance_at([phase])[0, 0, 0]
    via = model.condition([[y]], [phase], covariance=c)
    assert via.mean_at([phase])[0, 0] == pytest.approx(m + v / (v + c) * (y - m), rel=1e-9)
    assert via.covariance_at([phase])[0, 0, 0] == pytest.approx(v * c / (v + c), rel=1e-7)


def test_several_via_points_at_once_are_all_passed(full_rank_model):
    points = np.array([[0.0, 0.0], [1.0, 2.0], [-1.0, 0.5]])
    phases = np.array([0.0, 0.5, 1.0])
    via = full_rank_model.condition(points, phases)
    np.testing.assert_allclose(via.mean_at(phases), points, atol=1e-8)


@pytest.mark.parametrize("n_dims", [1, 2, 3])
def test_a_variance_and_the_same_variance_as_a_matrix_give_the_same_model(n_dims):
    """A variance takes the quick argument check, a matrix the full one: the same result,
    from millimetres to kilometres; the covariance is formed when first read."""
    rng = np.random.default_rng(20 + n_dims)
    for scale in (1e-3, 1.0, 1e3):
        mean, cov = known_distribution(rng, 5, n_dims)
        weights = scale * rng.multivariate_normal(mean, cov, 12)
        model = ProMP(n_basis=5).fit(demos_from_weights(weights, [np.linspace(0, 1, 40)] * 12, 5))
        for phase in (0.0, 0.41, 1.0):
            for variance in (0.0, 0.01 * scale**2):
                point = model.mean_at([phase])[0] + scale * rng.normal(0.0, 0.5, n_dims)
                quick = model.condition(point, [phase], variance)
                assert "weights_cov_" not in vars(quick)  # not formed yet
                general = model.condition(point, [phase], variance * np.eye(n_dims))
                for ours, theirs in (
                    (quick.weights_mean_, general.weights_mean_),
                    (quick.weights_cov_, general.weights_cov_),
                ):
                    np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-12 * abs(theirs).max())
                assert quick.weights_cov_ is quick.weights_cov_  # formed once, then kept
                assert not quick.weights_cov_.flags.writeable
                if variance == 0.0:
                    np.testing.assert_allclose(quick.mean_at([phase])[0], point, atol=1e-9 * scale)


@pytest.mark.parametrize("n_dims", [1, 2, 3])
def test_several_points_with_a_variance_take_their_own_kernel_with_the_general_result(n_dims):
    """Several points with a variance (the quick route: the several-point kernel) against the
    same variance as per-point matrices (the full checks and the general kernel): the same
    model from millimetres to kilometres, as lists or arrays, a repeated phase included."""
    rng = np.random.default_rng(40 + n_dims)
    for scale in (1e-3, 1.0, 1e3):
        mean, cov = known_distribution(rng, 6, n_dims)
        weights = scale * rng.multivariate_normal(mean, cov, 14)
        model = ProMP(n_basis=6).fit(demos_from_weights(weights, [np.linspace(0, 1, 40)] * 14, 6))
        for phases in ([0.0, 0.55], [0.1, 0.47, 1.0], [0.3, 0.3]):
            points = model.mean_at(phases) + scale * rng.normal(0.0, 0.3, (len(phases), n_dims))
            for variance in (0.0, 0.02 * scale**2):
                with warnings.catch_warnings(record=True) as quick_warned:
                    warnings.simplefilter("always")
                    quick = model.condition(points.tolist(), phases, variance)
                    from_arrays = model.condition(points, np.array(phases), variance)
                with warnings.catch_warnings(record=True) as general_warned:
                    warnings.simplefilter("always")
                    general = model.condition(
                        points, phases, np.tile(variance * np.eye(n_dims), (len(phases), 1, 1))
                    )
                assert len(quick_warned) == 2 * len(general_warned)  # warned alike
                for ours in (quick, from_arrays):
                    assert "weights_cov_" not in vars(ours)  # formed when first read
                    for got, want in (
                        (ours.weights_mean_, general.weights_mean_),
                        (ours.weights_cov_, general.weights_cov_),
                    ):
                        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * abs(want).max())
                    assert not ours.weights_mean_.flags.writeable
                if variance == 0.0 and phases[0] != phases[-1]:
                    np.testing.assert_allclose(quick.mean_at(phases), points, atol=1e-9 * scale)


def test_the_several_point_route_refuses_what_the_full_checks_refuse(full_rank_model):
    """Values the quick route's type checks let through get the full checks' one-line errors."""
    point = full_rank_model.mean_at([0.5])[0]
    with pytest.raises(ValueError, match="phases: expected phases in"):
        full_rank_model.condition([point, point], [0.2, 1.5])
    with pytest.raises(ValueError, match="points: contains NaN"):
        full_rank_model.condition([point, [np.nan, 0.0]], [0.2, 0.6])
    with pytest.raises(ValueError, match="phases: got 3 phases for 2 points"):
        full_rank_model.condition([point, point], [0.2, 0.6, 0.9])


def test_a_covariance_set_on_a_conditioned_model_is_the_one_its_band_reads(full_rank_model):
    """Setting ``weights_cov_`` before the conditioned covariance was formed replaces it: the
    band, the covariance and a further conditioning read the new one, not the pending one."""
    via = full_rank_model.condition(full_rank_model.mean_at([0.5]), [0.5], 0.01)
    via.weights_cov_ = 4.0 * full_rank_model.weights_cov_
    np.testing.assert_allclose(via.std(7), 2.0 * full_rank_model.std(7), rtol=1e-12)
    np.testing.assert_array_equal(via.weights_cov_, 4.0 * full_rank_model.weights_cov_)
    again = via.condition(via.mean_at([0.2]), [0.2], 0.01)
    fresh = ProMP.from_state(via.to_state()).condition(via.mean_at([0.2]), [0.2], 0.01)
    np.testing.assert_array_equal(again.weights_cov_, fresh.weights_cov_)


@pytest.mark.parametrize("n_points", [1, 3])
def test_the_covariance_formed_on_read_is_the_closed_form_exactly_symmetric(
    full_rank_model, n_points
):
    """A conditioned model's ``weights_cov_`` (formed on first read by a kernel) against
    ``Σ − Σ Hᵀ (H Σ Hᵀ + R)⁻¹ H Σ`` built from the reference basis; the compiled kernel and
    its NumPy twin agree to 1e-12 of the covariance's scale, each exactly symmetric."""
    from lfdkit.imitate import _promp_kernels, promp

    model = full_rank_model
    phases = np.array([0.3, 0.55, 0.8][:n_points])
    points = model.mean_at(phases) + 0.05
    variance = 1e-3
    via = model.condition(points, phases, covariance=variance)
    assert "weights_cov_" not in vars(via)  # not formed yet
    pending = vars(via)["_pending_cov"]
    formed = via.weights_cov_
    assert "_pending_cov" not in vars(via) and via.weights_cov_ is formed  # formed once
    assert not formed.flags.writeable
    np.testing.assert_array_equal(formed, formed.T)
    d, b, sigma = 2, 6, model.weights_cov_
    features = reference_features(phases, b, model.width_)
    h = np.zeros((n_points * d, d * b))
    for i in range(n_points):
        for c in range(d):
            h[i * d + c, c * b : (c + 1) * b] = features[i]
    gain = sigma @ h.T @ np.linalg.inv(h @ sigma @ h.T + variance * np.eye(n_points * d))
    scale = np.abs(sigma).max()
    np.testing.assert_allclose(formed, sigma - gain @ h @ sigma, rtol=0, atol=1e-9 * scale)
    cov, out, _, m, _, _, prior = pending
    both = []
    for run in (_promp_kernels.conditioned_covariance, promp.conditioned_covariance):
        result = np.empty_like(cov)
        assert run(prior, out, len(cov), m, result) == 0
        np.testing.assert_array_equal(result, result.T)
        both.append(result)
    np.testing.assert_allclose(both[0], both[1], rtol=0, atol=1e-12 * scale)
    assert any(np.array_equal(formed, one) for one in both)  # it is one of the two


@pytest.mark.filterwarnings("ignore:points.*cannot be reached")  # exact points, few demos
def test_the_covariance_formed_in_rows_is_the_mirrored_upper_triangle_to_the_bit():
    """Where ``Σ`` is exactly symmetric (every fitted or conditioned model's) the new
    covariance is formed in whole rows: the numbers of the upper triangle mirrored, to the
    bit, compiled and NumPy twin, on random models (1-3 dimensions, 1-3 points, units 1e-3
    to 1e3). A covariance not exactly symmetric takes the mirrored route (its upper
    triangle), and the result is exactly symmetric either way."""
    from lfdkit.imitate import _promp_kernels, promp

    rng = np.random.default_rng(60)
    for trial in range(16):
        d, b, unit = int(rng.integers(1, 4)), int(rng.integers(4, 9)), 10.0 ** rng.uniform(-3, 3)
        k = int(rng.integers(1, 4))
        mean, cov = known_distribution(rng, b, d)
        weights = unit * rng.multivariate_normal(mean, cov, int(rng.integers(3, 20)))
        demos = demos_from_weights(weights, [np.linspace(0, 1, 30)] * len(weights), b)
        model = ProMP(n_basis=b).fit(demos)
        phases = np.sort(rng.uniform(0.0, 1.0, k))
        points = model.mean_at(phases) + unit * rng.normal(0.0, 0.2, (k, d))
        variance = [0.0, 0.01 * unit**2][trial % 2]
        via = model.condition(points, phases, variance)
        if trial % 3 == 0:  # a conditioned model is exactly symmetric too
            via = via.condition(points[:1], phases[:1], variance + 0.01 * unit**2)
        cov_in, out, symmetric, m, _, _, prior = vars(via)["_pending_cov"]
        assert symmetric and np.array_equal(cov_in, cov_in.T)
        for rows, mirrored in (
            (_promp_kernels.conditioned_covariance_rows, _promp_kernels.conditioned_covariance),
            (promp.conditioned_covariance_rows, promp.conditioned_covariance),
        ):
            got, want = np.empty_like(cov_in), np.empty_like(cov_in)
            rows(prior, out, len(cov_in), m, got)
            mirrored(prior, out, len(cov_in), m, want)
            np.testing.assert_array_equal(got, want)
        np.testing.assert_array_equal(via.weights_cov_, via.weights_cov_.T)
        # One entry off by 1e-9 of the scale: not exactly symmetric, the mirrored route.
        skewed = np.array(model.weights_cov_)
        skewed[0, -1] += 1e-9 * np.abs(skewed).max()
        model.weights_cov_ = skewed
        via = model.condition(points, phases, variance)
        cov_in, out, symmetric, m, _, _, prior = vars(via)["_pending_cov"]
        assert symmetric is False
        mirrored, in_rows = np.empty_like(cov_in), np.empty_like(cov_in)
        _promp_kernels.conditioned_covariance(prior, out, len(cov_in), m, mirrored)
        _promp_kernels.conditioned_covariance_rows(prior, out, len(cov_in), m, in_rows)
        assert not np.array_equal(in_rows, in_rows.T)  # rows would read the skewed entry
        formed = via.weights_cov_
        np.testing.assert_array_equal(formed, mirrored)
        np.testing.assert_array_equal(formed, formed.T)


def test_an_unfitted_model_has_no_covariance_attribute():
    """The class's ``weights_cov_`` (forms a conditioned model's on read) is no attribute of
    a model that is neither fitted nor conditioned."""
    from sklearn.exceptions import NotFittedError

    model = ProMP()
    assert not hasattr(model, "weights_cov_")
    with pytest.raises(AttributeError, match="weights_cov_"):
        model.weights_cov_  # noqa: B018
    with pytest.raises(NotFittedError):
        model.condition([[0.0, 0.0]], [0.5])


def _invariants(buffer: np.ndarray, cov: np.ndarray, n_weights: int, m: int, d: int) -> tuple:
    """The new mean, the lost offsets and the new covariance of a one-set kernel buffer."""
    from lfdkit.imitate import promp

    means, _, lost, _, _ = promp._out_parts(buffer, 1, n_weights, m, d)
    return means, lost, _new_cov(promp.conditioned_covariance, cov, buffer, 1, m)


def _new_cov(run: Any, cov: np.ndarray, buffer: np.ndarray, n_sets: int, m: int) -> np.ndarray:
    """``Σ − Zᵀ Z`` of a kernel buffer, formed by ``run`` (a covariance kernel)."""
    n = len(cov)
    prior = np.r_[0.0, 0.0, np.zeros(n), cov.ravel()]
    result = np.empty((n, n))
    assert run(prior, buffer, n_sets * n, m, result) == 0
    return result


@pytest.mark.slow  # numba compiles the kernel once per checkout (~5-15 s), then loads it (~3 s)
def test_the_compiled_conditioning_equals_its_numpy_twin():
    """numba's kernel (Jacobi pseudo-inverse) against the NumPy twin (LAPACK's eigh) on random
    distributions: 1-3 dimensions, 1-3 points, units 1e-3 to 1e3, rank-deficient covariances,
    repeated phases (directions dropped), variances and per-point covariances."""
    from lfdkit.imitate import _promp_kernels, promp

    rng = np.random.default_rng(11)
    dropped_some = 0
    for trial in range(40):
        # Points well apart in phase (a few per basis function): a well-conditioned solve.
        d, b, k = int(rng.integers(1, 4)), int(rng.integers(6, 10)), int(rng.integers(1, 4))
        n_weights, m, scale = d * b, k * d, 10.0 ** rng.uniform(-3, 3)
        draws = scale * rng.normal(size=(int(rng.integers(3, 2 * n_weights)), n_weights))
        mean, cov = draws.mean(axis=0), np.atleast_2d(np.cov(draws.T))
        for array in (mean, cov):  # read-only, as a model's: numba compiles one signature
            array.flags.writeable = False
        width = 1.0 / (b - 1)
        phases = (np.arange(k) + rng.uniform(0.1, 0.9, k)) / k
        if trial % 4 == 0:
            phases[-1] = phases[0]  # the same phase twice: exact points contradict
        sets = scale * rng.normal(size=(2, k, d))
        noise = (
            np.zeros((0, d, d)) if trial % 3 else np.tile(0.02 * scale**2 * np.eye(d), (k, 1, 1))
        )
        noise.flags.writeable = False
        results = []
        for run, run_cov in (
            (_promp_kernels.condition_weights, _promp_kernels.conditioned_covariance),
            (promp.condition_weights, promp.conditioned_covariance),
        ):
            out = np.empty(promp._out_size(2, n_weights, m))
            centres = promp._scaled_centres(b, width)
            args = (mean, cov, centres, phases, width, sets, 0.01 * scale**2 * (trial % 2))
            n_dropped = run(*args, noise, 1e-10, out)
            means, root_h, lost, columns, root_h_t = promp._out_parts(out, 2, n_weights, m, d)
            new_cov = _new_cov(run_cov, cov, out, 2, m)
            np.testing.assert_array_equal(new_cov, new_cov.T)  # exactly symmetric
            # The same numbers in the layouts a path and a band read.
            np.testing.assert_array_equal(columns, means.reshape(2, d, b).transpose(0, 2, 1))
            np.testing.assert_array_equal(root_h_t, root_h.reshape(m * d, b).T)
            results.append((n_dropped, means, new_cov, lost))
        if k == 1 and not len(noise):  # the one-point kernel: the general one's, to rounding
            for run in (_promp_kernels.condition_point, promp.condition_point):
                single = np.empty(promp._out_size(1, n_weights, m))
                general = np.empty_like(single)
                variance = 0.01 * scale**2 * (trial % 2)
                prior = np.r_[width, 1e-10, mean, cov.ravel()]
                got = run(prior, phases[0], sets[0], variance, single)
                args = (mean, cov, centres, phases, width, sets[:1], variance, noise, 1e-10)
                assert got == _promp_kernels.condition_weights(*args, general)
                # Z is one root of many: compared through what is made of it.
                for ours, theirs, unit in zip(
                    _invariants(single, cov, n_weights, m, d),
                    _invariants(general, cov, n_weights, m, d),
                    (scale, scale, scale**2),
                    strict=True,
                ):
                    np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-12 * unit)
        if not len(noise):  # the several-point kernel: the general one's, to rounding
            variance = 0.01 * scale**2 * (trial % 2)
            prior = np.r_[width, 1e-10, mean, cov.ravel()]
            for run in (_promp_kernels.condition_points, promp.condition_points):
                several = np.empty(promp._out_size(1, n_weights, m))
                general = np.empty_like(several)
                got = run(prior, phases, sets[0], variance, several)
                args = (mean, cov, centres, phases, width, sets[:1], variance, noise, 1e-10)
                assert got == _promp_kernels.condition_weights(*args, general)
                for ours, theirs, unit in zip(
                    _invariants(several, cov, n_weights, m, d),
                    _invariants(general, cov, n_weights, m, d),
                    (scale, scale, scale**2),
                    strict=True,
                ):
                    np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-12 * unit)
        (dropped, *ours), (expected, *theirs) = results
        assert dropped == expected
        dropped_some += dropped > 0
        for got, want, unit in zip(ours, theirs, (scale, scale**2, scale), strict=True):
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-9 * unit)
    assert dropped_some >= 5


def test_many_via_points_at_once_under_one_blas_thread_equal_them_in_turn(full_rank_model):
    """13 points in 2-D: a 26 × 26 innovation covariance (its eigh runs on one BLAS thread)."""
    phases = np.linspace(0.02, 0.98, 13)
    points = full_rank_model.mean_at(phases) + np.random.default_rng(6).normal(0.0, 0.3, (13, 2))
    both = full_rank_model.condition(points, phases, covariance=0.01)
    in_turn = full_rank_model
    for point, phase in zip(points, phases, strict=True):
        in_turn = in_turn.condition(point, [phase], covariance=0.01)
    np.testing.assert_allclose(both.weights_mean_, in_turn.weights_mean_, rtol=1e-6, atol=1e-7)
    np.testing.assert_allclose(both.weights_cov_, in_turn.weights_cov_, rtol=1e-6, atol=1e-7)


def test_weights_are_read_only_and_new_ones_replace_what_was_kept():
    rng = np.random.default_rng(2)
    mean, cov = known_distribution(rng, 5, 2)
    weights = rng.multivariate_normal(mean, cov, 15)
    model = ProMP(n_basis=5).fit(demos_from_weights(weights, [np.linspace(0, 1, 30)] * 15, 5))
    with pytest.raises(ValueError, match="read-only"):
        model.weights_cov_[0, 0] = 1.0
    point = model.mean_at([0.5])[0] + 0.3
    model.sample(2, seed=0)  # keeps the covariance's root
    model.weights_cov_ = 4.0 * model.weights_cov_
    quick = model.condition(point, [0.5], 0.1)
    general = model.condition(point, [0.5], 0.1 * np.eye(2))
    np.testing.assert_allclose(quick.weights_mean_, general.weights_mean_, rtol=1e-12)
    np.testing.assert_allclose(
        model.sample(4000, n_points=3, seed=1).std(axis=0), model.std(3), rtol=0.05
    )
    # What is kept for speed stays with its model: not in copies, not pickled.
    assert "_root_cache" not in vars(quick)
    back = pickle.loads(pickle.dumps(model))
    assert "_root_cache" not in vars(back)
    # A conditioned model pickles with its covariance formed.
    copied = pickle.loads(pickle.dumps(model.condition(point, [0.5], 0.1)))
    assert "_pending_cov" not in vars(copied)
    np.testing.assert_array_equal(copied.weights_cov_, quick.weights_cov_)
    assert not back.weights_cov_.flags.writeable
    again = back.condition(point, [0.5], 0.1)
    np.testing.assert_array_equal(again.weights_mean_, quick.weights_mean_)
    np.testing.assert_array_equal(again.weights_cov_, quick.weights_cov_)


def test_what_conditioning_keeps_follows_attributes_set_after_it(full_rank_model):
    """The kernel's copy of the weights and the attributes copies take are kept per model:
    a new weight array, width or attribute set afterwards must be what the next
    conditioning (one point: the kept copy; two: the general route) uses."""
    model = ProMP.from_state(full_rank_model.to_state())
    point, phase = model.mean_at([0.4])[0] + 0.2, 0.4
    model.condition(point, [phase], 0.01)  # keeps the kernel's weights and the copied state
    model.weights_mean_ = model.weights_mean_ + 1.0  # every path 1 higher (bumps sum to 1)
    model.weights_cov_ = 2.0 * model.weights_cov_
    model.width_ = 0.3
    model.n_demos_ = 99
    fresh = ProMP.from_state(model.to_state())
    for points, phases in (([point], [phase]), ([point, point - 0.1], [phase, 0.8])):
        got, want = model.condition(points, phases, 0.01), fresh.condition(points, phases, 0.01)
        np.testing.assert_array_equal(got.weights_mean_, want.weights_mean_)
        np.testing.assert_array_equal(got.weights_cov_, want.weights_cov_)
        assert (got.width_, got.n_demos_) == (0.3, 99)
    # A conditioned model conditioned again: from its own weights (formed now), not its source's.
    via = model.condition(point, [phase], 0.01)
    twice = via.condition(point - 0.1, [0.8], 0.01)
    np.testing.assert_allclose(
        twice.weights_mean_,
        model.condition([point, point - 0.1], [phase, 0.8], 0.01).weights_mean_,
        rtol=1e-9,
        atol=1e-9,
    )


@settings(max_examples=40, deadline=None)
@given(
    phases=st.lists(st.floats(0.0, 1.0), min_size=2, max_size=2),
    offsets=st.lists(st.floats(-3.0, 3.0), min_size=4, max_size=4),
    variances=st.lists(st.floats(1e-4, 0.5), min_size=2, max_size=2),
)
def test_conditioning_at_once_equals_conditioning_in_turn(
    full_rank_model, phases, offsets, variances
):
    points = np.reshape(offsets, (2, 2))
    covs = np.array([v * np.eye(2) for v in variances])
    both = full_rank_model.condition(points, phases, covariance=covs)
    first = full_rank_model.condition(points[0], phases[:1], covariance=covs[0])
    in_turn = first.condition(points[1], phases[1:], covariance=covs[1])
    np.testing.assert_allclose(both.weights_mean_, in_turn.weights_mean_, rtol=1e-6, atol=1e-7)
    np.testing.assert_allclose(both.weights_cov_, in_turn.weights_cov_, rtol=1e-6, atol=1e-7)


def test_conditioning_many_sets_at_once_equals_conditioning_each(full_rank_model):
    rng = np.random.default_rng(4)
    phases = np.array([0.2, 0.7])
    sets = rng.normal(0.0, 1.0, (5, 2, 2))
    for covariance in (0.0, 0.01, np.array([[0.02, 0.005], [0.005, 0.01]])):
        many = full_rank_model.condition_many(sets, phases, covariance=covariance)
        assert len(many) == 5
        for model, points in zip(many, sets, strict=True):
            one = full_rank_model.condition(points, phases, covariance=covariance)
            np.testing.assert_allclose(model.weights_mean_, one.weights_mean_, rtol=0, atol=1e-12)
            np.testing.assert_array_equal(model.weights_cov_, one.weights_cov_)
    exact = full_rank_model.condition_many(sets, phases)
    for model, points in zip(exact, sets, strict=True):
        np.testing.assert_allclose(model.mean_at(phases), points, atol=1e-9)
    # One covariance for all, read-only so that no copy can change the others.
    assert exact[0].weights_cov_ is exact[4].weights_cov_
    assert not exact[0].weights_cov_.flags.writeable
    with pytest.raises(ValueError, match=r"^phases: got 1 phases for 2 points per set"):
        full_rank_model.condition_many(sets, [0.5])
    with pytest.raises(ValueError, match=r"^points: expected shape \(n_sets, n_via, 2\)"):
        full_rank_model.condition_many(sets[0], phases)


def test_conditioning_many_sets_names_the_first_set_out_of_reach():
    s = np.linspace(0.0, 1.0, 40)
    demos = [np.c_[s, a * np.sin(np.pi * s)] for a in (0.9, 1.1)]  # x never varies
    model = ProMP(n_basis=6).fit(demos)
    sets = np.array([[[0.5, 1.05]], [[0.5, 0.95]], [[0.7, 1.0]], [[0.9, 1.0]]])
    with pytest.warns(UserWarning, match=r"^points\[2\]\[0\]: cannot be reached.* by 0\.2") as got:
        model.condition_many(sets, [0.5])
    assert len(got) == 1


def test_the_band_of_a_conditioned_model_equals_that_of_its_formed_covariance(full_rank_model):
    """std before the covariance is formed (the source's band less the reduction, the
    source's band kept) equals std from the formed covariance, for several conditionings
    of one model, two grid sizes and a source whose covariance is replaced in between."""
    rng = np.random.default_rng(9)
    model = ProMP.from_state(full_rank_model.to_state())
    for n_points in (7, 31, 7):
        for phases in ([0.3], [0.1, 0.8]):
            points = model.mean_at(phases) + rng.normal(0.0, 0.2, (len(phases), 2))
            for variance in (0.0, 1e-3):
                band = model.condition(points, phases, variance).std(n_points)
                formed = model.condition(points, phases, variance)
                formed.weights_cov_  # noqa: B018 (formed: std takes the general path)
                expected = formed.std(n_points)
                scale = float(model.std(n_points).max())
                np.testing.assert_allclose(band**2, expected**2, rtol=0, atol=1e-12 * scale**2)
                assert np.all(band[np.searchsorted(np.linspace(0, 1, n_points), 0.5)] > 0)
        model.weights_cov_ = 1.5 * model.weights_cov_  # replaced: the band kept is not reused


def test_paths_on_the_cached_even_grid_equal_those_at_the_same_phases():
    s = np.linspace(0.0, 1.0, 30)
    demos = [np.c_[s, a * s**2, np.cos(a * s)] for a in (0.5, 1.0, 1.5, 1.7)]
    model = ProMP(n_basis=7).fit(demos)
    other = ProMP(n_basis=7, width=0.3).fit(demos)  # same grid size, other width: not shared
    u = np.linspace(0.0, 1.0, 23)
    for m in (model, other, model):
        np.testing.assert_array_equal(m.mean_path(23), m.mean_at(u))
        # Variances, to rounding of the largest (summed in another order: near a zero
        # band the square root would magnify that rounding).
        variances = np.einsum("nii->ni", m.covariance_at(u))
        exact = 1e-13 * variances.max()
        np.testing.assert_allclose(m.std(23) ** 2, variances, rtol=0, atol=exact)
    assert not np.allclose(model.std(23), other.std(23))


def test_a_point_the_demonstrations_cannot_reach_is_warned_about():
    s = np.linspace(0.0, 1.0, 40)
    demos = [np.c_[s, a * np.sin(np.pi * s)] for a in (0.9, 1.1)]  # x never varies
    model = ProMP(n_basis=6).fit(demos)
    with pytest.warns(
        UserWarning,
        match=r"^points\[0\]: cannot be reached; the conditioned mean misses it by 0\.2",
    ):
        model.condition([[0.7, 1.0]], [0.5])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        model.condition([[0.5, 1.05]], [0.5])  # reachable: no warning


def test_exact_via_points_that_contradict_each_other_are_warned_about(full_rank_model):
    with pytest.warns(UserWarning, match=r"^points\[\d\]: cannot be reached"):
        full_rank_model.condition([[0.0, 0.0], [1.0, 1.0]], [0.5, 0.5])
    # With a covariance the two become a compromise, silently and exactly halfway.
    both = full_rank_model.condition([[0.0, 0.0], [1.0, 1.0]], [0.5, 0.5], covariance=0.01)
    middle = full_rank_model.condition([[0.5, 0.5]], [0.5], covariance=0.005)
    np.testing.assert_allclose(both.weights_mean_, middle.weights_mean_, atol=1e-9)


def test_sample_statistics_match_the_model_and_the_seed_repeats(full_rank_model):
    n = 20_000
    samples = full_rank_model.sample(n, n_points=15, seed=11)
    assert samples.shape == (n, 15, 2)
    mean, std = full_rank_model.mean_path(15), full_rank_model.std(15)
    assert np.all(np.abs(samples.mean(axis=0) - mean) < 4.5 * std / np.sqrt(n))
    assert np.all(np.abs(samples.std(axis=0) / std - 1.0) < 4.5 / np.sqrt(2 * n))
    # Full covariance too: at one phase, the 2×2 covariance of the samples.
    empirical = np.cov(samples[:, 7, :].T)
    expected = full_rank_model.covariance_at([0.5])[0]
    np.testing.assert_allclose(empirical, expected, rtol=0.05, atol=0.02 * expected.max())
    again = full_rank_model.sample(3, n_points=15, seed=11)
    np.testing.assert_array_equal(again, full_rank_model.sample(3, n_points=15, seed=11))
    np.testing.assert_allclose(samples[:3], again, rtol=1e-12, atol=1e-12)
    assert not np.allclose(samples[:3], full_rank_model.sample(3, n_points=15, seed=12))


def test_samples_of_a_conditioned_model_all_pass_its_via_point(full_rank_model):
    via = full_rank_model.condition([2.0, 1.0], [0.5])
    samples = via.sample(50, n_points=3, seed=0)  # phases 0, 0.5, 1
    np.testing.assert_allclose(samples[:, 1, :], np.tile([2.0, 1.0], (50, 1)), atol=1e-6)


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (
            lambda m: m.condition([[0.0, 0.0]], [1.3]),
            r"^phases: expected phases in \[0, 1\], got 1.3",
        ),
        (lambda m: m.condition([[0.0, 0.0]], [-0.1]), r"^phases: .*got -0.1 at index 0"),
        (lambda m: m.condition([[0.0, 0.0, 0.0]], [0.5]), r"^points: expected 2 coordinates"),
        (lambda m: m.condition([[0.0, 0.0]], [0.2, 0.5]), r"^phases: got 2 phases for 1 points"),
        (lambda m: m.condition([0.0, 0.0], [0.5], np.eye(3)), r"^covariance: expected"),
        (lambda m: m.condition([0.0, 0.0], [0.5], -1.0), r"^covariance: must be positive"),
        (lambda m: m.condition([0.0, np.nan], [0.5]), r"^points: contains NaN"),
        (lambda m: m.condition([0.0, 0.0], np.nan), r"^phases: contains NaN"),
        (lambda m: m.condition([0.0, 0.0], [0.5], np.inf), r"^covariance: contains NaN"),
        (lambda m: m.condition([[0.0], [0.0]], [0.5]), r"^points: expected 2 coordinates"),
        (lambda m: m.mean_at([2.0]), r"^phases: expected phases in \[0, 1\]"),
        (lambda m: m.sample(0), r"^n_samples:"),
    ],
)
def test_bad_input_is_refused_in_one_line_naming_the_argument(full_rank_model, call, message):
    with pytest.raises(ValueError, match=message) as info:
        call(full_rank_model)
    assert "\n" not in str(info.value)


def test_bad_fit_input_is_refused_in_one_line():
    s = np.linspace(0.0, 1.0, 20)
    demo = np.c_[s, s**2]
    with pytest.raises(ValueError, match=r"^demos: needs at least 2 demonstrations.*got 1"):
        ProMP().fit([demo])
    with pytest.raises(ValueError, match=r"^demos\[1\]: expected 2 columns"):
        ProMP().fit([demo, np.c_[s, s, s]])
    with pytest.raises(ValueError, match=r"^times: got 1 time arrays for 2 demonstrations"):
        ProMP().fit([demo, demo], times=[s])
    with pytest.raises(ValueError, match=r"^n_basis:"):
        ProMP(n_basis=1).fit([demo, demo])
    with pytest.raises(ValueError, match=r"^width:"):
        ProMP(width=2.0).fit([demo, demo])


def test_a_malformed_state_is_refused_in_one_line(full_rank_model):
    state = full_rank_model.to_state()
    for change, message in (
        ({"residual_rms": float("nan")}, r"^promp\.residual_rms: expected a number >= 0"),
        ({"width": 1.5}, r"^promp\.width: expected a value in \(0, 1\]"),
        ({"width": "0.2"}, r"^promp\.width: expected a number"),
        ({"params": None}, r"^promp\.params: expected an object"),
    ):
        with pytest.raises(ValueError, match=message):
            ProMP.from_state({**state, **change})
    with pytest.raises(ValueError, match=r"^promp: expected an object, got list"):
        ProMP.from_state([])
    back = ProMP.from_state(state)
    np.testing.assert_array_equal(back.weights_cov_, full_rank_model.weights_cov_)


def test_use_before_fit_says_so():
    from sklearn.exceptions import NotFittedError

    with pytest.raises(NotFittedError):
        ProMP().mean_path()


def test_conditioned_model_keeps_the_parameters():
    s = np.linspace(0.0, 1.0, 30)
    demos = [np.c_[s, a * s] for a in (0.5, 1.0, 1.5)]
    model = ProMP(n_basis=5, width=0.2, regularization=1e-4).fit(demos)
    via = model.condition([0.5, 0.5], [0.5], covariance=1e-3)
    assert via.get_params() == model.get_params()
    assert via.width_ == model.width_ == 0.2


def test_against_movement_primitives_promp():
    """movement_primitives' ProMP on the same data: conditioning agrees to rounding, fits closely.

    Given the same basis (its centres, its width ``sqrt(-1 / (8 n² ln 0.7))``) and
    the same weight distribution, its mean, variance and conditioned mean and
    covariance are ours to 1e-12. Each fitted on its own (ours ridge least
    squares, its EM with a smoothness prior), the means agree within 1 % and
    the bands within 0.5 % of the paths' extent (measured: 0.8 % and 0.24 %).
    """
    peer = pytest.importorskip("movement_primitives.promp")
    n_demos, n_steps, n_basis = 12, 101, 10
    rng = np.random.default_rng(5)
    t = np.linspace(0.0, 1.0, n_steps)
    Y = np.empty((n_demos, n_steps, 2))
    for j in range(n_demos):
        Y[j, :, 0] = np.cos(2 * np.pi * t + rng.normal(0.0, 0.1))
        Y[j, :, 1] = (1.0 + rng.normal(0.0, 0.1)) * np.sin(np.pi * t)
    extent = float(np.ptp(Y))
    width = np.sqrt(-1.0 / (8.0 * n_basis**2 * np.log(0.7)))
    ours = ProMP(n_basis=n_basis, width=width).fit(list(Y))
    theirs = peer.ProMP(n_dims=2, n_weights_per_dim=n_basis).from_weight_distribution(
        ours.weights_mean_.copy(), ours.weights_cov_.copy()
    )
    exact = 1e-12 * extent
    np.testing.assert_allclose(ours.mean_path(n_steps), theirs.mean_trajectory(t), atol=exact)
    np.testing.assert_allclose(ours.std(n_steps), np.sqrt(theirs.var_trajectory(t)), atol=exact)
    point = np.array([0.2, 1.2])
    their_via = theirs.condition_position(point, y_cov=np.eye(2) * 1e-6, t=0.5, t_max=1.0)
    our_via = ours.condition(point, [0.5], covariance=1e-6)
    np.testing.assert_allclose(our_via.mean_path(n_steps), their_via.mean_trajectory(t), atol=exact)
    np.testing.assert_allclose(our_via.weights_cov_, their_via.weight_cov, atol=1e-12)

    fitted = peer.ProMP(n_dims=2, n_weights_per_dim=n_basis)
    fitted.imitate(np.tile(t, (n_demos, 1)), Y)
    own = ProMP(n_basis=n_basis).fit(list(Y))
    np.testing.assert_allclose(
        own.mean_path(n_steps), fitted.mean_trajectory(t), atol=0.01 * extent
    )
    np.testing.assert_allclose(
        own.std(n_steps), np.sqrt(fitted.var_trajectory(t)), atol=0.005 * extent
    )
