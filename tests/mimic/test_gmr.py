"""Tests for lfdkit.mimic.gmr: GMM/GMR generalized path (thesis §3.2)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from sklearn.base import clone
from sklearn.exceptions import NotFittedError

from lfdkit.mimic.gmr import GMR, ComponentLimitWarning, _Mixture, select_n_components

gmr_pkg = pytest.importorskip("gmr")


# ----------------------------------------------------------------- helpers
def sine_demos(n_demos=5, n=100, noise=0.01, seed=0, noise_second_half=None):
    """Noisy copies of s(t) = (t, sin 2πt), t in [0, 1]."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, n)
    truth = np.c_[t, np.sin(2 * np.pi * t)]
    sd = np.full(n, noise)
    if noise_second_half is not None:
        sd[t > 0.5] = noise_second_half
    demos = [truth + rng.normal(size=truth.shape) * sd[:, None] for _ in range(n_demos)]
    return demos, t, truth


def random_fitted_gmr(k, q, rng):
    """A GMR whose mixture is set by hand (no EM), for conditioning checks."""
    model = GMR(n_components=k)
    d = 1 + q
    weights = rng.uniform(0.2, 1.0, k)
    model.weights_ = weights / weights.sum()
    model.means_ = rng.normal(size=(k, d))
    a = rng.normal(size=(k, d, d))
    model.covariances_ = a @ np.swapaxes(a, 1, 2) + 0.2 * np.eye(d)
    model.n_dims_ = q
    model.time_range_ = (0.0, 1.0)
    return model


def reference_condition(model, t0):
    """Conditional mixture at one phase from the independent `gmr` package."""
    ref = gmr_pkg.GMM(
        n_components=len(model.weights_),
        priors=model.weights_,
        means=model.means_,
        covariances=model.covariances_,
    )
    return ref.condition(np.array([0]), np.array([t0]))


@pytest.fixture(scope="module")
def sine_model():
    demos, t, truth = sine_demos()
    return GMR(n_components=8, random_state=0).fit(demos), t, truth


# ------------------------------------------------------ reference answers
def test_mean_matches_gmr_package(sine_model):
    model, _, _ = sine_model
    ref = gmr_pkg.GMM(
        n_components=model.n_components,
        priors=model.weights_,
        means=model.means_,
        covariances=model.covariances_,
    )
    tq = np.linspace(-0.2, 1.2, 57)
    expected = ref.predict(np.array([0]), tq[:, None])
    np.testing.assert_allclose(model.predict(tq), expected, rtol=0, atol=1e-10)


def test_covariances_match_gmr_package_conditional_mixture(sine_model):
    model, _, _ = sine_model
    tq = np.array([0.0, 0.13, 0.5, 0.77, 1.0])
    _, cov_thesis = model.predict(tq, return_cov=True)
    _, cov_ltc = model.predict(tq, return_cov=True, cov_mode="law_of_total_covariance")
    for i, t0 in enumerate(tq):
        cond = reference_condition(model, t0)
        beta, mu, sig = cond.priors, cond.means, cond.covariances
        mean = beta @ mu
        thesis = np.einsum("k,kij->ij", beta**2, sig)
        dev = mu - mean
        ltc = np.einsum("k,kij->ij", beta, sig) + np.einsum("k,ki,kj->ij", beta, dev, dev)
        np.testing.assert_allclose(cov_thesis[i], thesis, rtol=0, atol=1e-10)
        np.testing.assert_allclose(cov_ltc[i], ltc, rtol=0, atol=1e-10)


@settings(max_examples=30, deadline=None)
@given(
    k=st.integers(1, 5),
    q=st.integers(1, 3),
    seed=st.integers(0, 2**31 - 1),
)
def test_conditioning_matches_gmr_package_random_mixtures(k, q, seed):
    rng = np.random.default_rng(seed)
    model = random_fitted_gmr(k, q, rng)
    tq = rng.uniform(-2.0, 2.0, 7)
    ref = gmr_pkg.GMM(
        n_components=k, priors=model.weights_, means=model.means_, covariances=model.covariances_
    )
    mean, cov = model.predict(tq, return_cov=True, cov_mode="law_of_total_covariance")
    np.testing.assert_allclose(mean, ref.predict(np.array([0]), tq[:, None]), atol=1e-9)
    for i, t0 in enumerate(tq):
        cond = ref.condition(np.array([0]), np.array([t0]))
        # The exact conditional mixture's covariance, from samples' moments.
        m = cond.priors @ cond.means
        dev = cond.means - m
        expected = np.einsum("k,kij->ij", cond.priors, cond.covariances) + np.einsum(
            "k,ki,kj->ij", cond.priors, dev, dev
        )
        np.testing.assert_allclose(cov[i], expected, atol=1e-9)


