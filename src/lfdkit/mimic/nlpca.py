"""Nonlinear PCA by an auto-associative neural network (thesis baseline, §1c).

Kramer (1991) / Scholz (2005): a network ``q → h → 1 → h → q`` is trained to
reproduce its input through a one-unit bottleneck. The encoder half
(``q → h`` tanh, ``h → 1`` linear) maps a point to a scalar *score*; the
decoder half (``1 → h`` tanh, ``h → q`` linear) maps a score back to a point,
so decoding an interval of scores traces a curve: the nonlinear first
principal component, used here as a generalized path of the demonstrations.
With a single bottleneck unit the hierarchical NLPCA of Scholz reduces to this
plain auto-associative network.

Training minimises the mean squared reconstruction error of the scaled data
plus a weight-decay penalty,

    L(θ) = (1/N) Σ_n ‖x̂_n − x_n‖² + α Σ_layers ‖W‖²_F

(biases are not penalised), with analytic gradients and L-BFGS-B, from several
random starts; the start with the lowest final loss is kept.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

import numpy as np

from lfdkit.core.constraints import Integer, OneOf, Real
from lfdkit.core.estimator import Estimator, check_fitted
from lfdkit.core.threads import one_blas_thread
from lfdkit.core.validation import (
    check_demos,
    check_path,
    check_random_state,
    check_values,
)
from lfdkit.mimic.base import MimicMethod, register
from lfdkit.mimic.orientation import check_one_motion, orient_demos

__all__ = ["NLPCA"]

Scaling = Literal["isotropic", "per_dimension"]
_SCALINGS = ("isotropic", "per_dimension")
#: Caps on sizes a caller gives, so that a typo is an error, not a MemoryError.
_MAX_HIDDEN = 1000
_MAX_RESTARTS = 1000


# ---------------------------------------------------------------- network
def _n_params(n_in: int, n_hidden: int) -> int:
    """Number of weights and biases of the ``q → h → 1 → h → q`` network."""
    q, h = n_in, n_hidden
    return (h * q + h) + (h + 1) + (h + h) + (q * h + q)


def _unpack(theta: np.ndarray, n_in: int, n_hidden: int) -> tuple[np.ndarray, ...]:
    """Split the flat parameter vector into ``W1, b1, W2, b2, W3, b3, W4, b4``.

    Shapes: ``W1 (h, q)``, ``b1 (h,)``, ``W2 (1, h)``, ``b2 (1,)``,
    ``W3 (h, 1)``, ``b3 (h,)``, ``W4 (q, h)``, ``b4 (q,)``.
    """
    q, h = n_in, n_hidden
    shapes = [(h, q), (h,), (1, h), (1,), (h, 1), (h,), (q, h), (q,)]
    out = []
    i = 0
    for shape in shapes:
        size = int(np.prod(shape))
        out.append(theta[i : i + size].reshape(shape))
        i += size
    return tuple(out)


def _encode(params: tuple[np.ndarray, ...], x: np.ndarray) -> np.ndarray:
    """Scores of scaled points ``x`` (N, q) → (N,)."""
    w1, b1, w2, b2 = params[:4]
    return (np.tanh(x @ w1.T + b1) @ w2.T + b2)[:, 0]


def _decode(params: tuple[np.ndarray, ...], z: np.ndarray) -> np.ndarray:
    """Scaled points from scores ``z`` (N,) → (N, q)."""
    w3, b3, w4, b4 = params[4:]
    return np.tanh(z[:, None] @ w3.T + b3) @ w4.T + b4


def _loss_and_grad(
    theta: np.ndarray, x: np.ndarray, n_hidden: int, alpha: float
) -> tuple[float, np.ndarray]:
    """Loss ``(1/N) Σ‖x̂ − x‖² + α Σ‖W‖²`` and its gradient with respect to ``theta``.

    Parameters
    ----------
    theta : ndarray, shape (P,)
        Flat parameters (see ``_unpack``).
    x : ndarray, shape (N, q)
        Scaled training points.
    n_hidden : int
        Hidden units per tanh layer.
    alpha : float
        Weight-decay coefficient.

    Returns
    -------
    loss : float
    grad : ndarray, shape (P,)
    """
    n, q = x.shape
    w1, b1, w2, b2, w3, b3, w4, b4 = _unpack(theta, q, n_hidden)
    # forward
    h1 = np.tanh(x @ w1.T + b1)  # (N, h)
    z = h1 @ w2.T + b2  # (N, 1)
    h3 = np.tanh(z @ w3.T + b3)  # (N, h)
    y = h3 @ w4.T + b4  # (N, q)
    err = y - x
    decay = float(np.sum(w1**2) + np.sum(w2**2) + np.sum(w3**2) + np.sum(w4**2))
    loss = float(np.sum(err**2)) / n + alpha * decay
    # backward
    d_y = (2.0 / n) * err  # (N, q)
    g_w4 = d_y.T @ h3 + 2.0 * alpha * w4
    g_b4 = d_y.sum(axis=0)
    d_a3 = (d_y @ w4) * (1.0 - h3**2)  # (N, h)
    g_w3 = d_a3.T @ z + 2.0 * alpha * w3
    g_b3 = d_a3.sum(axis=0)
    d_z = d_a3 @ w3  # (N, 1)
    g_w2 = d_z.T @ h1 + 2.0 * alpha * w2
    g_b2 = d_z.sum(axis=0)
    d_a1 = (d_z @ w2) * (1.0 - h1**2)  # (N, h)
    g_w1 = d_a1.T @ x + 2.0 * alpha * w1
    g_b1 = d_a1.sum(axis=0)
    grad = np.concatenate([g.ravel() for g in (g_w1, g_b1, g_w2, g_b2, g_w3, g_b3, g_w4, g_b4)])
    return loss, grad


def _init_params(n_in: int, n_hidden: int, rng: np.random.Generator) -> np.ndarray:
    """Random start: weights ~ N(0, 1/fan_in), biases small."""
    q, h = n_in, n_hidden
    parts = [
        rng.normal(0.0, 1.0 / np.sqrt(q), (h, q)),
        rng.normal(0.0, 0.1, h),
        rng.normal(0.0, 1.0 / np.sqrt(h), (1, h)),
        np.zeros(1),
        rng.normal(0.0, 1.0, (h, 1)),
        rng.normal(0.0, 0.1, h),
        rng.normal(0.0, 1.0 / np.sqrt(h), (q, h)),
        np.zeros(q),
    ]
    return np.concatenate([p.ravel() for p in parts])


class NLPCA(Estimator):
    """Nonlinear first principal component by an auto-associative network.

    Parameters
    ----------
    n_hidden : int, default 10
        Units in each of the two tanh hidden layers (at most 1000).
    alpha : float, default 1e-3
        Weight-decay coefficient (non-negative); larger values give a smoother,
        flatter curve.
    max_iter : int, default 2000
        Maximum L-BFGS-B iterations per restart.
    n_restarts : int, default 3
        Number of random initialisations; the lowest final loss is kept.
    n_points : int, default 100
        Number of samples in ``path_`` (2 to 1,000,000).
    scaling : {"isotropic", "per_dimension"}, default "isotropic"
        Input standardisation. ``"isotropic"`` centres the data and divides
        every coordinate by one common scale (the RMS distance to the
        centroid), which keeps the geometry, so the loss is the Euclidean
        squared distance; ``"per_dimension"`` is the classical z-score of each
        coordinate (it stretches thin directions, e.g. the noise across a
        nearly straight path).
    random_state : None, int or numpy.random.Generator, default None
        Seed for the random initialisations.
    orient : {"auto", "as_given"}, default "auto"
        ``"auto"``: demonstrations recorded against the majority's direction
        are reversed before their first and last points orient ``path_``
        (:func:`lfdkit.mimic.orient_demos`); ``"as_given"``: trust them.
        Either way a path shorter than 0.3 times the median demonstration is
        refused (:func:`lfdkit.mimic.check_one_motion`).

    Attributes
    ----------
    path_ : ndarray, shape (n_points, q)
        Decoded curve for scores ``linspace(min, max)`` of the training
        scores, oriented to run from the demonstrations' start (mean of their
        first points) to their end (mean of their last points).
    scores_ : ndarray, shape (N,)
        Score of every training point (demonstrations stacked in order);
        increasing score runs from start to end.
    loss_ : float
        Final training loss of the kept restart (scaled units, weight decay
        included).
    mse_ : float
        Mean squared reconstruction distance of the training points, in the
        original squared length units.
    n_iter_ : int
        L-BFGS-B iterations of the kept restart.
    converged_ : bool
        Whether the kept restart's optimiser reported success.
    n_dims_ : int
        Spatial dimension ``q``.
    reversed_ : ndarray of bool, shape (n_demos,)
        Which demonstrations were reversed to orient ``path_``.
    mean_ : ndarray, shape (q,)
        Centre subtracted before the network.
    scale_ : ndarray, shape (q,)
        Divisor applied after centring.
    coefs_ : ndarray, shape (P,)
        Flat network parameters (``W1, b1, W2, b2, W3, b3, W4, b4``).
    """

    _parameter_constraints: ClassVar[dict[str, Any]] = {
        "n_hidden": Integer(maximum=_MAX_HIDDEN),
        "alpha": Real(allow_zero=True),
        "max_iter": Integer(),
        "n_restarts": Integer(maximum=_MAX_RESTARTS),
        "n_points": Integer(minimum=2),  # at most MAX_POINTS
        "orient": OneOf(("auto", "as_given")),
        "scaling": OneOf(_SCALINGS),
    }

    def __init__(
        self,
        n_hidden: int = 10,
        alpha: float = 1e-3,
        max_iter: int = 2000,
        n_restarts: int = 3,
        n_points: int = 100,
        scaling: Scaling = "isotropic",
        random_state: Any = None,
        orient: Literal["auto", "as_given"] = "auto",
    ) -> None:
        self.n_hidden = n_hidden
        self.alpha = alpha
        self.max_iter = max_iter
        self.n_restarts = n_restarts
        self.n_points = n_points
        self.scaling = scaling
        self.random_state = random_state
        self.orient = orient

    def fit(self, demos: Any, *, check_input: bool = True) -> NLPCA:
        """Train the network on all points of all demonstrations.

        Parameters
        ----------
        demos : list of array_like, each shape (n_i, q)
            Demonstrations, possibly of different lengths, sharing ``q >= 1``.
            Point order inside a demonstration only matters for its first and
            last point, which orient ``path_``.
        check_input : bool
            False: ``demos`` are already validated (finite float64 arrays of one dimension), e.g. by
            :meth:`lfdkit.skill.Skill.fit_path`, and are not checked again.

        Returns
        -------
        self : NLPCA
        """
        params = self._validate_params()
        n_hidden, alpha, max_iter = params["n_hidden"], params["alpha"], params["max_iter"]
        n_restarts, n_points = params["n_restarts"], params["n_points"]
        rng = check_random_state(self.random_state)

        demos = check_demos(demos, "demos", min_dims=1) if check_input else list(demos)
        # The network sees the point cloud in the recorded order (scores_ follows it);
        # only the end points that orient the path need the common direction.
        data = np.vstack(demos)
        self.reversed_ = np.zeros(len(demos), dtype=bool)
        oriented = demos
        if self.orient == "auto":
            oriented, self.reversed_ = orient_demos(demos, method="NLPCA")
        q = data.shape[1]
        mean = data.mean(axis=0)
        centred = data - mean
        if self.scaling == "isotropic":
            rms = float(np.sqrt(np.mean(np.sum(centred**2, axis=1))))
            scale = np.full(q, rms)
        else:
            scale = centred.std(axis=0)
        if not np.all(scale > 0.0):
            raise ValueError(
                "demos: the points do not spread (zero variance"
                + (" in some coordinate" if self.scaling == "per_dimension" else "")
                + "); nonlinear PCA needs a point cloud with extent"
            )
        x = centred / scale

        # Small dense products (N x h): BLAS threads only add overhead here.
        with one_blas_thread():
            best = self._optimise(x, q, n_hidden, alpha, max_iter, n_restarts, rng)
        assert best is not None
        theta = np.asarray(best.x, dtype=np.float64).copy()

        self.n_dims_ = q
        self.mean_ = mean
        self.scale_ = scale
        self.coefs_ = theta
        self.loss_ = float(best.fun)
        self.n_iter_ = int(best.nit)
        self.converged_ = bool(best.success)

        # Orient: increasing score must run from the demos' start to their end.
        start = np.mean([d[0] for d in oriented], axis=0)
        end = np.mean([d[-1] for d in oriented], axis=0)
        scores = self.transform(data)
        path = self.inverse_transform(np.linspace(scores.min(), scores.max(), n_points))
        forward = np.linalg.norm(path[0] - start) + np.linalg.norm(path[-1] - end)
        backward = np.linalg.norm(path[-1] - start) + np.linalg.norm(path[0] - end)
        if backward < forward:
            # Negate the bottleneck: z → −z with an unchanged decoded curve.
            params = _unpack(self.coefs_, q, n_hidden)  # views into coefs_
            params[2][...] *= -1.0  # W2
            params[3][...] *= -1.0  # b2
            params[4][...] *= -1.0  # W3
            scores = self.transform(data)
            path = self.inverse_transform(np.linspace(scores.min(), scores.max(), n_points))
        self.length_ratio_ = check_one_motion(path, demos, "NLPCA")
        self.scores_ = scores
        self.path_ = path
        recon = self.inverse_transform(scores)
        self.mse_ = float(np.mean(np.sum((recon - data) ** 2, axis=1)))
        return self

    @staticmethod
    def _optimise(
        x: np.ndarray,
        q: int,
        n_hidden: int,
        alpha: float,
        max_iter: int,
        n_restarts: int,
        rng: np.random.Generator,
    ) -> Any:
        """Run L-BFGS-B from ``n_restarts`` random starts; return the best result."""
        from scipy.optimize import minimize  # imported here: lfdkit.mimic loads fast

        best = None
        for _ in range(n_restarts):
            theta0 = _init_params(q, n_hidden, rng)
            res = minimize(
                _loss_and_grad,
                theta0,
                args=(x, n_hidden, alpha),
                jac=True,
                method="L-BFGS-B",
                options={"maxiter": max_iter},
            )
            if best is None or res.fun < best.fun:
                best = res
        return best

    def _params(self) -> tuple[np.ndarray, ...]:
        return _unpack(self.coefs_, self.n_dims_, self.n_hidden)

    def transform(self, X: Any) -> np.ndarray:
        """Score (position along the curve) of each point.

        Parameters
        ----------
        X : array_like, shape (n, q)
            Points in the demonstrations' length units.

        Returns
        -------
        ndarray, shape (n,)
            Scores (dimensionless); increasing from start to end.
        """
        check_fitted(self, ("coefs_", "mean_", "scale_"))
        arr = check_path(X, "X", min_points=1, n_dims=self.n_dims_)
        return _encode(self._params(), (arr - self.mean_) / self.scale_)

    def inverse_transform(self, scores: Any) -> np.ndarray:
        """Points on the curve for given scores.

        Parameters
        ----------
        scores : array_like, shape (n,)
            Scores (a scalar is read as one score).

        Returns
        -------
        ndarray, shape (n, q)
            Points in the demonstrations' length units.
        """
        check_fitted(self, ("coefs_", "mean_", "scale_"))
        z = check_values(scores, "scores")
        return _decode(self._params(), z) * self.scale_ + self.mean_

    def fit_transform(self, demos: Any) -> np.ndarray:
        """Fit and return ``scores_`` (shape ``(N,)``, all demos stacked)."""
        return self.fit(demos).scores_


register(
    MimicMethod(
        key="nlpca",
        label="NLPCA",
        color="#2ca02c",
        build=lambda settings: NLPCA(
            n_points=settings.n_points, random_state=settings.random_state
        ),
        diagnostics=lambda fitted: {
            "loss": float(fitted.loss_),
            "converged": bool(fitted.converged_),
            "n_iter": int(fitted.n_iter_),
        },
        uses=("n_points", "random_state"),
        check_input=True,
    )
)
