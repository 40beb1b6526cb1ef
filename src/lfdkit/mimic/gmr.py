"""Gaussian mixture model / Gaussian mixture regression (thesis §3.2).

A time-indexed generalized path: every demonstration point becomes a sample
``(t, s)`` of a scalar phase ``t`` and a spatial vector ``s``. A ``K``-component
Gaussian mixture is fitted to the joint samples by EM (k-means initialisation,
stopping when the log-likelihood stops improving), and the path is recovered
by conditioning the mixture on ``t`` (Gaussian mixture regression):

* per component ``k``::

      ŝ_k(t) = μ_s,k + Σ_st,k Σ_tt,k⁻¹ (t − μ_t,k)
      Σ̂_k    = Σ_ss,k − Σ_st,k Σ_tt,k⁻¹ Σ_ts,k

  (standard Gaussian conditioning; the thesis prints a minus sign in ``ŝ_k``,
  which is a typo);
* responsibilities ``β_k(t) ∝ π_k N(t; μ_t,k, Σ_tt,k)``, evaluated in log
  space so that they never underflow, even far from every component;
* mean ``ŝ(t) = Σ_k β_k ŝ_k`` and covariance ``Σ_k β_k² Σ̂_k`` (thesis
  eq. 3.4), or, with ``cov_mode="law_of_total_covariance"``, the exact
  covariance of the conditional mixture
  ``Σ_k β_k (Σ̂_k + (ŝ_k − ŝ)(ŝ_k − ŝ)ᵀ)``.

The covariance along the path shows where the task is constrained (small)
and where it is free (large).
"""

from __future__ import annotations

import itertools
import warnings
from collections.abc import Iterable
from typing import Any, ClassVar, Literal, NamedTuple

import numpy as np

from lfdkit.core.constraints import Integer, OneOf, Real
from lfdkit.core.estimator import Estimator, check_fitted
from lfdkit.core.threads import one_blas_thread
from lfdkit.core.validation import (
    check_count,
    check_demos,
    check_positive,
    check_random_state,
    check_times_list,
    check_values,
)
from lfdkit.mimic.base import MimicMethod, register
from lfdkit.mimic.orientation import check_one_motion, orient_demos

__all__ = ["GMR", "ComponentLimitWarning", "select_n_components"]

TimeMode = Literal["index", "arclength"]
CovMode = Literal["thesis", "law_of_total_covariance"]

_TIME_MODES = ("index", "arclength")
_COV_MODES = ("thesis", "law_of_total_covariance")
_LOG_2PI = float(np.log(2.0 * np.pi))
#: Caps on sizes a caller gives, so that a typo is an error, not a MemoryError.
_MAX_COMPONENTS = 1000
_MAX_INIT = 1000
#: Samples of the path whose length is compared with the demonstrations'.
_LENGTH_CHECK_POINTS = 200


def _phase(demo: np.ndarray, time_mode: str) -> np.ndarray:
    """Phase in [0, 1] for each sample of one demonstration, shape ``(n_i,)``."""
    n = demo.shape[0]
    if time_mode == "arclength":
        seg = np.linalg.norm(np.diff(demo, axis=0), axis=1)
        total = seg.sum()
        if total > 0.0:
            return np.concatenate(([0.0], np.cumsum(seg))) / total
        # A demonstration that never moves has no arc length: fall back to
        # equal steps rather than dividing by zero.
    return np.linspace(0.0, 1.0, n)


def _sklearn_seed(random_state: Any) -> int:
    """An int seed for scikit-learn from ``None``, an int or a ``Generator``."""
    if isinstance(random_state, (int, np.integer)) and not isinstance(random_state, bool):
        if random_state < 0:
            raise ValueError(f"random_state: must be >= 0, got {random_state}")
        return int(random_state) % (2**32)
    rng = check_random_state(random_state)
    return int(rng.integers(0, 2**32 - 1))


