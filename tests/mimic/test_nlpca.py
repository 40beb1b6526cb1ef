"""Tests for lfdkit.mimic.nlpca: auto-associative nonlinear PCA baseline."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from sklearn.exceptions import NotFittedError

from lfdkit.mimic.nlpca import NLPCA, _init_params, _loss_and_grad, _n_params


def arc_demos(n_demos=4, n=60, noise=0.01, seed=0, reverse=False):
    """Noisy quarter circles of radius 1 from (1, 0) to (0, 1)."""
    rng = np.random.default_rng(seed)
    demos = []
    for _ in range(n_demos):
        th = np.linspace(0.0, np.pi / 2, n)
        demo = np.c_[np.cos(th), np.sin(th)] + rng.normal(0, noise, (n, 2))
        demos.append(demo[::-1] if reverse else demo)
    return demos


@pytest.fixture(scope="module")
def arc_model():
    demos = arc_demos()
    return NLPCA(n_restarts=2, random_state=0).fit(demos), demos


# ------------------------------------------------------------- gradients
def finite_difference(theta, x, n_hidden, alpha, eps=1e-6):
    grad = np.empty_like(theta)
    for i in range(theta.size):
        e = np.zeros_like(theta)
        e[i] = eps
        grad[i] = (
            _loss_and_grad(theta + e, x, n_hidden, alpha)[0]
            - _loss_and_grad(theta - e, x, n_hidden, alpha)[0]
        ) / (2 * eps)
    return grad


@settings(max_examples=15, deadline=None)
@given(
    q=st.integers(1, 3),
    n_hidden=st.integers(1, 6),
    alpha=st.sampled_from([0.0, 1e-3, 0.5]),
    seed=st.integers(0, 2**31 - 1),
)
def test_gradient_matches_finite_differences(q, n_hidden, alpha, seed):
    rng = np.random.default_rng(seed)
    x = rng.normal(size=(17, q))
    theta = _init_params(q, n_hidden, rng) + rng.normal(0, 0.3, _n_params(q, n_hidden))
    loss, grad = _loss_and_grad(theta, x, n_hidden, alpha)
    assert grad.shape == theta.shape
    assert np.isfinite(loss)
    np.testing.assert_allclose(
        grad, finite_difference(theta, x, n_hidden, alpha), atol=1e-7, rtol=1e-5
    )


def test_loss_is_reconstruction_error_plus_weight_decay():
    rng = np.random.default_rng(0)
    q, h = 2, 3
    x = rng.normal(size=(10, q))
    theta = _init_params(q, h, rng)
    plain, _ = _loss_and_grad(theta, x, h, 0.0)
    with_decay, _ = _loss_and_grad(theta, x, h, 0.1)
    # weights are everything except the biases b1 (h), b2 (1), b3 (h), b4 (q)
    sizes = [h * q, h, h, 1, h, h, q * h, q]
    is_weight = np.concatenate(
        [np.full(s, w) for s, w in zip(sizes, [1, 0, 1, 0, 1, 0, 1, 0], strict=True)]
    )
    assert with_decay - plain == pytest.approx(0.1 * np.sum(theta[is_weight == 1] ** 2))
    # a zero network reconstructs every point as the origin
    zero, _ = _loss_and_grad(np.zeros_like(theta), x, h, 0.1)
    assert zero == pytest.approx(np.mean(np.sum(x**2, axis=1)))


# ------------------------------------------------------- behaviour on data
def test_recovers_quarter_circle(arc_model):
    model, _ = arc_model
    path = model.path_
    assert path.shape == (100, 2)
    # every path point lies on the unit arc ...
    assert np.max(np.abs(np.linalg.norm(path, axis=1) - 1.0)) < 0.05
    # ... the path covers the arc and runs from (1, 0) to (0, 1) monotonically
    angle = np.arctan2(path[:, 1], path[:, 0])
    assert np.all(np.diff(angle) > 0)
    assert angle[0] < 0.1 and angle[-1] > np.pi / 2 - 0.1
    np.testing.assert_allclose(path[0], [1.0, 0.0], atol=0.05)
    np.testing.assert_allclose(path[-1], [0.0, 1.0], atol=0.05)
    # the reconstruction error is at the noise level (2 · 0.01² per point)
    assert model.mse_ < 3 * 2 * 0.01**2
    assert model.n_iter_ > 0 and np.isfinite(model.loss_)


def test_scores_order_points_along_the_path(arc_model):
    model, demos = arc_model
    n = demos[0].shape[0]
    assert model.scores_.shape == (len(demos) * n,)
    np.testing.assert_allclose(model.scores_, model.transform(np.vstack(demos)))
    for j in range(len(demos)):
        scores = model.scores_[j * n : (j + 1) * n]
        rank = np.argsort(np.argsort(scores))
        assert np.corrcoef(rank, np.arange(n))[0, 1] > 0.99
    # decoding the training range reproduces path_
    z = np.linspace(model.scores_.min(), model.scores_.max(), 100)
    np.testing.assert_allclose(model.inverse_transform(z), model.path_)
    # points on the curve map back to themselves (encoder ∘ decoder ≈ id on the curve)
    np.testing.assert_allclose(
        model.inverse_transform(model.transform(model.path_)), model.path_, atol=0.02
    )
    assert model.inverse_transform(0.0).shape == (1, 2)


def test_orientation_follows_demonstrations():
    model = NLPCA(n_restarts=1, n_points=30, random_state=1).fit(arc_demos(reverse=True, seed=2))
    assert model.path_.shape == (30, 2)
    np.testing.assert_allclose(model.path_[0], [0.0, 1.0], atol=0.05)
    np.testing.assert_allclose(model.path_[-1], [1.0, 0.0], atol=0.05)


def test_seed_determinism(arc_model):
    model, demos = arc_model
    again = NLPCA(n_restarts=2, random_state=0).fit(demos)
    np.testing.assert_array_equal(again.path_, model.path_)
    np.testing.assert_array_equal(again.coefs_, model.coefs_)
    assert again.loss_ == model.loss_


def test_restarts_keep_lowest_loss():
    demos = arc_demos(n_demos=2, n=40, seed=3)
    # one shared Generator hands successive starts to successive single fits,
    # exactly as it does to the successive restarts of one fit
    rng = np.random.default_rng(11)
    single_losses = [
        NLPCA(n_restarts=1, max_iter=200, random_state=rng).fit(demos).loss_ for _ in range(3)
    ]
    multi = NLPCA(n_restarts=3, max_iter=200, random_state=np.random.default_rng(11)).fit(demos)
    assert multi.loss_ == pytest.approx(min(single_losses), rel=1e-12)


def test_per_dimension_scaling_and_one_dimension():
    model = NLPCA(n_restarts=1, scaling="per_dimension", random_state=0).fit(arc_demos(seed=4))
    assert np.max(np.abs(np.linalg.norm(model.path_, axis=1) - 1.0)) < 0.05
    # q = 1: the "curve" is the segment between the extreme points, start → end
    line = [np.linspace(0.0, 2.0, 30)[:, None], np.linspace(0.1, 1.9, 25)[:, None]]
    m1 = NLPCA(n_restarts=1, n_points=10, random_state=0).fit(line)
    assert m1.path_.shape == (10, 1)
    assert np.all(np.diff(m1.path_[:, 0]) > 0)
    assert m1.path_[0, 0] == pytest.approx(0.0, abs=0.05)
    assert m1.path_[-1, 0] == pytest.approx(2.0, abs=0.05)


# ------------------------------------------------------------------ errors
def test_not_fitted():
    with pytest.raises(NotFittedError):
        NLPCA().transform(np.zeros((3, 2)))
    with pytest.raises(NotFittedError):
        NLPCA().inverse_transform(np.zeros(3))


@pytest.mark.parametrize(
    ("params", "exc", "match"),
    [
        ({"n_hidden": 0}, ValueError, "n_hidden"),
        ({"n_hidden": 2.0}, TypeError, "n_hidden"),
        ({"alpha": -1.0}, ValueError, "alpha"),
        ({"alpha": float("nan")}, ValueError, "alpha"),
        ({"max_iter": 0}, ValueError, "max_iter"),
        ({"n_restarts": 0}, ValueError, "n_restarts"),
        ({"n_points": 1}, ValueError, "n_points"),
        ({"scaling": "minmax"}, ValueError, "scaling"),
        ({"random_state": 1.5}, TypeError, "seed"),
    ],
)
def test_bad_parameters(params, exc, match):
    with pytest.raises(exc, match=match):
        NLPCA(**params).fit(arc_demos(n_demos=1, n=10))


@pytest.mark.parametrize(
    ("demos", "match"),
    [
        ([np.array([[0.0, 0.0], [np.nan, 1.0], [2.0, 2.0]])], "NaN"),
        ([np.array([[0.0, 0.0]])], "at least 2"),
        (
            [np.random.default_rng(0).random((5, 2)), np.random.default_rng(1).random((5, 3))],
            r"demos\[1\]",
        ),
        ([np.ones((5, 2)), np.ones((4, 2))], "spread"),
    ],
)
def test_bad_demos(demos, match):
    with pytest.raises(ValueError, match=match):
        NLPCA(n_restarts=1, max_iter=5).fit(demos)


def test_bad_transform_inputs(arc_model):
    model, _ = arc_model
    with pytest.raises(ValueError, match="X"):
        model.transform(np.zeros((4, 3)))
    with pytest.raises(ValueError, match="X"):
        model.transform(np.array([[0.0, np.inf]]))
    with pytest.raises(ValueError, match="scores"):
        model.inverse_transform(np.array([0.0, np.nan]))
    with pytest.raises(ValueError, match="scores"):
        model.inverse_transform(np.zeros((2, 2)))