def test_single_component_is_linear_regression():
    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 1.0, 80)
    demos = [np.c_[2.0 + 3.0 * t, -1.0 + 0.5 * t] + rng.normal(0, 0.05, (80, 2)) for _ in range(3)]
    reg = 1e-6
    model = GMR(n_components=1, covariance_reg=reg, random_state=0).fit(demos)

    data = np.vstack([np.c_[t, d] for d in demos])
    mu = data.mean(axis=0)
    sigma = np.cov(data.T, bias=True) + reg * np.eye(3)
    np.testing.assert_allclose(model.means_[0], mu, atol=1e-12)
    np.testing.assert_allclose(model.covariances_[0], sigma, atol=1e-10)

    tq = np.array([-0.5, 0.0, 0.3, 1.0, 2.0])
    slope = sigma[1:, 0] / sigma[0, 0]
    expected_mean = mu[1:] + (tq[:, None] - mu[0]) * slope
    expected_cov = sigma[1:, 1:] - np.outer(sigma[1:, 0], sigma[0, 1:]) / sigma[0, 0]
    for mode in ("thesis", "law_of_total_covariance"):
        mean, cov = model.predict(tq, return_cov=True, cov_mode=mode)
        np.testing.assert_allclose(mean, expected_mean, atol=1e-10)
        np.testing.assert_allclose(cov, np.broadcast_to(expected_cov, cov.shape), atol=1e-12)
    # ordinary least squares on the pooled samples gives the same line
    coef = np.polyfit(data[:, 0], data[:, 1], 1)
    assert slope[0] == pytest.approx(coef[0], rel=1e-4)


# -------------------------------------------------------- behaviour on data
def test_recovers_noisy_sine(sine_model):
    model, t, truth = sine_model
    assert model.converged_
    rms = np.sqrt(np.mean(np.sum((model.predict(t) - truth) ** 2, axis=1)))
    assert rms < 0.03
    path = model.path(50)
    assert path.shape == (50, 2)
    np.testing.assert_allclose(path, model.predict(np.linspace(0, 1, 50)))


def test_covariance_tracks_demo_spread():
    # noise sd 0.01 for t < 0.5 and 0.08 after: the variance across the path
    # (sine coordinate) must be much larger in the second half
    demos, _, _ = sine_demos(n_demos=8, noise=0.01, noise_second_half=0.08, seed=1)
    model = GMR(n_components=12, random_state=0).fit(demos)
    tq = np.linspace(0.0, 1.0, 101)
    first, second = (tq > 0.1) & (tq < 0.4), (tq > 0.6) & (tq < 0.9)
    for mode in ("thesis", "law_of_total_covariance"):
        _, cov = model.predict(tq, return_cov=True, cov_mode=mode)
        assert cov[second, 1, 1].mean() > 5 * cov[first, 1, 1].mean()
        np.testing.assert_allclose(cov, np.swapaxes(cov, 1, 2), atol=1e-15)
        assert np.all(np.linalg.eigvalsh(cov) > 0)
    # the proper (law of total covariance) variance is close to the true 0.08²
    _, cov = model.predict(tq, return_cov=True, cov_mode="law_of_total_covariance")
    assert cov[second, 1, 1].mean() == pytest.approx(0.08**2, rel=0.3)


def test_law_of_total_covariance_dominates_thesis_covariance(sine_model):
    model, _, _ = sine_model
    tq = np.linspace(0.0, 1.0, 41)
    _, thesis = model.predict(tq, return_cov=True, cov_mode="thesis")
    _, ltc = model.predict(tq, return_cov=True, cov_mode="law_of_total_covariance")
    # β_k ≥ β_k² and the between-component term is PSD
    assert np.all(np.linalg.eigvalsh(ltc - thesis) > -1e-14)
    ltc_model = clone(model).set_params(cov_mode="law_of_total_covariance")
    ltc_model.__dict__.update({k: v for k, v in model.__dict__.items() if k.endswith("_")})
    np.testing.assert_allclose(ltc_model.predict(tq, return_cov=True)[1], ltc)