class GMR(Estimator):
    """Generalized path by Gaussian mixture model / regression (thesis §3.2).

    Parameters
    ----------
    n_components : int, default 10
        Number of Gaussian components ``K`` (at most 1000).
    covariance_reg : float, default 1e-6
        Non-negative value added to the diagonal of every covariance during EM
        (scikit-learn's ``reg_covar``): squared phase units, and squared
        ``length_scale`` units for the positions. Raise it when the data are
        degenerate (for example, a demonstration that stands still).
    max_iter : int, default 500
        Maximum number of EM iterations per initialisation.
    tol : float, default 1e-4
        EM stops when the gain in mean per-sample log-likelihood falls below
        ``tol``.
    n_init : int, default 1
        Number of k-means/EM initialisations; the best likelihood is kept.
    random_state : None, int or numpy.random.Generator, default None
        Seed for k-means initialisation. An int gives reproducible fits.
    time_mode : {"index", "arclength"}, default "index"
        Phase given to each demonstration when ``fit`` gets no ``times``:
        ``"index"`` gives equal steps ``linspace(0, 1, n_i)`` (the thesis
        rescales each demonstration to the same number of points);
        ``"arclength"`` gives the normalised cumulative arc length, which
        ignores how fast the demonstrator moved.
    cov_mode : {"thesis", "law_of_total_covariance"}, default "thesis"
        Covariance returned by ``predict(..., return_cov=True)``:
        ``"thesis"`` is ``Σ_k β_k² Σ̂_k`` (eq. 3.4); ``"law_of_total_covariance"``
        is the exact covariance of the conditional mixture,
        ``Σ_k β_k (Σ̂_k + (ŝ_k − ŝ)(ŝ_k − ŝ)ᵀ)``, which is the statistically
        proper choice (it never shrinks below the within-component spread and
        grows where components disagree).
    orient : {"auto", "as_given"}, default "auto"
        ``"auto"``: reverse demonstrations recorded against the majority's
        direction before fitting (:func:`lfdkit.mimic.orient_demos`; not when
        ``fit`` is given ``times``, which say which way each one runs).
        ``"as_given"``: trust the recorded directions. Either way a path
        shorter than 0.3 times the median demonstration is refused
        (:func:`lfdkit.mimic.check_one_motion`).
    n_points : int, default 100
        Points of :attr:`path_`.
    length_scale : float, default 1.0
        The unit of length EM works in, in the demonstrations' units: the
        positions are divided by it before fitting and every fitted quantity
        is converted back. A mixture of phase and position is not
        scale-invariant (``covariance_reg`` and the k-means initialisation
        weigh the phase against the positions), so the same demonstrations
        in metres and in millimetres give the same path only when EM sees
        them in one unit: :class:`lfdkit.skill.Skill` passes one metre in
        its units (1000 for millimetres). The default fits the data as given.

    Attributes
    ----------
    weights_ : ndarray, shape (K,)
        Mixing weights ``π_k``.
    means_ : ndarray, shape (K, 1 + q)
        Component means; column 0 is the phase, columns ``1:`` the position.
    covariances_ : ndarray, shape (K, 1 + q, 1 + q)
        Full component covariances, ordered like ``means_``.
    n_dims_ : int
        Number of spatial dimensions ``q``.
    time_range_ : tuple of float
        Smallest and largest training phase; ``path`` samples this range
        (``(0.0, 1.0)`` unless ``times`` were given).
    log_likelihood_ : float
        Mean per-sample log-likelihood of the training samples.
    converged_ : bool
        Whether EM converged within ``max_iter`` iterations.
    n_iter_ : int
        EM iterations used by the best initialisation.
    bic_, aic_ : float
        Bayesian / Akaike information criterion on the training samples
        (smaller is better).
    n_samples_ : int
        Number of ``(t, s)`` samples the mixture was fitted to.
    reversed_ : ndarray of bool, shape (n_demos,)
        Which demonstrations were reversed before fitting.
    path_ : ndarray, shape (n_points, q)
        ``path(n_points)``, the generalized path (:mod:`lfdkit.mimic.base`).
    length_ratio_ : float
        Its length over the median demonstration's.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 1, 50)
    >>> demos = [np.c_[t, np.sin(np.pi * t) + 0.01 * k] for k in range(3)]
    >>> gmr = GMR(n_components=4, random_state=0).fit(demos)
    >>> gmr.path(20).shape
    (20, 2)
    """

    _parameter_constraints: ClassVar[dict[str, Any]] = {
        "n_components": Integer(maximum=_MAX_COMPONENTS),
        "n_points": Integer(minimum=2),  # at most MAX_POINTS
        "covariance_reg": Real(allow_zero=True),
        "max_iter": Integer(),
        "tol": Real(allow_zero=True),
        "n_init": Integer(maximum=_MAX_INIT),
        "length_scale": Real(),
        "time_mode": OneOf(_TIME_MODES),
        "cov_mode": OneOf(_COV_MODES),
        "orient": OneOf(("auto", "as_given")),
    }

    def __init__(
        self,
        n_components: int = 10,
        covariance_reg: float = 1e-6,
        max_iter: int = 500,
        tol: float = 1e-4,
        n_init: int = 1,
        random_state: Any = None,
        time_mode: TimeMode = "index",
        cov_mode: CovMode = "thesis",
        orient: Literal["auto", "as_given"] = "auto",
        n_points: int = 100,
        length_scale: float = 1.0,
    ) -> None:
        self.n_components = n_components
        self.covariance_reg = covariance_reg
        self.max_iter = max_iter
        self.tol = tol
        self.n_init = n_init
        self.random_state = random_state
        self.time_mode = time_mode
        self.cov_mode = cov_mode
        self.orient = orient
        self.n_points = n_points
        self.length_scale = length_scale

    # ------------------------------------------------------------------ fit
    def fit(self, demos: Any, times: Any = None, *, check_input: bool = True) -> GMR:
        """Fit the joint mixture of phase and position.

        Parameters
        ----------
        demos : list of array_like, each shape (n_i, q)
            Demonstrations, possibly of different lengths, in any consistent
            length unit; all share the spatial dimension ``q >= 1``.
        times : list of array_like, each shape (n_i,), optional
            Phase (or time, in any unit) of every sample. When omitted each
            demonstration gets a phase in ``[0, 1]`` chosen by ``time_mode``.
        check_input : bool
            False: ``demos`` (finite float64 arrays of one dimension) and
            ``times`` (one finite 1-D array per demonstration, or None) are
            already validated, e.g. by :meth:`lfdkit.skill.Skill.fit_path`, and
            are not checked again.

        Returns
        -------
        self : GMR

        Raises
        ------
        ValueError
            On NaN/inf, a demonstration with fewer than 2 points, mixed
            dimensions, ``times`` that do not match ``demos``, ``n_components``
            larger than the number of samples, or a singular covariance that
            ``covariance_reg`` does not cure.
        """
        self._validate_params()
        if check_input:
            demos = check_demos(demos, "demos", min_dims=1)
            if times is not None:
                times = check_times_list(
                    times, demos, missing=False, increasing=False, style="shape"
                )
        demos, self.reversed_, data = self._samples(demos, times)
        gm = self._mixture(data, _sklearn_seed(self.random_state))
        n_samples, q = data.shape[0], int(data.shape[1] - 1)
        # Back to the demonstrations' units: positions times the scale, and the
        # density of the positions divided by scale**q.
        to_data = np.concatenate(([1.0], np.full(q, float(self.length_scale))))
        self.weights_ = np.asarray(gm.weights_, dtype=np.float64)
        self.means_ = np.asarray(gm.means_, dtype=np.float64) * to_data
        self.covariances_ = (
            np.asarray(gm.covariances_, dtype=np.float64) * to_data[:, None] * to_data[None, :]
        )
        self.n_dims_ = q
        self.n_samples_ = int(n_samples)
        self.time_range_ = (float(data[:, 0].min()), float(data[:, 0].max()))
        log_scale = self._log_scale(q)
        self.log_likelihood_ = float(gm.score(data) - log_scale)
        self.converged_ = bool(gm.converged_)
        self.n_iter_ = int(gm.n_iter_)
        self.bic_ = float(gm.bic(data) + 2.0 * n_samples * log_scale)
        self.aic_ = float(gm.aic(data) + 2.0 * n_samples * log_scale)
        self.length_ratio_ = check_one_motion(
            self.path(_LENGTH_CHECK_POINTS), demos, "GMR", times=times
        )
        self.path_ = self.path(self.n_points)
        return self

    def fit_mixture(self, samples: np.ndarray, start: tuple[np.ndarray, ...] | None = None) -> Any:
        """EM on joint samples as given: GMR's mixture without its path.

        For models that build on GMR's mixture over other samples
        (:class:`lfdkit.imitate.TPGMM` fits one over the phase and the
        positions in every task frame): no orientation of demonstrations, no
        ``length_scale`` (the caller scales) and no check that the samples
        make one motion. Uses ``n_components``, ``covariance_reg``,
        ``max_iter``, ``tol``, ``n_init`` and ``random_state``; sets no
        attribute of ``self``.

        Parameters
        ----------
        samples : ndarray, shape (n_samples, n_features)
            Finite float64 samples, already validated.
        start : tuple of ndarray, optional
            ``(weights, means, covariances)`` of ``n_components`` components,
            shapes (K,), (K, n_features), (K, n_features, n_features): one EM
            run from them instead of ``n_init`` k-means starts.

        Returns
        -------
        sklearn.mixture.GaussianMixture
            The fitted full-covariance mixture.
        """
        self._validate_params()
        return self._mixture(samples, _sklearn_seed(self.random_state), start)

    def _samples(
        self, demos: list[np.ndarray], times: list[np.ndarray] | None
    ) -> tuple[list[np.ndarray], np.ndarray, np.ndarray]:
        """Oriented demonstrations, which were reversed, and the ``(t, s)`` samples."""
        reversed_ = np.zeros(len(demos), dtype=bool)
        if times is None:
            if self.orient == "auto":
                demos, reversed_ = orient_demos(demos, method="GMR")
            phases = [_phase(d, self.time_mode) for d in demos]
        else:
            phases = times  # the times say which way each demonstration runs
        data = np.vstack([np.column_stack((tj, d)) for tj, d in zip(phases, demos, strict=True)])
        scale = float(self.length_scale)
        if scale != 1.0:
            data[:, 1:] /= scale  # EM in units of length_scale
        return demos, reversed_, data

    def _log_scale(self, q: int) -> float:
        """Log of the positions' density factor between EM's units and the data's."""
        return q * float(np.log(float(self.length_scale)))

    def _mixture(
        self, data: np.ndarray, seed: int, start: tuple[np.ndarray, ...] | None = None
    ) -> Any:
        """EM on the samples: from k-means (``n_init`` times), or once from ``start``.

        ``start`` = (weights, means, covariances) of ``n_components`` components.
        """
        from sklearn.mixture import GaussianMixture  # imported here: lfdkit.mimic loads fast

        n_samples = data.shape[0]
        if self.n_components > n_samples:
            raise ValueError(
                f"n_components: {self.n_components} components need at least as many "
                f"data points, but the demonstrations hold only {n_samples}"
            )
        options: dict[str, Any] = {"n_init": self.n_init, "init_params": "kmeans"}
        if start is not None:
            weights, means, covariances = start
            options = {
                "n_init": 1,
                # Every parameter is given: the initial responsibilities are not used.
                "init_params": "random_from_data",
                "weights_init": weights,
                "means_init": means,
                "precisions_init": _symmetric_inverse(covariances),
            }
        gm = GaussianMixture(
            n_components=self.n_components,
            covariance_type="full",
            tol=self.tol,
            reg_covar=self.covariance_reg,
            max_iter=self.max_iter,
            random_state=seed,
            **options,
        )
        try:
            # The matrices are tiny ((1+q) x (1+q)): BLAS/OpenMP threads only add
            # overhead (and stall badly on a loaded machine), so run EM single-threaded.
            with one_blas_thread():
                gm.fit(data)
        except ValueError as exc:
            msg = str(exc)
            if "covariance" in msg or "singular" in msg or "positive" in msg:
                raise ValueError(
                    "GMR.fit: EM produced a singular covariance matrix (a component "
                    "collapsed onto too few or degenerate points); increase "
                    f"covariance_reg (now {self.covariance_reg!r}) or reduce n_components"
                ) from exc
            raise
        if not np.all(np.isfinite(gm.covariances_)) or not np.all(np.isfinite(gm.means_)):
            raise ValueError(
                "GMR.fit: EM produced a singular covariance matrix; increase covariance_reg"
            )
        return gm

    # -------------------------------------------------------------- predict
    def _responsibilities(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Return ``β`` of shape ``(T, K)`` and ``t − μ_t`` of shape ``(T, K)``."""
        mu_t = self.means_[:, 0]
        var_t = self.covariances_[:, 0, 0]
        if np.any(var_t <= 0.0):
            raise ValueError(
                "covariances_: the phase variance Σ_tt of some component is not positive "
                "(singular covariance); refit with a larger covariance_reg"
            )
        diff = t[:, None] - mu_t[None, :]
        with np.errstate(divide="ignore"):
            log_w = np.log(self.weights_)
        log_p = log_w[None, :] - 0.5 * (_LOG_2PI + np.log(var_t)[None, :] + diff**2 / var_t)
        from scipy.special import logsumexp  # imported here: lfdkit.mimic loads fast

        log_beta = log_p - logsumexp(log_p, axis=1, keepdims=True)
        return np.exp(log_beta), diff

    def predict(
        self,
        t: Any,
        return_cov: bool = False,
        cov_mode: CovMode | None = None,
    ) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
        """Conditional mean (and covariance) of the position given the phase.

        Parameters
        ----------
        t : array_like, shape (T,)
            Query phases, in the units used for training (``[0, 1]`` by
            default). A scalar is read as one query. Values outside the
            training range are allowed (extrapolation stays finite).
        return_cov : bool, default False
            Also return the conditional covariance.
        cov_mode : {"thesis", "law_of_total_covariance"}, optional
            Overrides the estimator's ``cov_mode`` for this call.

        Returns
        -------
        mean : ndarray, shape (T, q)
            Generalized path at ``t`` (spatial units of the demonstrations).
        cov : ndarray, shape (T, q, q)
            Conditional covariance (squared spatial units); only with
            ``return_cov=True``.
        """
        check_fitted(self, ("weights_", "means_", "covariances_"))
        tq = check_values(t, "t")
        mode = self.cov_mode if cov_mode is None else cov_mode
        if mode not in _COV_MODES:
            raise ValueError(f"cov_mode: expected one of {_COV_MODES}, got {mode!r}")

        mu_s = self.means_[:, 1:]  # (K, q)
        var_t = self.covariances_[:, 0, 0]  # (K,)
        cov_st = self.covariances_[:, 1:, 0]  # (K, q)
        gain = cov_st / var_t[:, None]  # Σ_st Σ_tt⁻¹, (K, q)

        beta, diff = self._responsibilities(tq)  # (T, K)
        s_k = mu_s[None, :, :] + diff[:, :, None] * gain[None, :, :]  # (T, K, q)
        mean = np.einsum("tk,tkq->tq", beta, s_k)
        if not return_cov:
            return mean

        # Σ̂_k = Σ_ss − Σ_st Σ_tt⁻¹ Σ_ts   (K, q, q)
        cond_cov = self.covariances_[:, 1:, 1:] - np.einsum("ki,kj->kij", gain, cov_st)
        cond_cov = 0.5 * (cond_cov + np.swapaxes(cond_cov, 1, 2))
        if mode == "thesis":
            cov = np.einsum("tk,kij->tij", beta**2, cond_cov)
        else:
            dev = s_k - mean[:, None, :]
            cov = np.einsum("tk,kij->tij", beta, cond_cov) + np.einsum(
                "tk,tki,tkj->tij", beta, dev, dev
            )
        return mean, cov

    def path(self, n_points: int = 100) -> np.ndarray:
        """Generalized path on ``n_points`` equally spaced phases.

        Parameters
        ----------
        n_points : int, default 100
            Number of samples (at most 1,000,000); the phases are
            ``linspace(*time_range_, n_points)``, i.e. ``linspace(0, 1, n_points)``
            unless ``fit`` was given explicit ``times``.

        Returns
        -------
        ndarray, shape (n_points, q)
        """
        check_fitted(self, ("weights_", "means_", "covariances_"))
        n_points = check_count(n_points, "n_points")  # at most MAX_POINTS
        t0, t1 = getattr(self, "time_range_", (0.0, 1.0))
        return self.predict(np.linspace(t0, t1, n_points))


class ComponentLimitWarning(UserWarning):
    """:func:`select_n_components` chose its largest candidate count.

    The criterion was still falling there: more components may describe the
    demonstrations better. Try larger candidates, or take the count as a cap.
    """


def select_n_components(
    demos: Any,
    candidates: Iterable[int] = range(2, 31),
    criterion: Literal["bic", "aic"] = "bic",
    random_state: Any = None,
    times: Any = None,
    *,
    search: Literal["ladder", "exhaustive"] = "ladder",
    patience: int = 2,
    **gmr_params: Any,
) -> tuple[int, dict[int, float]]:
    """Choose the number of GMR components by an information criterion.

    Parameters
    ----------
    demos : list of array_like, each shape (n_i, q)
        Demonstrations, as for ``GMR.fit``.
    candidates : iterable of int, default range(2, 31)
        Component counts to choose from. Counts larger than the number of
        samples are skipped (they cannot be fitted).
    criterion : {"bic", "aic"}, default "bic"
        Criterion to minimise.
    random_state : None, int or numpy.random.Generator
        Seed; every k-means initialisation uses the same derived seed.
    times : list of array_like, each shape (n_i,), optional
        Explicit phases, as for ``GMR.fit``.
    search : {"ladder", "exhaustive"}, default "ladder"
        ``"exhaustive"`` fits every candidate from its own k-means start.
        ``"ladder"`` fits a coarse ladder of candidates (each at least 1.5
        times the previous, the smallest and the largest included) in
        increasing order, each EM started from the previous rung's mixture
        with its widest components split in two; it stops climbing once the
        criterion has risen on ``patience`` rungs in a row, then narrows down
        between the best rung's neighbours by a bracketing search, each fit
        started from the nearest smaller count fitted. Several times faster,
        and usually the same choice (``benchmarks/mimic.py --sections gmr``).
    patience : int, default 2
        ``search="ladder"``: rungs on which the criterion may rise above its
        best before the climb stops.
    **gmr_params
        Further ``GMR`` parameters (``covariance_reg``, ``time_mode``, ...).

    Returns
    -------
    best_k : int
        Candidate with the smallest criterion (the smallest such ``k`` on ties).
    scores : dict of int to float
        Criterion value of every candidate fitted (with ``"ladder"``, a subset).

    Warns
    -----
    ComponentLimitWarning
        When the choice is the largest of several candidates.
    """
    if criterion not in ("bic", "aic"):
        raise ValueError(f"criterion: expected 'bic' or 'aic', got {criterion!r}")
    if search not in ("ladder", "exhaustive"):
        raise ValueError(f"search: expected 'ladder' or 'exhaustive', got {search!r}")
    check_positive(patience, "patience", integer=True)
    demos = check_demos(demos, "demos", min_dims=1)
    if times is not None:
        times = check_times_list(times, demos, missing=False, increasing=False, style="shape")
    # At most _MAX_COMPONENTS + 1 read: a huge range is refused, not materialised.
    cand = list(itertools.islice(candidates, _MAX_COMPONENTS + 1))
    if len(cand) > _MAX_COMPONENTS:
        raise ValueError(f"candidates: at most {_MAX_COMPONENTS} component counts to try")
    if not cand:
        raise ValueError("candidates: needs at least one component count")
    for k in cand:
        check_positive(k, "candidates", integer=True)
    n_samples = sum(d.shape[0] for d in demos)
    usable = sorted({int(k) for k in cand if k <= n_samples})
    if not usable:
        raise ValueError(
            f"candidates: every candidate exceeds the {n_samples} available data points"
        )
    seed = _sklearn_seed(random_state)
    if search == "exhaustive":
        scores: dict[int, float] = {}
        for k in usable:
            model = GMR(n_components=k, random_state=seed, **gmr_params).fit(
                demos, times=times, check_input=False
            )
            scores[k] = model.bic_ if criterion == "bic" else model.aic_
    else:
        scores = _ladder_search(demos, times, usable, criterion, seed, patience, gmr_params)
    best_k = min(scores, key=lambda k: (scores[k], k))
    if best_k == usable[-1] and len(usable) > 1:
        warnings.warn(
            f"select_n_components: the {criterion.upper()} is smallest at the largest "
            f"candidate, {best_k} components; more may fit better (give larger candidates)",
            ComponentLimitWarning,
            stacklevel=2,
        )
    return best_k, scores


#: ``search="ladder"``: each rung at least this many times the previous one.
_LADDER_RATIO = 1.5


def _ladder_search(
    demos: list[np.ndarray],
    times: list[np.ndarray] | None,
    usable: list[int],
    criterion: str,
    seed: int,
    patience: int,
    gmr_params: dict[str, Any],
) -> dict[int, float]:
    """Criterion values of the candidates :func:`select_n_components` visits (``"ladder"``)."""
    template = GMR(random_state=seed, **gmr_params)
    template._validate_params()
    _, _, data = template._samples(demos, times)
    mixtures: dict[int, _Mixture] = {}
    scores: dict[int, float] = {}

    def score(i: int) -> float:
        k = usable[i]
        if k not in scores:
            below = [j for j in mixtures if j < k]
            mixture = None
            if below:
                start = _split_start(mixtures[max(below)], k)
                mixture = _em(data, start, template.covariance_reg, template.tol, template.max_iter)
            if mixture is None:  # the smallest count, or EM from the split start collapsed
                model = GMR(n_components=k, random_state=seed, **gmr_params)
                gm = model._mixture(data, seed)
                mixture = _Mixture(gm.weights_, gm.means_, gm.covariances_, gm.score(data))
            mixtures[k] = mixture
            # In the demonstrations' units, as GMR.bic_ / aic_ (EM ran in length_scale's).
            shift = 2.0 * len(data) * template._log_scale(data.shape[1] - 1)
            scores[k] = mixture.criterion(criterion, len(data)) + shift
        return scores[k]

    rungs = [0]
    for i, k in enumerate(usable[1:], start=1):
        if k >= _LADDER_RATIO * usable[rungs[-1]] or i == len(usable) - 1:
            rungs.append(i)
    best, worse = 0, 0
    for r, i in enumerate(rungs):
        if score(i) < score(rungs[best]):
            best, worse = r, 0
        elif r > 0:
            worse += 1
            if worse >= patience:
                break
    # Bracket search between the best rung's neighbours (the criterion taken as
    # unimodal there): probe the middle of the wider side, keep the best point.
    lo = rungs[best - 1] if best > 0 else rungs[best]
    hi = rungs[best + 1] if best + 1 < len(rungs) else rungs[best]
    mid = rungs[best]
    while hi - lo > 2:
        if mid - lo >= hi - mid:
            probe = (lo + mid) // 2
            if score(probe) < score(mid):
                hi, mid = mid, probe
            else:
                lo = probe
        else:
            probe = (mid + hi + 1) // 2
            if score(probe) < score(mid):
                lo, mid = mid, probe
            else:
                hi = probe
    for i in (mid - 1, mid + 1):
        if lo <= i <= hi:
            score(i)
    return scores


class _Mixture(NamedTuple):
    """A fitted full-covariance mixture and its mean log-likelihood per sample."""

    weights: np.ndarray
    means: np.ndarray
    covariances: np.ndarray
    log_likelihood: float

    def criterion(self, name: str, n_samples: int) -> float:
        """BIC or AIC, as scikit-learn's ``GaussianMixture.bic`` / ``aic``."""
        k, d = self.means.shape
        n_params = k * (d + d * (d + 1) / 2) + k - 1
        penalty = n_params * (np.log(n_samples) if name == "bic" else 2.0)
        return float(-2.0 * self.log_likelihood * n_samples + penalty)


def _em(
    data: np.ndarray,
    start: tuple[np.ndarray, np.ndarray, np.ndarray],
    reg: float,
    tol: float,
    max_iter: int,
) -> _Mixture | None:
    """EM for a full-covariance mixture from given parameters (compiled; None if singular).

    The same iteration, regularisation (``reg`` on every covariance's
    diagonal) and stopping rule (gain in mean log-likelihood below ``tol``,
    at most ``max_iter`` iterations) as scikit-learn's ``GaussianMixture``,
    whose per-component Python loops cost several times more on the few
    dimensions of a path (:mod:`lfdkit.mimic._gmr_kernels`).
    """
    from lfdkit.mimic._gmr_kernels import em  # numba compiles on first use

    weights, means, covariances = (np.array(a, dtype=np.float64) for a in start)
    data = np.ascontiguousarray(data, dtype=np.float64)
    log_likelihood, _, ok = em(data, weights, means, covariances, reg, tol, max_iter)
    return _Mixture(weights, means, covariances, float(log_likelihood)) if ok else None


def _symmetric_inverse(covariances: np.ndarray) -> np.ndarray:
    """Inverses of symmetric positive definite matrices, exactly symmetric."""
    inverse = np.linalg.inv(covariances)
    return 0.5 * (inverse + np.swapaxes(inverse, -1, -2))


def _split_start(mixture: _Mixture, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``k`` components from a fitted mixture's: the widest split in two until there are ``k``.

    The widest is the component of largest weight times variance along its main
    axis; its halves sit half a standard deviation either side of its mean along
    that axis, each with the variance there quartered and half the weight.
    """
    weights = list(np.asarray(mixture.weights, dtype=np.float64))
    means = list(np.asarray(mixture.means, dtype=np.float64))
    covs = list(np.asarray(mixture.covariances, dtype=np.float64))
    while len(weights) < k:
        spread = [np.linalg.eigh(c) for c in covs]
        j = int(np.argmax([w * vals[-1] for w, (vals, _) in zip(weights, spread, strict=True)]))
        vals, vecs = spread[j]
        axis = np.sqrt(max(vals[-1], 0.0)) * vecs[:, -1]
        cov = covs[j] - 0.75 * np.outer(axis, axis)
        mean, weight = means[j], 0.5 * weights[j]
        weights[j], means[j], covs[j] = weight, mean - 0.5 * axis, cov
        weights.append(weight)
        means.append(mean + 0.5 * axis)
        covs.append(cov.copy())
    return np.array(weights), np.array(means), np.array(covs)


register(
    MimicMethod(
        key="gmr",
        label="GMR",
        color="#1f77b4",
        build=lambda settings: GMR(
            n_components=settings.n_components,
            random_state=settings.random_state,
            n_points=settings.n_points,
            length_scale=settings.length_scale,
        ),
        diagnostics=lambda fitted: {
            "log_likelihood": float(fitted.log_likelihood_),
            "converged": bool(fitted.converged_),
            "n_iter": int(fitted.n_iter_),
        },
        uses=("n_points", "random_state", "n_components", "length_scale"),
        check_input=True,
    )
)
