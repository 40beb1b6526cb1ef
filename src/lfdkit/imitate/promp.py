"""Probabilistic movement primitive (ProMP): a Gaussian over paths, conditioned on via-points.

What: each demonstration, resampled to phase ``s`` in [0, 1] (sample index or
time, normalised), is fitted by ``n_basis`` normalised Gaussian bumps per
dimension (ridge least squares); the weight vectors of the demonstrations give
a Gaussian ``N(weights_mean_, weights_cov_)``. A path is ``y(s) = Ψ(s) w``, so
the model gives a mean path (:meth:`ProMP.timed_mean`: as a
:class:`~lfdkit.model.timed_path.TimedPath` of a given duration, velocities
exact), a band (``std``), samples, and — the reason it
exists — closed-form Gaussian conditioning on points the movement must pass
(Paraschos et al., 2013): with ``H`` the stacked ``Ψ(s_i)`` of all via-points,
``y`` their positions and ``R`` their covariances,

    K = Σ Hᵀ (H Σ Hᵀ + R)⁻¹,   μ' = μ + K (y − H μ),   Σ' = Σ − K H Σ.

Why this design:

- **Several via-points at once** (movement_primitives #21 asks for it): ``H``
  stacks all of them, one solve of size ``n_points · n_dims``; the result
  equals conditioning one after the other (a tested property).
- **Exact when asked**: ``covariance=0`` passes through the point wherever the
  demonstrations' spread reaches it. A point the spread cannot reach (the
  demonstrations never varied that way) is not silently missed: a warning says
  by how much the conditioned mean misses it and what to do.
- **Basis in linear phase, evenly spaced** (not the DMP's exponential phase of
  :mod:`._dmp_numerics`): a ProMP has no canonical system, and even spacing
  gives every part of the movement the same resolution. Width: the centre
  spacing unless given. Wider bumps fit a smooth path closer without a ridge
  but are spoiled by one (12 bumps on a sine and cosine: 1.5× spacing,
  residual 0.5 → 0.75 → 3 mm per metre for ridge 1e-8 → 1e-6 → 1e-4); at the
  spacing the residual stays 2.7 mm for all three.
- **Covariances are PSD but may be singular** (rank ``n_demos − 1`` at most):
  sampling uses an eigen-decomposition, conditioning a pseudo-inverse (eigen-
  values below 1e-10 of the largest dropped); the part of a via-point's offset
  in the dropped directions is what the model cannot reach, and is warned of.

Numbers: 10 basis functions × 3 dimensions is a 30 × 30 covariance; fitting
and conditioning cost well under a millisecond.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np

from lfdkit.core.constraints import Integer, Real
from lfdkit.core.estimator import Estimator, check_fitted
from lfdkit.core.validation import (
    check_count,
    check_demos,
    check_positive,
    check_random_state,
    check_times,
    check_values,
)
from lfdkit.model.timed_path import TimedPath

__all__ = ["ProMP"]

#: Most basis functions per dimension: beyond a few hundred the weight
#: covariance (``(n_basis · n_dims)²`` entries) outgrows any demonstration set.
MAX_PROMP_BASIS = 500

#: Relative cut of the pseudo-inverse in conditioning: singular values below
#: this fraction of the largest are directions the model cannot move in.
_PINV_RCOND = 1e-10


class ProMP(Estimator):
    """Probabilistic movement primitive: a Gaussian over basis weights, learned from demonstrations.

    Parameters
    ----------
    n_basis : int, default 10
        Gaussian basis functions per dimension, centres evenly spaced over the
        phase [0, 1].
    width : float, optional
        Standard deviation of each basis function, in phase units (0 < width
        <= 1). Default: the spacing of the centres, ``1 / (n_basis − 1)``.
    regularization : float, default 1e-6
        Ridge factor of each demonstration's weight fit, relative to the mean
        squared basis activation (dimensionless; 0 for plain least squares).

    Attributes
    ----------
    weights_mean_ : ndarray, shape (n_dims * n_basis,)
        Mean weight vector, dimension-major (the ``n_basis`` weights of
        dimension 0, then of dimension 1, ...), in the demonstrations' units.
    weights_cov_ : ndarray, shape (n_dims * n_basis, n_dims * n_basis)
        Covariance of the weights (unbiased over demonstrations), units².
    n_dims_ : int
        Dimensions of a point.
    n_demos_ : int
        Demonstrations fitted (for a conditioned model, those of its source).
    width_ : float
        Standard deviation of the basis functions used, in phase units.
    residual_rms_ : float
        Root-mean-square distance between the demonstrations and their own
        weight fits, in the demonstrations' units (how well the basis fits).

    Examples
    --------
    >>> import numpy as np
    >>> s = np.linspace(0, 1, 50)
    >>> demos = [np.c_[s, np.sin(np.pi * s) * a] for a in (0.8, 1.0, 1.2)]
    >>> model = ProMP(n_basis=8).fit(demos)
    >>> via = model.condition([[0.5, 1.1]], [0.5])
    >>> bool(np.allclose(via.mean_at([0.5]), [[0.5, 1.1]], atol=1e-6))
    True
    """

    _parameter_constraints: ClassVar[dict[str, Any]] = {
        "n_basis": Integer(minimum=2, maximum=MAX_PROMP_BASIS),
        "width": Real(maximum=1.0, meaning="a standard deviation in phase units", optional=True),
        "regularization": Real(allow_zero=True),
    }

    def __init__(
        self, n_basis: int = 10, width: float | None = None, regularization: float = 1e-6
    ) -> None:
        self.n_basis = n_basis
        self.width = width
        self.regularization = regularization

    # ------------------------------------------------------------------ fit
    def fit(self, demos: Any, times: Any = None) -> ProMP:
        """Learn the weight distribution from demonstrations.

        Parameters
        ----------
        demos : sequence of array_like, each shape (n_points_j, n_dims)
            At least 2 demonstrations (a spread needs two), of possibly
            different lengths, in any consistent length unit.
        times : sequence of array_like, each shape (n_points_j,), optional
            Sample times of each demonstration in seconds, strictly increasing;
            each is mapped linearly onto phase [0, 1]. Default: samples evenly
            spaced in phase.

        Returns
        -------
        self
        """
        params = self._validate_params()
        demos = check_demos(demos, min_dims=1)
        if len(demos) < 2:
            raise ValueError(
                f"demos: needs at least 2 demonstrations to learn their spread, got {len(demos)}"
            )
        if times is not None and len(times) != len(demos):
            raise ValueError(
                f"times: got {len(times)} time arrays for {len(demos)} demonstrations; "
                "give one per demonstration or None"
            )
        n_basis = params["n_basis"]
        self.width_ = params["width"] if params["width"] is not None else 1.0 / (n_basis - 1)
        n_dims = demos[0].shape[1]
        weights = np.empty((len(demos), n_dims * n_basis))
        squared_residual, n_total = 0.0, 0
        for j, demo in enumerate(demos):
            if times is None:
                phase = np.linspace(0.0, 1.0, len(demo))
            else:
                t = check_times(times[j], len(demo), f"times[{j}]", of=f"demos[{j}]")
                phase = (t - t[0]) / (t[-1] - t[0])
            features = self._features(phase)  # (n_points_j, n_basis)
            gram = features.T @ features
            # Ridge relative to the mean activation, so the factor means the same for any length.
            ridge = params["regularization"] * np.trace(gram) / n_basis
            coef = np.linalg.solve(gram + ridge * np.eye(n_basis), features.T @ demo)
            weights[j] = coef.T.reshape(-1)  # dimension-major
            squared_residual += float(np.sum((features @ coef - demo) ** 2))
            n_total += len(demo)
        self.weights_mean_ = weights.mean(axis=0)
        centred = weights - self.weights_mean_
        self.weights_cov_ = centred.T @ centred / (len(demos) - 1)
        self.n_dims_ = n_dims
        self.n_demos_ = len(demos)
        self.residual_rms_ = float(np.sqrt(squared_residual / n_total))
        return self

    # ------------------------------------------------------------ evaluation
    def mean_at(self, phases: Any) -> np.ndarray:
        """Mean position at given phases.

        Parameters
        ----------
        phases : array_like, shape (n,)
            Phases in [0, 1].

        Returns
        -------
        ndarray, shape (n, n_dims)
            In the demonstrations' units.
        """
        self._check_fitted()
        features = self._features(_check_phases(phases, "phases"))
        return features @ self.weights_mean_.reshape(self.n_dims_, self.n_basis).T

    def covariance_at(self, phases: Any) -> np.ndarray:
        """Covariance of the position at given phases.

        Parameters
        ----------
        phases : array_like, shape (n,)
            Phases in [0, 1].

        Returns
        -------
        ndarray, shape (n, n_dims, n_dims)
            In units².
        """
        self._check_fitted()
        features = self._features(_check_phases(phases, "phases"))
        d, b = self.n_dims_, self.n_basis
        blocks = self.weights_cov_.reshape(d, b, d, b)
        # Σ_y(s)[i, k] = φ(s)ᵀ Σ_w[i-block, k-block] φ(s)
        return np.einsum("nb,ibkc,nc->nik", features, blocks, features)

    def mean_path(self, n_points: int = 100) -> np.ndarray:
        """Mean path at ``n_points`` phases evenly spaced over [0, 1].

        Returns
        -------
        ndarray, shape (n_points, n_dims)
        """
        return self.mean_at(_even_phases(n_points))

    def timed_mean(self, duration: float, n_points: int = 100) -> TimedPath:
        """The mean path as a movement of ``duration`` seconds (phase linear in time).

        Parameters
        ----------
        duration : float
            Seconds the movement takes (> 0); time ``t`` is phase ``t / duration``.
        n_points : int, default 100
            Samples, evenly spaced in phase (and so in time).

        Returns
        -------
        TimedPath
            ``times`` (n_points,) in s from 0 to ``duration``; ``positions``
            (n_points, n_dims) as :meth:`mean_path`; ``velocities`` the exact
            derivative of the mean in time (units per second), so
            :meth:`TimedPath.sample` follows the model between the samples.
        """
        seconds = check_positive(duration, "duration")
        phases = _even_phases(n_points)
        positions = self.mean_at(phases)
        weights = self.weights_mean_.reshape(self.n_dims_, self.n_basis).T
        velocities = self._feature_slopes(phases) @ weights / seconds  # dy/dt = dy/ds · ds/dt
        return TimedPath(phases * seconds, positions, velocities)

    def std(self, n_points: int = 100) -> np.ndarray:
        """Standard deviation of each coordinate at ``n_points`` evenly spaced phases.

        Returns
        -------
        ndarray, shape (n_points, n_dims)
            In the demonstrations' units.
        """
        cov = self.covariance_at(_even_phases(n_points))
        return np.sqrt(np.clip(np.einsum("nii->ni", cov), 0.0, None))

    def sample(self, n_samples: int = 1, n_points: int = 100, seed: Any = None) -> np.ndarray:
        """Draw paths from the model.

        Parameters
        ----------
        n_samples : int
            Paths to draw.
        n_points : int
            Points per path, at evenly spaced phases over [0, 1].
        seed : None, int or numpy.random.Generator
            Randomness; the same seed gives the same paths.

        Returns
        -------
        ndarray, shape (n_samples, n_points, n_dims)
        """
        self._check_fitted()
        n_samples = check_count(n_samples, "n_samples")
        rng = check_random_state(seed)
        # Eigen-decomposition, not Cholesky: the covariance has rank n_demos − 1 at most.
        values, vectors = np.linalg.eigh(self.weights_cov_)
        root = vectors * np.sqrt(np.clip(values, 0.0, None))
        draws = self.weights_mean_ + rng.standard_normal((n_samples, len(values))) @ root.T
        features = self._features(_even_phases(n_points))
        w = draws.reshape(n_samples, self.n_dims_, self.n_basis)
        return np.einsum("pb,sdb->spd", features, w)

    # ----------------------------------------------------------- conditioning
    def condition(self, points: Any, phases: Any, covariance: Any = 0.0) -> ProMP:
        """A new ProMP conditioned to pass through one or several via-points.

        Parameters
        ----------
        points : array_like, shape (n_via, n_dims) or (n_dims,)
            Positions to pass, in the demonstrations' units.
        phases : array_like, shape (n_via,)
            Phase of each via-point, in [0, 1] (0 start, 1 end).
        covariance : float or array_like, default 0
            How closely to pass, units²: a variance for every coordinate, an
            ``(n_dims, n_dims)`` matrix for every point, or ``(n_via, n_dims,
            n_dims)``, one per point. 0 passes exactly (where the
            demonstrations' spread allows).

        Returns
        -------
        ProMP
            A fitted copy; this model is unchanged.

        Warns
        -----
        UserWarning
            If part of a via-point's offset from the mean lies where the model
            cannot move (more than 1e-6 of the points' scale): the
            demonstrations never varied that way, or exact via-points close
            in phase contradict each other. A covariance > 0 makes every
            point a compromise, never unreachable.
        """
        self._check_fitted()
        d = self.n_dims_
        pts = _check_points(points, d)
        s = _check_phases(phases, "phases")
        if len(s) != len(pts):
            raise ValueError(
                f"phases: got {len(s)} phases for {len(pts)} points; give one phase per point"
            )
        noise = _check_covariance(covariance, len(pts), d)
        observe = self._observation(s)  # (n_via·d, n_weights)
        mean, cov = self.weights_mean_, self.weights_cov_
        cov_observed = cov @ observe.T
        innovation = pts.reshape(-1) - observe @ mean
        # Pseudo-inverse by eigen-decomposition: the directions it drops are those
        # the model cannot move in, and what of the innovation lies there is missed.
        values, vectors = np.linalg.eigh(observe @ cov_observed + _block_diagonal(noise))
        kept = values > _PINV_RCOND * max(float(values.max()), np.finfo(float).tiny)
        inverse = (vectors[:, kept] / values[kept]) @ vectors[:, kept].T
        gain = cov_observed @ inverse
        # A copy without the constructor's signature inspection (a third of the call).
        new = type(self).__new__(type(self))
        new.__dict__.update(self.__dict__)
        new.width_ = self.width_
        new.weights_mean_ = mean + gain @ innovation
        new_cov = cov - gain @ cov_observed.T
        new.weights_cov_ = 0.5 * (new_cov + new_cov.T)
        new.n_dims_, new.n_demos_, new.residual_rms_ = d, self.n_demos_, self.residual_rms_
        lost = vectors[:, ~kept] @ (vectors[:, ~kept].T @ innovation)
        new._warn_unreachable(pts, s, lost.reshape(len(pts), d))
        return new

    # ---------------------------------------------------------------- state
    def to_state(self) -> dict[str, Any]:
        """The fitted state as plain data: parameters, the weights' mean and covariance.

        :meth:`from_state` restores it to the bit (the skill file stores it,
        :mod:`lfdkit.io.skill_file`).
        """
        self._check_fitted()
        return {
            "params": self.get_params(),
            "width": float(self.width_),
            "n_dims": int(self.n_dims_),
            "n_demos": int(self.n_demos_),
            "residual_rms": float(self.residual_rms_),
            "weights_mean": np.array(self.weights_mean_),
            "weights_cov": np.array(self.weights_cov_),
        }

    @classmethod
    def from_state(cls, state: Mapping[str, Any], where: str = "promp") -> ProMP:
        """The fitted ProMP of :meth:`to_state`, without refitting.

        Raises
        ------
        ValueError
            One line starting with ``where`` for a missing or malformed field.
        """
        keys = ("params", "width", "n_dims", "n_demos", "residual_rms")
        for key in (*keys, "weights_mean", "weights_cov"):
            if key not in state:
                raise ValueError(f"{where}.{key}: missing field")
        try:
            made = cls(**dict(state["params"]))
            made._validate_params()
        except (TypeError, ValueError) as exc:
            raise ValueError(f"{where}.params: {exc}") from None
        for key in keys[1:]:
            value = state[key]
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ValueError(f"{where}.{key}: expected a number, got {value!r}")
        n_dims = state["n_dims"]
        if not isinstance(n_dims, int) or not 1 <= n_dims <= 3:
            raise ValueError(f"{where}.n_dims: expected 1 to 3, got {n_dims!r}")
        if not 0.0 < state["width"] <= 1.0:
            raise ValueError(f"{where}.width: expected a value in (0, 1], got {state['width']!r}")
        n_weights = n_dims * made.n_basis
        mean = np.asarray(state["weights_mean"], dtype=np.float64)
        cov = np.asarray(state["weights_cov"], dtype=np.float64)
        if mean.shape != (n_weights,) or cov.shape != (n_weights, n_weights):
            raise ValueError(
                f"{where}: weights of shape {mean.shape} and {cov.shape}, expected "
                f"({n_weights},) and ({n_weights}, {n_weights}) for {n_dims} dimensions "
                f"of {made.n_basis} basis functions"
            )
        if not (np.all(np.isfinite(mean)) and np.all(np.isfinite(cov))):
            raise ValueError(f"{where}: weights contain NaN or infinite values")
        made.width_ = float(state["width"])
        made.n_dims_ = n_dims
        made.n_demos_ = int(state["n_demos"])
        made.residual_rms_ = float(state["residual_rms"])
        made.weights_mean_, made.weights_cov_ = mean, cov
        return made

    def scaled(self, factor: float) -> ProMP:
        """The same model with every length times ``factor`` (a change of units).

        Returns a fitted copy: weights' mean times ``factor``, covariance
        times ``factor²``, residual times ``factor``.
        """
        self._check_fitted()
        new = type(self).from_state(self.to_state())
        new.weights_mean_ = self.weights_mean_ * factor
        new.weights_cov_ = self.weights_cov_ * factor**2
        new.residual_rms_ = self.residual_rms_ * abs(factor)
        return new

    # -------------------------------------------------------------- helpers
    def _features(self, phase: np.ndarray) -> np.ndarray:
        """Normalised Gaussian activations, shape (n_points, n_basis)."""
        centres = np.linspace(0.0, 1.0, self.n_basis)
        bumps = np.exp(-0.5 * ((phase[:, None] - centres) / self.width_) ** 2)
        return bumps / bumps.sum(axis=1, keepdims=True)

    def _feature_slopes(self, phase: np.ndarray) -> np.ndarray:
        """Derivatives of :meth:`_features` in phase, shape (n_points, n_basis).

        With ``φ_i = b_i / Σ b`` and ``b_i' = g_i b_i``, ``g_i = −(s − c_i) / w²``:
        ``φ_i' = φ_i (g_i − Σ_j φ_j g_j)``.
        """
        centres = np.linspace(0.0, 1.0, self.n_basis)
        features = self._features(phase)
        slopes = -(phase[:, None] - centres) / self.width_**2
        return features * (slopes - np.sum(features * slopes, axis=1, keepdims=True))

    def _observation(self, phase: np.ndarray) -> np.ndarray:
        """Stacked ``Ψ(s)``: rows point-major then dimension, shape (n·n_dims, n_dims·n_basis)."""
        features = self._features(phase)
        d = self.n_dims_
        return np.einsum("nb,ik->nikb", features, np.eye(d)).reshape(len(phase) * d, -1)

    def _warn_unreachable(self, pts: np.ndarray, phase: np.ndarray, lost: np.ndarray) -> None:
        """Warn about the first via-point whose offset lies partly where the model cannot move."""
        scale = max(float(np.abs(pts).max()), 1.0)
        bad = np.flatnonzero(np.linalg.norm(lost, axis=1) > 1e-6 * scale)
        if bad.size:
            i = int(bad[0])
            miss = float(np.linalg.norm(self.mean_at(phase[i : i + 1])[0] - pts[i]))
            warnings.warn(
                f"points[{i}]: cannot be reached; the conditioned mean misses it by {miss:.3g}: "
                "the demonstrations never varied that way, or another via-point close in "
                "phase asks otherwise; add demonstrations that vary that way, move the "
                "points apart in phase, or give a covariance > 0",
                UserWarning,
                stacklevel=3,
            )

    def _check_fitted(self) -> None:
        check_fitted(self, "weights_cov_")


def _even_phases(n_points: Any) -> np.ndarray:
    return np.linspace(0.0, 1.0, check_count(n_points, "n_points", minimum=1))


def _check_phases(phases: Any, name: str) -> np.ndarray:
    """Phases as a 1-D array, each in [0, 1]; one-line error naming the first outside."""
    s = check_values(phases, name)
    outside = np.flatnonzero((s < 0.0) | (s > 1.0))
    if outside.size:
        i = int(outside[0])
        raise ValueError(
            f"{name}: expected phases in [0, 1], got {s[i]:g} at index {i}; "
            "give each as a fraction of the movement (0 start, 1 end)"
        )
    return s


def _check_points(points: Any, n_dims: int) -> np.ndarray:
    try:
        arr = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError("points: expected a numeric array of shape (n_via, n_dims)") from exc
    if arr.ndim == 1:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[0] == 0:
        raise ValueError(f"points: expected shape (n_via, {n_dims}), got {arr.shape}")
    if arr.shape[1] != n_dims:
        raise ValueError(
            f"points: expected {n_dims} coordinates per point (the model's dimensions), "
            f"got {arr.shape[1]}"
        )
    if not np.all(np.isfinite(arr)):
        raise ValueError("points: contains NaN or an infinite value")
    return arr


def _check_covariance(covariance: Any, n_via: int, n_dims: int) -> np.ndarray:
    """Per-point covariances, shape (n_via, n_dims, n_dims), symmetric PSD."""
    try:
        arr = np.asarray(covariance, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError("covariance: expected a number or a numeric array") from exc
    if arr.ndim == 0:  # a variance: the one check it needs (most calls)
        variance = float(arr)
        if not math.isfinite(variance):
            raise ValueError("covariance: contains NaN or an infinite value")
        if variance < 0.0:
            raise ValueError(
                f"covariance: must be positive semi-definite (a variance is >= 0), got {variance!r}"
            )
        return np.broadcast_to(variance * np.eye(n_dims), (n_via, n_dims, n_dims))
    elif arr.shape == (n_dims, n_dims):
        arr = np.broadcast_to(arr, (n_via, n_dims, n_dims))
    elif arr.shape != (n_via, n_dims, n_dims):
        raise ValueError(
            f"covariance: expected a variance, shape ({n_dims}, {n_dims}) or "
            f"({n_via}, {n_dims}, {n_dims}), got shape {arr.shape}"
        )
    if not np.all(np.isfinite(arr)):
        raise ValueError("covariance: contains NaN or an infinite value")
    if not np.allclose(arr, np.swapaxes(arr, 1, 2)):
        raise ValueError("covariance: must be symmetric")
    if np.linalg.eigvalsh(arr).min() < -1e-12 * max(1.0, float(np.abs(arr).max())):
        raise ValueError("covariance: must be positive semi-definite (a variance is >= 0)")
    return np.array(arr)


def _block_diagonal(blocks: np.ndarray) -> np.ndarray:
    n, d, _ = blocks.shape
    out = np.zeros((n * d, n * d))
    for i in range(n):
        out[i * d : (i + 1) * d, i * d : (i + 1) * d] = blocks[i]
    return out