def test_far_extrapolation_does_not_underflow(sine_model):
    model, _, _ = sine_model
    tq = np.array([-1e4, -100.0, -5.0, 6.0, 100.0, 1e4])
    for mode in ("thesis", "law_of_total_covariance"):
        mean, cov = model.predict(tq, return_cov=True, cov_mode=mode)
        assert np.all(np.isfinite(mean)) and np.all(np.isfinite(cov))
    # far away one component takes all the weight: the mean is its regression line
    beta, _ = model._responsibilities(tq)
    np.testing.assert_allclose(beta.sum(axis=1), 1.0)
    assert np.all(beta.max(axis=1) > 1 - 1e-12)


def test_arclength_phase_ignores_speed():
    # a straight line traversed with quadratic speed profile: x = u², y = 0
    u = np.linspace(0.0, 1.0, 60)
    demos = [np.c_[u**2, np.zeros_like(u)], np.c_[u**2, np.zeros_like(u)] * 1.0]
    by_arc = GMR(n_components=1, time_mode="arclength", random_state=0).fit(demos)
    by_index = GMR(n_components=1, time_mode="index", random_state=0).fit(demos)
    # along arc length x is exactly linear in the phase: K=1 regression is exact
    np.testing.assert_allclose(by_arc.predict([0.0, 0.5, 1.0])[:, 0], [0.0, 0.5, 1.0], atol=1e-4)
    # by index the best line through x = u² misses the midpoint by ~1/6
    assert by_index.predict([0.5])[0, 0] == pytest.approx(1 / 3, abs=0.01)


def test_explicit_times_and_path_range():
    rng = np.random.default_rng(4)
    demos, times = [], []
    for n in (40, 55, 70):  # different lengths
        tj = np.sort(rng.uniform(0.0, 2.0, n))
        times.append(tj)
        demos.append(np.c_[np.cos(tj), np.sin(tj)] + rng.normal(0, 0.005, (n, 2)))
    model = GMR(n_components=5, random_state=0).fit(demos, times=times)
    assert model.time_range_[0] >= 0.0 and model.time_range_[1] <= 2.0
    tq = np.linspace(0.2, 1.8, 30)
    err = np.linalg.norm(model.predict(tq) - np.c_[np.cos(tq), np.sin(tq)], axis=1)
    assert err.max() < 0.02
    path = model.path(11)
    np.testing.assert_allclose(path, model.predict(np.linspace(*model.time_range_, 11)))


def test_one_spatial_dimension_and_shapes():
    t = np.linspace(0.0, 1.0, 50)
    demos = [(t**2)[:, None], (t**2 + 0.01)[:, None]]
    model = GMR(n_components=3, random_state=0).fit(demos)
    assert model.n_dims_ == 1
    assert model.means_.shape == (3, 2) and model.covariances_.shape == (3, 2, 2)
    assert model.weights_.shape == (3,)
    mean, cov = model.predict(t, return_cov=True)
    assert mean.shape == (50, 1) and cov.shape == (50, 1, 1)
    assert model.predict(0.5).shape == (1, 1)
    np.testing.assert_allclose(mean[:, 0], t**2 + 0.005, atol=0.02)


def test_seed_determinism_and_sklearn_api():
    demos, _, _ = sine_demos(seed=5)
    a = GMR(n_components=6, random_state=7).fit(demos)
    b = clone(a).fit(demos)
    np.testing.assert_array_equal(a.means_, b.means_)
    np.testing.assert_array_equal(a.path(), b.path())
    assert a.get_params()["n_components"] == 6
    assert np.isfinite(a.bic_) and np.isfinite(a.aic_) and np.isfinite(a.log_likelihood_)
    assert a.weights_.sum() == pytest.approx(1.0)


@pytest.mark.parametrize("scale", [1000.0, 0.01])
def test_length_scale_makes_the_fit_independent_of_the_units(scale):
    # The same demonstrations in millimetres (or hectometres), EM in the original unit.
    demos, _, _ = sine_demos(seed=3, noise=0.05)
    base = GMR(n_components=6, random_state=2).fit(demos)
    scaled = GMR(n_components=6, random_state=2, length_scale=scale).fit([scale * d for d in demos])
    np.testing.assert_allclose(scaled.path_, scale * base.path_, rtol=1e-9, atol=1e-12 * scale)
    to_data = np.array([1.0, scale, scale])
    np.testing.assert_allclose(scaled.means_, base.means_ * to_data, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(
        scaled.covariances_, base.covariances_ * np.outer(to_data, to_data), rtol=1e-7, atol=1e-15
    )
    # Densities of positions in the new unit: divided by scale**q (q = 2).
    shift = 2.0 * np.log(scale)
    assert scaled.log_likelihood_ == pytest.approx(base.log_likelihood_ - shift, abs=1e-9)
    n = scaled.n_samples_
    assert scaled.bic_ == pytest.approx(base.bic_ + 2.0 * n * shift, rel=1e-9, abs=1e-6)
    assert scaled.aic_ == pytest.approx(base.aic_ + 2.0 * n * shift, rel=1e-9, abs=1e-6)
    # Without it, EM weighs phase against positions differently: another path.
    plain = GMR(n_components=6, random_state=2).fit([scale * d for d in demos])
    assert not np.allclose(plain.path_, scale * base.path_, rtol=1e-6, atol=1e-6 * scale)


def test_select_n_components_finds_true_mixture_size():
    rng = np.random.default_rng(0)
    # samples (t, s) from a known 3-component mixture, split into "demos"
    centres = np.array([[0.1, 0.0, 1.0], [0.5, 2.0, -1.0], [0.9, 4.0, 1.0]])
    pts = np.vstack([c + rng.normal(0, [0.03, 0.1, 0.1], (200, 3)) for c in centres])
    rng.shuffle(pts)
    demos = [pts[i::4, 1:] for i in range(4)]
    times = [pts[i::4, 0] for i in range(4)]
    best, scores = select_n_components(
        demos, candidates=range(1, 7), random_state=0, times=times, search="exhaustive"
    )
    assert best == 3
    assert set(scores) == set(range(1, 7))
    assert scores[3] == min(scores.values())
    # The ladder visits fewer counts and makes the same choice.
    fast, visited = select_n_components(demos, candidates=range(1, 7), random_state=0, times=times)
    assert fast == 3
    assert set(visited) <= set(range(1, 7))
    assert visited[3] == min(visited.values())
    with pytest.warns(ComponentLimitWarning, match="AIC"):
        best_aic, aic = select_n_components(
            demos, candidates=[1, 3], criterion="aic", random_state=0, times=times
        )
    assert best_aic == 3 and aic[3] < aic[1]


# ------------------------------------------------------------------ errors
def test_predict_before_fit():
    with pytest.raises(NotFittedError):
        GMR().predict([0.5])
    with pytest.raises(NotFittedError):
        GMR().path()


@pytest.mark.parametrize(
    ("demos", "match"),
    [
        ([np.array([[0.0, 0.0], [np.nan, 1.0], [2.0, 2.0]])], "NaN"),
        ([np.array([[0.0, 0.0], [np.inf, 1.0], [2.0, 2.0]])], "infinite"),
        ([np.zeros((5, 2)) + np.arange(5)[:, None], np.array([[0.0, 1.0]])], "at least 2"),
        (
            [np.random.default_rng(0).random((5, 2)), np.random.default_rng(1).random((5, 3))],
            r"demos\[1\]",
        ),
        (np.ones((4, 2)), "list"),
    ],
)
def test_bad_demos(demos, match):
    with pytest.raises(ValueError, match=match):
        GMR(n_components=1).fit(demos)


def test_bad_demos_type():
    with pytest.raises(TypeError, match="demos"):
        GMR(n_components=1).fit("not demos")


@pytest.mark.parametrize(
    ("params", "exc", "match"),
    [
        ({"n_components": 0}, ValueError, "n_components"),
        ({"n_components": 2.5}, TypeError, "n_components"),
        ({"n_components": 1000}, ValueError, "n_components"),
        ({"covariance_reg": -1.0}, ValueError, "covariance_reg"),
        ({"max_iter": 0}, ValueError, "max_iter"),
        ({"n_init": 0}, ValueError, "n_init"),
        ({"time_mode": "speed"}, ValueError, "time_mode"),
        ({"cov_mode": "bogus"}, ValueError, "cov_mode"),
        ({"random_state": "seed"}, TypeError, "seed"),
        ({"length_scale": 0.0}, ValueError, "length_scale"),
        ({"length_scale": float("inf")}, ValueError, "length_scale"),
    ],
)
def test_bad_parameters(params, exc, match):
    demos, _, _ = sine_demos(n_demos=2, n=20)
    with pytest.raises(exc, match=match):
        GMR(**params).fit(demos)


def test_times_must_match_demos():
    demos, t, _ = sine_demos(n_demos=2, n=20)
    with pytest.raises(ValueError, match="times"):
        GMR(n_components=2).fit(demos, times=[t])
    with pytest.raises(ValueError, match=r"times\[1\]"):
        GMR(n_components=2).fit(demos, times=[t, t[:-1]])
    with pytest.raises(ValueError, match=r"times\[0\]"):
        GMR(n_components=2).fit(demos, times=[np.where(t > 0.5, np.nan, t), t])


def test_bad_query_times(sine_model):
    model, _, _ = sine_model
    with pytest.raises(ValueError, match="t:"):
        model.predict([0.1, np.nan])
    with pytest.raises(ValueError, match="t:"):
        model.predict(np.zeros((2, 2)))
    with pytest.raises(ValueError, match="cov_mode"):
        model.predict([0.1], return_cov=True, cov_mode="nope")
    with pytest.raises(ValueError, match="n_points"):
        model.path(0)


def test_singular_covariance():
    # the demonstrator never moves: Σ_ss is exactly zero
    demos = [np.ones((10, 2)), np.ones((12, 2))]
    with pytest.raises(ValueError, match=r"singular covariance.*covariance_reg"):
        GMR(n_components=1, covariance_reg=0.0, random_state=0).fit(demos)
    # the default regularisation copes, and the path is the fixed point
    model = GMR(n_components=2, random_state=0).fit(demos)
    mean, cov = model.predict(np.linspace(0, 1, 5), return_cov=True)
    np.testing.assert_allclose(mean, 1.0, atol=1e-8)
    assert np.all(np.isfinite(cov))


def test_ladder_search_visits_a_ladder_and_warns_at_the_bound():
    demos, _, _ = sine_demos(n_demos=4, n=100, noise=0.02)
    with pytest.warns(ComponentLimitWarning, match="largest candidate, 3 components"):
        best, scores = select_n_components(demos, candidates=[1, 2, 3], random_state=0)
    assert best == 3
    # Twenty candidates: the coarse ladder 2, 3, 5, 8, 12, 18, 21, then a bracket search.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ComponentLimitWarning)
        best, scores = select_n_components(demos, candidates=range(2, 22), random_state=0)
    assert {2, 3, 5, 8, 12} <= set(scores)
    assert len(scores) < 20
    assert scores[best] == min(scores.values())


def test_compiled_em_agrees_with_scikit_learn():
    """The ladder's EM (compiled) is scikit-learn's iteration: same start, same mixture."""
    from sklearn.mixture import GaussianMixture

    from lfdkit.mimic.gmr import _em, _split_start

    demos, _, _ = sine_demos(n_demos=5, n=80, noise=0.02)
    model = GMR(n_components=3, random_state=0)
    _, _, data = model._samples(demos, None)
    gm = model._mixture(data, 0)
    start = _split_start(_Mixture(gm.weights_, gm.means_, gm.covariances_, 0.0), 5)
    ours = _em(data, start, reg=1e-6, tol=1e-4, max_iter=500)
    theirs = GaussianMixture(
        5,
        reg_covar=1e-6,
        tol=1e-4,
        max_iter=500,
        init_params="random_from_data",
        weights_init=start[0],
        means_init=start[1],
        precisions_init=np.linalg.inv(start[2]),
        random_state=0,
    ).fit(data)
    np.testing.assert_allclose(ours.means, theirs.means_, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(ours.covariances, theirs.covariances_, rtol=1e-6, atol=1e-12)
    assert ours.criterion("bic", len(data)) == pytest.approx(theirs.bic(data), rel=1e-9)
    assert ours.criterion("aic", len(data)) == pytest.approx(theirs.aic(data), rel=1e-9)


def test_select_n_components_errors():
    demos, _, _ = sine_demos(n_demos=2, n=20)
    with pytest.raises(ValueError, match="criterion"):
        select_n_components(demos, candidates=[2], criterion="e1")
    with pytest.raises(ValueError, match="search"):
        select_n_components(demos, candidates=[2], search="all")
    with pytest.raises(ValueError, match="patience"):
        select_n_components(demos, candidates=[2], patience=0)
    with pytest.raises(ValueError, match="candidates"):
        select_n_components(demos, candidates=[])
    with pytest.raises(ValueError, match="candidates"):
        select_n_components(demos, candidates=[500])
