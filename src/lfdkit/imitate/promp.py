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

- **Speed where it is used many times** (``benchmarks/promp.py``, against
  movement_primitives on the same model): ``H`` is never built (each observed
  coordinate touches one block of weights, so ``Σ Hᵀ`` and ``H Σ Hᵀ`` are
  products with ``φ``); activations on an even grid are cached per
  ``(n_basis, width, n_points)`` (paths, bands and samples reuse them);
  samples are one matrix product, not an einsum (10× slower). A band
  (:meth:`ProMP.std`) is one gather of the diagonal blocks' upper triangles
  and one product with the activations' pairwise products, cached per grid
  (2.4× the former product per block, multiply and sum).
  :meth:`ProMP.condition_many` conditions many point sets at the same phases:
  the gain and the conditioned covariance do not depend on the points, so
  they are computed once.
- **Conditioning is one compiled call** (:mod:`._promp_kernels`, numba, with
  a NumPy twin :func:`condition_weights`; :func:`lfdkit.core.kernels.kernel`
  picks one, so a one-shot command does not pay numba's start-up). A call at
  a new phase was about 20 small NumPy calls (basis, ``Σ Hᵀ``, ``eigh``,
  gain, mean, covariance, warning test), 0.05–0.10 ms against the peer's
  0.07–0.12: 1.2×. Now: argument types and shapes checked in Python, values
  (finite points, phases in [0, 1]) by the kernel before any work, one buffer
  out (a returned array cost a microsecond to box), and the new covariance
  formed only when first read (``weights_cov_``, a descriptor on the class
  that an instance's own array shadows once formed): a planned path's mean
  does not need it. With ``S⁺ = L Lᵀ`` the kernel hands back ``Z = Lᵀ H Σ``,
  so that ``Σ' = Σ − Zᵀ Z``, formed by a second small kernel
  (:func:`conditioned_covariance`: the upper triangle, mirrored, so exactly
  symmetric; NumPy's product and subtraction took 1.5–2× its time, and
  ``__getattr__``, reached only after a failed look-up, added about 1 µs;
  where ``Σ`` is exactly symmetric, every fitted or conditioned model's,
  :func:`conditioned_covariance_rows` gives the same numbers in whole rows
  without the mirrored copy, 0.65 against 0.95 µs of work. Forming ``Σ'`` in
  the conditioning call instead made a 1-point conditioning 1.3× slower for
  the paths that read only the mean, to save the read's ~2 µs of dispatch and
  glue); a
  conditioned model's :meth:`ProMP.std` needs not even that: its source's
  band (kept on the source per grid) less the squared norms of ``Z φ`` per
  coordinate. Forming it inside the conditioning kernel was not taken: its
  work (n²·m/2 products) would fall on every call, read or not. One point
  at one phase with a variance (most calls) goes to its own kernel,
  :func:`condition_point`: the phase a float, the basis centres formed in
  it, 5 arguments, the model's width,
  cut, mean and covariance in one writeable array kept per model (numba's
  dispatch is a third of the kernel's call; 8 arguments with two read-only
  arrays, which numba types by its slow path, took 0.3 µs more), its glue
  inline (each NumPy call or method call costs 0.1–1 µs of a ~3 µs call;
  ``setflags`` by keyword cost 2.5× positional); the conditioned copy fills
  its own dict from the attributes kept for copies (copying the dict and
  deleting what is kept for speed was 0.7 µs), kept with the model's array
  and read as an attribute (a class default ``None`` where none is kept),
  not from ``__dict__``. What is kept is dropped when
  an attribute is set (:meth:`ProMP.__setattr__`). The kernel writes the
  new mean basis-major as well and ``Z`` transposed by dimension, so that a
  path and a band are each one ``np.dot`` with a contiguous operand (a
  transposed one cost 40 % more; ``@`` 20 % more than ``np.dot``). The kernel's
  pseudo-inverse is a Jacobi eigen-decomposition with the NumPy twin's cut
  (or, where the innovation covariance is certainly well conditioned, its
  inverse Cholesky factor: :mod:`._promp_kernels`); the two agree to 1e-9
  of the units on random well-conditioned models (1–3 dimensions, units
  1e-3 to 1e3, directions dropped alike). Replaced: a per-phase cache of
  factors and a closed-form Cholesky for one point (the kernel is as fast
  at a new phase as they were at a seen one).
  Several points with a variance go to :func:`condition_points`, with the
  same one-array model and five arguments: the general kernel's ten, three
  of them read-only, and its Python glue were a quarter of a three-point
  call (3 points at new phases: 11× → 15× the peer). One point: 11.4× the
  peer at a phase seen before, 10.8× at a new one (quartiles 10.8–11.9× and
  10.1–12.0×; 10.4× and 10.3× before the glue above was trimmed and the
  kernel's views dropped; 32 runs of each, side by side, at load 3–6), a
  call ~3 µs: by a profile half of it CPython running the glue and making
  the copy, under a third the compiled call (the kernel's work ~1 µs,
  numba's dispatch and unboxing ~0.3 µs), NumPy's and the C library's
  allocation a tenth. With ``weights_cov_`` read, 6.8× (6.1× before): its
  30 × 30 entries are the work of another conditioning.
- **BLAS threads**: a 30 × 30 ``eigh`` with OpenBLAS's default threads took
  3–48 ms on a busy 2-core machine instead of 0.1 ms (its divide-and-conquer
  hands blocks to threads that wait for a core; 2 × 2 to 12 × 12 were not
  affected). Sampling's eigen-decomposition runs under one BLAS thread
  (:func:`lfdkit.core.threads.one_blas_thread`, ~12 µs a use) and is kept per
  model (sample 100 × 100: 4.8–16 ms → 0.26–0.34 ms at load ~20); the NumPy
  twin's ``eigh`` above 25 × 25 runs on one thread too. The weight arrays
  are read-only, so that what is kept cannot go stale.

Numbers: 10 basis functions × 3 dimensions is a 30 × 30 covariance; fitting
and conditioning cost well under a millisecond.
"""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Callable, Mapping
from typing import Any, ClassVar

import numpy as np

from lfdkit.core.constraints import Integer, Real
from lfdkit.core.estimator import Estimator, check_fitted
from lfdkit.core.kernels import kernel
from lfdkit.core.validation import (
    check_count,
    check_demos,
    check_positive,
    check_random_state,
    check_state_number,
    check_times,
    check_values,
    made_from_state,
)
from lfdkit.model.timed_path import TimedPath

__all__ = ["ProMP"]

#: Most basis functions per dimension: beyond a few hundred the weight
#: covariance (``(n_basis · n_dims)²`` entries) outgrows any demonstration set.
MAX_PROMP_BASIS = 500

#: Relative cut of the pseudo-inverse in conditioning: singular values below
#: this fraction of the largest are directions the model cannot move in.
_PINV_RCOND = 1e-10

#: Smallest positive float: the cut's floor for an all-zero covariance.
_TINY = float(np.finfo(float).tiny)

#: Covariance types the quick argument check takes as a variance (others: the full check).
_SCALAR_TYPES = frozenset((float, int, np.float64, np.float32, np.int64, np.int32))

#: Largest ``eigh`` left to BLAS's threads: above 25 LAPACK divides and conquers
#: in threads that, on a busy machine, wait for a core (30 × 30: 42 ms against
#: 0.2 ms with one thread, load 10); up to 12 × 12 the limit (~12 µs) cost more.
_SMALL_EIGH = 25

#: Activations on even grids by (n_basis, width, n_points): a dict look-up before
#: the argument check and the LRU cache (together 3× the product of a mean path).
_GRIDS: dict = {}

#: Attributes a model keeps for speed only (the sampling root, the bands its conditioned
#: models' std reads) or until first use (the conditioned covariance's parts): never
#: copied to another model.
_KEPT = (
    "_root_cache",
    "_pending_cov",
    "_band_cache",
    "_columns_cache",
    "_copy_state",
    "_prior_cache",
)

#: What an attribute set makes stale (the others are checked against the weight arrays).
_DROPPED_ON_SET = ("_copy_state", "_prior_cache")

#: Phase types the one-point route takes as they are (others: an array first).
_PHASE_TYPES = frozenset((float, np.float64))

#: NumPy's float64 (a type's dtype is this one object: compared by identity, 10× faster).
_FLOAT64 = np.dtype(np.float64)

#: Infinity, NumPy's array type and allocation, a new object: module globals, an
#: attribute look-up less each in the one-point route.
_INF = math.inf
_NDARRAY = np.ndarray
_EMPTY = np.empty
_NEW = object.__new__


def _kernel_getter(name: str) -> tuple[list, Callable[[], Any]]:
    """``(kept, get)`` for the kernel ``name``: ``get()`` hands out numba's form (from
    :mod:`._promp_kernels`) or its NumPy twin of the same name in this module, as
    :func:`lfdkit.core.kernels.kernel`'s rule says.

    numba's is kept in ``kept`` once handed out (the rule never turns back within a
    process; asking it again cost as much as the kernel itself): a hot path reads
    ``kept[0]`` and calls ``get()`` only while ``kept`` is empty.
    """
    kept: list = []

    def get() -> Any:
        if kept:
            return kept[0]
        run = kernel(name, "lfdkit.imitate._promp_kernels", __name__)
        if run is not globals()[name]:  # not the twin: numba's
            kept.append(run)
        return run

    return kept, get


#: The conditioning kernel (:func:`condition_weights`), the one-point kernel
#: (:func:`condition_point`), the several-point one with a variance
#: (:func:`condition_points`), the conditioned covariance's (:func:`conditioned_covariance`)
#: and its form for an exactly symmetric weight covariance
#: (:func:`conditioned_covariance_rows`): numba's once handed out, and their getters.
_COMPILED, _condition_kernel = _kernel_getter("condition_weights")
_COMPILED_POINT, _point_kernel = _kernel_getter("condition_point")
_COMPILED_POINTS, _points_kernel = _kernel_getter("condition_points")
_COMPILED_COV, _cov_kernel = _kernel_getter("conditioned_covariance")
_COMPILED_ROWS, _rows_kernel = _kernel_getter("conditioned_covariance_rows")


class _FormedOnRead:
    """``ProMP.weights_cov_`` where the instance has none yet: a conditioned model's
    covariance formed on first read (then an instance attribute, found first).

    A non-data descriptor: an instance's own ``weights_cov_`` (set by ``fit`` or
    once formed) shadows it, so a formed covariance costs a plain attribute
    read. Replaced ``__getattr__``, reached only after a failed look-up, which
    raised and caught an AttributeError first: about 1 µs, a third of a
    one-point conditioning, on every first read.
    """

    def __get__(self, model: Any, owner: type | None = None) -> Any:
        if model is None:
            return self
        state = model.__dict__
        pending = state.pop("_pending_cov", None)
        if pending is None:
            raise AttributeError(f"{type(model).__name__!r} object has no attribute 'weights_cov_'")
        cov, out, symmetric, m, _, _, prior = pending
        result = _EMPTY(cov.shape)
        if symmetric:  # whole rows, no mirrored copy: the same numbers, 0.3 µs less
            run = _COMPILED_ROWS[0] if _COMPILED_ROWS else _rows_kernel()
        else:
            run = _COMPILED_COV[0] if _COMPILED_COV else _cov_kernel()
        run(prior, out, len(cov), m, result)
        result.setflags(False)  # read-only, as every weight array (by keyword: slower)
        state["weights_cov_"] = result
        return result


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
        Both weight arrays are read-only (factors kept for conditioning and
        sampling depend on them): assign new arrays to change them.
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

    #: A conditioned model's covariance is formed on first read (:class:`_FormedOnRead`).
    weights_cov_ = _FormedOnRead()

    #: What :meth:`_kernel_prior` keeps, where an instance has none: read as an attribute
    #: (the instance's own found first), not from ``__dict__``, an attribute and a call less.
    _prior_cache: tuple | None = None

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
        mean = weights.mean(axis=0)
        centred = weights - mean
        self.weights_mean_ = _frozen(mean)
        self.weights_cov_ = _frozen(centred.T @ centred / (len(demos) - 1))
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
        return self._mean_from(self._features(_check_phases(phases, "phases")))

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
        # Σ_y(s)[i, k] = φ(s)ᵀ Σ_w[i-block, k-block] φ(s): two matrix products, no einsum.
        left = (features @ self._weights_cov().reshape(d, b, d * b)).reshape(d, -1, d, b)
        return np.sum(left * features[:, None, :], axis=-1).transpose(1, 0, 2)

    def mean_path(self, n_points: int = 100) -> np.ndarray:
        """Mean path at ``n_points`` phases evenly spaced over [0, 1].

        Returns
        -------
        ndarray, shape (n_points, n_dims)
        """
        state = self.__dict__
        mean = state.get("weights_mean_")
        if mean is None:
            self._check_fitted()
        # Inline (each method call is 0.1 µs of a 1.5 µs path): the grid's activations...
        features = None
        if type(n_points) is int:
            features = _GRIDS.get((state["n_basis"], state["width_"], n_points))
        if features is None:
            features = self._grid(n_points)
        # ... and the mean basis-major (:meth:`_mean_columns`).
        kept = state.get("_columns_cache")
        if kept is None or kept[0] is not mean:
            kept = self._mean_columns()
        return np.dot(features, kept[1])

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
        self._check_fitted()
        seconds = check_positive(duration, "duration")
        phases = _even_phases(n_points)
        positions = self._mean_from(self._grid(n_points))
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
        state = self.__dict__
        if "weights_mean_" not in state:
            self._check_fitted()
        pending = state.get("_pending_cov")
        if pending is None:
            variances = _variances(self._weights_cov(), *self._grid_products(n_points))
        else:
            # Conditioned, covariance not formed: its source's band (kept on the source)
            # less the reduction, the squared norms of Zᵀ φ per coordinate (Σ' = Σ − Zᵀ Z).
            cov, out, _, m, source, _, _ = pending
            d = state["n_dims_"]
            # Z split by dimension and transposed, (b, m·d): the buffer's last part.
            root_h_t = out[len(out) - m * len(cov) :].reshape(-1, m * d)
            projected = np.dot(self._grid(n_points), root_h_t)
            # Summed over the rows of Z by a product (a sum over the middle axis: 4×).
            reduction = np.dot(np.square(projected, out=projected), _summing(m, d))
            variances = source._band(cov, n_points) - reduction
        return np.sqrt(np.maximum(variances, 0.0, out=variances), out=variances)

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
        features = self._grid(n_points)
        rng = check_random_state(seed)
        root = self._covariance_root()
        draws = self.weights_mean_ + rng.standard_normal((n_samples, len(root))) @ root.T
        # One product for all samples and dimensions (einsum here was 10× slower).
        paths = draws.reshape(n_samples * self.n_dims_, self.n_basis) @ features.T
        return np.ascontiguousarray(paths.reshape(n_samples, self.n_dims_, -1).transpose(0, 2, 1))

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
            A fitted copy; this model is unchanged. Its ``weights_cov_`` is
            formed when first read (a path's mean does not need it).

        Warns
        -----
        UserWarning
            If part of a via-point's offset from the mean lies where the model
            cannot move (more than 1e-6 of the points' scale): the
            demonstrations never varied that way, or exact via-points close
            in phase contradict each other. A covariance > 0 makes every
            point a compromise, never unreachable.
        """
        kept = self._prior_cache
        if kept is None:  # checks that it is fitted, forms a conditioned model's covariance
            kept = self._kernel_prior()
        prior, n_weights, size, shape, cov, symmetric, copied = kept
        # The common call, one point at one phase with a variance, goes to the one-point
        # kernel with its argument types and shapes checked here (values by the kernel);
        # the glue is inline: each NumPy call or method call costs 0.1–1 µs of a 3 µs call.
        kind, phase, pts = type(phases), phases, None
        if kind is list and len(phases) == 1:
            phase = phases[0]
        elif kind is _NDARRAY:
            phase = phases[0] if phases.shape == (1,) else None
        kind = type(covariance)
        quick = (kind is float or kind in _SCALAR_TYPES) and 0.0 <= covariance < _INF
        if quick and type(phase) in _PHASE_TYPES:
            pts = points
            if type(pts) is not _NDARRAY or pts.dtype is not _FLOAT64:
                try:
                    pts = np.asarray(points, dtype=np.float64)
                except (TypeError, ValueError):
                    pts = None
            if pts is not None and pts.shape != shape:
                pts = pts.reshape(shape) if pts.shape == shape[1:] else None
        if pts is not None:
            out = _EMPTY(size)
            n_dropped = (_COMPILED_POINT[0] if _COMPILED_POINT else _point_kernel())(
                prior,
                phase,
                pts,
                covariance if kind is float else float(covariance),
                out,
            )
            if n_dropped < 0:  # a value the quick check let through: the full checks name it
                self._checked_via(points, phases, covariance, full=True)
            out.setflags(False)  # the new mean is a view: read-only too (by keyword: 2.5× slower)
            s, m = phase, shape[1]
        else:
            pts = s = None
            if quick:  # several points with a variance: types and shapes checked here
                pts, s = self._quick_via(points, phases, shape[1])
            if pts is not None:
                m = pts.size
                out = np.empty(2 * (1 + m) * n_weights + m)
                n_dropped = (_COMPILED_POINTS[0] if _COMPILED_POINTS else _points_kernel())(
                    prior,
                    s,
                    pts,
                    covariance if kind is float else float(covariance),
                    out,
                )
                if n_dropped < 0:
                    self._checked_via(points, phases, covariance, full=True)
                out.setflags(False)
            else:
                pts, s, variance, noise = self._checked_via(points, phases, covariance)
                out, n_dropped = self._conditioned(pts[None], s, variance, noise)
                if n_dropped < 0:  # nothing computed: the full checks name the value
                    self._checked_via(points, phases, covariance, full=True)
                m = pts.size
        # The covariance is formed when first read (Σ' = Σ − Zᵀ Z): a path's mean
        # alone does not need it. The copy made inline (a method call is 0.1 µs).
        new = _NEW(type(self))
        made = new.__dict__  # filled, not replaced: the instance's own dict is the cheapest
        made.update(copied)
        mean = made["weights_mean_"] = out[:n_weights]
        # self: keeps the band for std; prior: the model as the covariance's kernel takes it;
        # symmetric: whether Σ is exactly (which of its two kernels forms Σ').
        made["_pending_cov"] = (cov, out, symmetric, m, self, mean, prior)
        made["_copy_state"] = copied
        if n_dropped:
            lost = out[n_weights * (1 + m) : n_weights * (1 + m) + m].reshape(pts.shape)
            new._warn_unreachable(pts, np.reshape(s, -1), lost, "points")
        return new

    def condition_many(self, points: Any, phases: Any, covariance: Any = 0.0) -> list[ProMP]:
        """Condition on many sets of via-points at the same phases, in one go.

        Equal to ``[self.condition(p, phases, covariance) for p in points]``
        (to rounding), but the gain and the conditioned covariance, which do
        not depend on where the points are, are computed once: per set it
        costs a matrix-vector product (for planning many goals, or sweeping a
        via-point over a grid).

        Parameters
        ----------
        points : array_like, shape (n_sets, n_via, n_dims)
            Each set's positions, in the demonstrations' units.
        phases : array_like, shape (n_via,)
            Phase of each via-point, shared by all sets, in [0, 1].
        covariance : float or array_like, default 0
            As :meth:`condition`, shared by all sets.

        Returns
        -------
        list of ProMP, length n_sets
            Fitted copies; they share one read-only covariance array.

        Warns
        -----
        UserWarning
            As :meth:`condition`, for the first set with a point out of reach.
        """
        self._check_fitted()
        d = self.n_dims_
        try:
            sets = np.asarray(points, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise TypeError(
                "points: expected a numeric array of shape (n_sets, n_via, n_dims)"
            ) from exc
        if sets.ndim != 3 or sets.shape[0] == 0:
            raise ValueError(f"points: expected shape (n_sets, n_via, {d}), got {sets.shape}")
        _check_points(sets.reshape(-1, sets.shape[-1]), d)
        s = _check_phases(phases, "phases")
        if len(s) != sets.shape[1]:
            raise ValueError(
                f"phases: got {len(s)} phases for {sets.shape[1]} points per set; "
                "give one phase per point"
            )
        noise = _check_covariance(covariance, len(s), d)
        variance, noise = (noise, _no_noise(d)) if isinstance(noise, float) else (0.0, noise)
        out, n_dropped = self._conditioned(
            np.ascontiguousarray(sets), s, variance, np.ascontiguousarray(noise)
        )
        means, _, lost, _, _ = _out_parts(out, len(sets), len(self.weights_mean_), sets[0].size, d)
        n = len(self.weights_mean_)
        cov = np.empty((n, n))
        kept = self._kernel_prior()
        run = _rows_kernel() if kept[5] else _cov_kernel()  # kept[5]: Σ exactly symmetric
        run(kept[0], out, len(sets) * n, sets[0].size, cov)
        cov.setflags(False)
        out = self._with_weights(means, cov)
        if n_dropped:
            for j, model in enumerate(out):
                if model._warn_unreachable(sets[j], s, lost[j].reshape(-1, d), f"points[{j}]"):
                    break
        return out

    def _checked_via(
        self, points: Any, phases: Any, covariance: Any, full: bool = False
    ) -> tuple[np.ndarray, np.ndarray, float, np.ndarray]:
        """Via-point arguments checked once, here at the edge: ``(points (k, d), phases (k,),
        variance, noise (k or 0, d, d))``, or the one-line error of the full checks.

        The common call (a few points, a variance) has its types and shapes
        checked here and its values (finite points, phases in [0, 1]) by the
        kernel, which refuses them before any work (:meth:`condition` then
        calls this with ``full=True``); anything else goes through the full
        checks, which name what is wrong.
        """
        d = self.n_dims_
        if not full and type(covariance) in _SCALAR_TYPES and 0.0 <= covariance < math.inf:
            try:
                pts, s = _floats(points), _floats(phases)
            except (TypeError, ValueError):
                pts = s = None
            if pts is not None and pts.ndim == 1:
                pts = pts.reshape(1, -1)
            if (
                pts is not None
                and pts.ndim == 2
                and pts.shape[1] == d
                and 0 < len(pts) == s.size
                and s.ndim <= 1
            ):
                return pts, (s if s.ndim else s.reshape(1)), float(covariance), _no_noise(d)
        pts = _check_points(points, d)
        s = _check_phases(phases, "phases")
        if len(s) != len(pts):
            raise ValueError(
                f"phases: got {len(s)} phases for {len(pts)} points; give one phase per point"
            )
        noise = _check_covariance(covariance, len(s), d)
        if isinstance(noise, float):
            return pts, s, noise, _no_noise(d)
        return pts, s, 0.0, noise

    def _conditioned(
        self, sets: np.ndarray, phases: np.ndarray, variance: float, noise: np.ndarray
    ) -> tuple[np.ndarray, int]:
        """:func:`condition_weights` (numba's or the NumPy twin) on this model's weights.

        ``sets`` (n_sets, k, d) points, C-contiguous. Returns the kernel's
        buffer (read-only; :func:`_out_parts` splits it) and its count of
        dropped directions (−1: a value out of range, nothing computed).
        """
        n_sets, k, d = sets.shape
        n_weights = len(self.weights_mean_)
        out = np.empty(_out_size(n_sets, n_weights, k * d))
        n_dropped = _condition_kernel()(
            self.weights_mean_,
            self._weights_cov(),
            _scaled_centres(self.n_basis, self.width_),
            phases,
            self.width_,
            sets,
            variance,
            noise,
            _PINV_RCOND,
            out,
        )
        # Read-only: the weights handed to the copies are views that inherit it.
        out.setflags(False)
        return out, n_dropped

    def _with_weights(self, means: np.ndarray, cov: np.ndarray) -> list[ProMP]:
        """Fitted copies, one per mean of ``means`` (n_copies, n_weights), sharing the
        covariance ``cov`` (all read-only).

        Without the constructor's signature inspection (it was a third of a
        conditioning call); width, dimensions, demos and residual are kept.
        """
        copied, kind, copies = self._copied_state(), type(self), []
        for mean in means:
            new = object.__new__(kind)
            made = new.__dict__  # filled, not replaced: the instance's own dict is the cheapest
            made.update(copied)
            made["weights_mean_"] = mean
            made["weights_cov_"] = cov
            made["_copy_state"] = copied
            copies.append(new)
        return copies

    def _copied_state(self) -> dict[str, Any]:
        """What a conditioned copy takes of this model's attributes: all but its weights
        and what is kept for speed (kept until an attribute is set, shared by the copies).

        Copying the attributes and deleting those per call was a quarter of a
        one-point conditioning (0.7 of 3 µs of glue).
        """
        state = self.__dict__
        copied = state.get("_copy_state")
        if copied is None:
            skipped = (*_KEPT, "weights_mean_", "weights_cov_")
            copied = {key: value for key, value in state.items() if key not in skipped}
            state["_copy_state"] = copied
        return copied

    def _kernel_prior(
        self,
    ) -> tuple[np.ndarray, int, int, tuple[int, int], np.ndarray, bool, dict[str, Any]]:
        """For the one- and several-point kernels: ``[width, rcond, mean, cov]`` in one
        writeable array (private; the weights' own arrays are read-only), the weights'
        count, the one-point buffer's length, a point's shape (1, n_dims),
        ``weights_cov_``, whether it is exactly symmetric, and what a conditioned copy
        takes (:meth:`_copied_state`); kept until an attribute is set.

        Three arrays of which two read-only took numba 0.3 µs more to type and
        unbox than one writeable array (a tenth of a one-point conditioning).
        """
        state = self.__dict__
        kept = state.get("_prior_cache")
        if kept is None:
            self._check_fitted()
            mean, cov = state["weights_mean_"], self._weights_cov()
            n, d = len(mean), state["n_dims_"]
            prior = np.empty(2 + n + n * n)
            prior[0], prior[1] = state["width_"], _PINV_RCOND
            prior[2 : 2 + n] = mean
            prior[2 + n :] = cov.reshape(-1)
            # Exactly symmetric (every fitted or conditioned model's; checked once): the new
            # covariance is then formed in whole rows (:func:`conditioned_covariance_rows`).
            symmetric = bool(np.array_equal(cov, cov.T))
            kept = (prior, n, 2 * (1 + d) * n + d, (1, d), cov, symmetric, self._copied_state())
            state["_prior_cache"] = kept
        return kept

    def _quick_via(self, points: Any, phases: Any, n_dims: int) -> tuple[Any, Any]:
        """Several via-points' arguments as the several-point kernel takes them, their
        types and shapes checked (values by the kernel): ``(points (k, d), phases (k,))``
        as float arrays, or ``(None, None)`` for the full checks of :meth:`_checked_via`."""
        s = phases
        if type(s) is not np.ndarray or s.dtype is not _FLOAT64:
            try:
                s = np.array(phases, dtype=np.float64)
            except (TypeError, ValueError):
                return None, None
        pts = points
        if type(pts) is not np.ndarray or pts.dtype is not _FLOAT64:
            try:
                pts = np.asarray(points, dtype=np.float64)
            except (TypeError, ValueError):
                return None, None
        k = s.shape[0] if s.ndim == 1 else 0
        if k == 0 or pts.shape != (k, n_dims):
            return None, None
        return pts, s

    def __setattr__(self, name: str, value: Any) -> None:
        """Set an attribute, forgetting what is kept of the others for conditioning."""
        state = self.__dict__
        for stale in _DROPPED_ON_SET:
            if stale in state:
                del state[stale]
        if name == "weights_cov_":  # a covariance not yet formed is replaced, not formed later
            state.pop("_pending_cov", None)
        object.__setattr__(self, name, value)

    def _weights_cov(self) -> np.ndarray:
        """``weights_cov_``, formed now if pending (a method: what the class's descriptor calls)."""
        cov = self.__dict__.get("weights_cov_")
        return self.weights_cov_ if cov is None else cov

    def __getstate__(self) -> dict[str, Any]:
        """For pickling and copies: what is kept for speed is left out (rebuilt on use)."""
        if "_pending_cov" in self.__dict__:
            self._weights_cov()  # formed now: a copy holds the array
        return {key: value for key, value in self.__dict__.items() if key not in _KEPT}

    def __setstate__(self, state: dict[str, Any]) -> None:
        """Restore a pickled model, its weight arrays read-only again."""
        self.__dict__.update(state)
        for name in ("weights_mean_", "weights_cov_"):
            if name in state:
                _frozen(state[name])

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
        made = made_from_state(
            cls,
            state,
            where,
            ("width", "n_dims", "n_demos", "residual_rms", "weights_mean", "weights_cov"),
        )
        width = check_state_number(state, "width", where, positive=True)
        check_state_number(state, "n_demos", where, positive=False)  # 0: made, not fitted
        check_state_number(state, "residual_rms", where, positive=False)
        n_dims = state["n_dims"]
        if isinstance(n_dims, bool) or not isinstance(n_dims, int) or not 1 <= n_dims <= 3:
            raise ValueError(f"{where}.n_dims: expected 1 to 3, got {n_dims!r}")
        if width > 1.0:
            raise ValueError(f"{where}.width: expected a value in (0, 1], got {state['width']!r}")
        n_weights = n_dims * made.n_basis
        try:
            mean = np.array(state["weights_mean"], dtype=np.float64)  # own copies: frozen below
            cov = np.array(state["weights_cov"], dtype=np.float64)
        except (TypeError, ValueError):
            raise ValueError(
                f"{where}: weights_mean and weights_cov must be lists of numbers "
                f"(a vector and a square matrix)"
            ) from None
        if mean.shape != (n_weights,) or cov.shape != (n_weights, n_weights):
            raise ValueError(
                f"{where}: weights of shape {mean.shape} and {cov.shape}, expected "
                f"({n_weights},) and ({n_weights}, {n_weights}) for {n_dims} dimensions "
                f"of {made.n_basis} basis functions"
            )
        if not (np.all(np.isfinite(mean)) and np.all(np.isfinite(cov))):
            raise ValueError(f"{where}: weights contain NaN or infinite values")
        made.width_ = width
        made.n_dims_ = n_dims
        made.n_demos_ = int(state["n_demos"])
        made.residual_rms_ = float(state["residual_rms"])
        made.weights_mean_, made.weights_cov_ = _frozen(mean), _frozen(cov)
        return made

    def scaled(self, factor: float) -> ProMP:
        """The same model with every length times ``factor`` (a change of units).

        Returns a fitted copy: weights' mean times ``factor``, covariance
        times ``factor²``, residual times ``factor``.
        """
        self._check_fitted()
        new = type(self).from_state(self.to_state())
        new.weights_mean_ = _frozen(self.weights_mean_ * factor)
        new.weights_cov_ = _frozen(self.weights_cov_ * factor**2)
        new.residual_rms_ = self.residual_rms_ * abs(factor)
        return new

    # -------------------------------------------------------------- helpers
    def _features(self, phase: np.ndarray) -> np.ndarray:
        """Normalised Gaussian activations, shape (n_points, n_basis)."""
        return _activations(phase, _centres(self.n_basis), self.width_)

    def _grid(self, n_points: Any) -> np.ndarray:
        """:meth:`_features` at ``n_points`` even phases, cached (read-only)."""
        if type(n_points) is not int:  # an int is checked by the cache's miss below
            n_points = check_count(n_points, "n_points")
        features = _GRIDS.get((self.n_basis, self.width_, n_points))
        if features is None:
            features = _grid_features(self.n_basis, self.width_, check_count(n_points, "n_points"))
            if len(_GRIDS) >= 64:
                _GRIDS.clear()
            _GRIDS[(self.n_basis, self.width_, n_points)] = features
        return features

    def _grid_products(self, n_points: Any) -> tuple[np.ndarray, np.ndarray]:
        """At ``n_points`` even phases: the activations' pairwise products ``φ_i φ_j``,
        ``i <= j`` (shape (n_points, b (b + 1) / 2), the pairs ``i < j`` doubled), and
        the flat indices of those pairs in each diagonal block of the weight covariance
        (shape (b (b + 1) / 2, n_dims)): a variance is their product (cached, read-only)."""
        if type(n_points) is not int:
            n_points = check_count(n_points, "n_points")
        key = (self.n_basis, self.width_, n_points, self.n_dims_)
        kept = _GRIDS.get(key)
        if kept is None:
            features = self._grid(n_points)
            b, d = self.n_basis, self.n_dims_
            rows, cols = np.triu_indices(b)
            products = features[:, rows] * features[:, cols]
            products[:, rows != cols] *= 2.0
            blocks = np.arange(d)[None, :] * b
            pairs = (rows[:, None] + blocks) * (d * b) + cols[:, None] + blocks
            kept = (_frozen(products), _frozen(pairs))
            if len(_GRIDS) >= 64:
                _GRIDS.clear()
            _GRIDS[key] = kept
        return kept

    def _band(self, cov: np.ndarray, n_points: int) -> np.ndarray:
        """Variances of the covariance ``cov`` (this model's, now or when a model was
        conditioned on it) at ``n_points`` even phases, kept for the next conditioned
        model's :meth:`std` (read-only)."""
        kept = self.__dict__.get("_band_cache")
        if kept is None or kept[0] is not cov:
            kept = (cov, {})
            self.__dict__["_band_cache"] = kept
        bands = kept[1]
        variances = bands.get(n_points)
        if variances is None:
            variances = _frozen(_variances(cov, *self._grid_products(n_points)))
            if len(bands) >= 8:
                bands.clear()
            bands[n_points] = variances
        return variances

    def _mean_from(self, features: np.ndarray) -> np.ndarray:
        """Mean positions for the activations ``features`` (n, n_basis): shape (n, n_dims)."""
        state = self.__dict__
        kept = state.get("_columns_cache")
        if kept is None or kept[0] is not state.get("weights_mean_"):
            kept = self._mean_columns()
        return np.dot(features, kept[1])

    def _mean_columns(self) -> tuple[np.ndarray, np.ndarray]:
        """``(weights_mean_, its weights basis-major (n_basis, n_dims))``, kept.

        A path is one product of the activations with them: contiguous, not a
        transposed view of the mean (40 % slower). A model conditioned on one
        point set takes them from the kernel's buffer, which holds them.
        """
        state = self.__dict__
        mean = state.get("weights_mean_")
        if mean is None:
            self._check_fitted()
        pending = state.get("_pending_cov")
        if pending is not None and pending[5] is mean:  # the kernel's buffer holds this mean
            out, m, n = pending[1], pending[3], len(mean)
            columns = out[n * (1 + m) + m : n * (2 + m) + m].reshape(-1, state["n_dims_"])
        else:
            columns = _frozen(np.ascontiguousarray(mean.reshape(state["n_dims_"], -1).T))
        kept = state["_columns_cache"] = (mean, columns)
        return kept

    def _feature_slopes(self, phase: np.ndarray) -> np.ndarray:
        """Derivatives of :meth:`_features` in phase, shape (n_points, n_basis).

        With ``φ_i = b_i / Σ b`` and ``b_i' = g_i b_i``, ``g_i = −(s − c_i) / w²``:
        ``φ_i' = φ_i (g_i − Σ_j φ_j g_j)``.
        """
        centres = _centres(self.n_basis)
        features = self._features(phase)
        slopes = -(phase[:, None] - centres) / self.width_**2
        return features * (slopes - np.sum(features * slopes, axis=1, keepdims=True))

    def _covariance_root(self) -> np.ndarray:
        """``R`` with ``R Rᵀ = Σ_w``, kept for this model's covariance array.

        Eigen-decomposition, not Cholesky: the covariance has rank n_demos − 1
        at most. Under one BLAS thread: with OpenBLAS's default threads a
        30 × 30 ``eigh`` took 3–48 ms on a busy machine instead of 0.1 ms.
        """
        cov = self._weights_cov()
        kept = self.__dict__.get("_root_cache")
        if kept is not None and kept[0] is cov:
            return kept[1]
        from lfdkit.core.threads import one_blas_thread  # threadpoolctl: 13 ms to import

        with one_blas_thread():
            values, vectors = np.linalg.eigh(cov)
        root = vectors * np.sqrt(np.clip(values, 0.0, None))
        root.flags.writeable = False
        self._root_cache = (cov, root)
        return root

    def _warn_unreachable(
        self, pts: np.ndarray, phase: np.ndarray, lost: np.ndarray, name: str
    ) -> bool:
        """Warn about the first via-point whose offset lies partly where the model cannot move.

        Returns whether it warned.
        """
        scale = max(float(np.abs(pts).max()), 1.0)
        bad = np.flatnonzero(np.linalg.norm(lost, axis=1) > 1e-6 * scale)
        if not bad.size:
            return False
        i = int(bad[0])
        miss = float(np.linalg.norm(self.mean_at(phase[i : i + 1])[0] - pts[i]))
        warnings.warn(
            f"{name}[{i}]: cannot be reached; the conditioned mean misses it by {miss:.3g}: "
            "the demonstrations never varied that way, or another via-point close in "
            "phase asks otherwise; add demonstrations that vary that way, move the "
            "points apart in phase, or give a covariance > 0",
            UserWarning,
            stacklevel=3,
        )
        return True

    def _check_fitted(self) -> None:
        # The mean: a conditioned model's covariance is formed only when read.
        check_fitted(self, "weights_mean_")


def condition_weights(
    mean: np.ndarray,
    cov: np.ndarray,
    scaled_centres: np.ndarray,
    phases: np.ndarray,
    width: float,
    sets: np.ndarray,
    variance: float,
    noise: np.ndarray,
    rcond: float,
    out: np.ndarray,
) -> int:
    """Condition ``N(mean, cov)`` on ``k`` via-points for each of ``n_sets`` point sets (NumPy).

    The twin of :func:`lfdkit.imitate._promp_kernels.condition_weights` (same
    arguments and results, to rounding); :func:`lfdkit.core.kernels.kernel`
    picks one.

    Parameters
    ----------
    mean : ndarray, shape (n_weights,)
    cov : ndarray, shape (n_weights, n_weights)
        The weights' distribution, dimension-major blocks of ``b`` weights.
    scaled_centres : ndarray, shape (b,)
        Basis centres divided by the basis width.
    phases : ndarray, shape (k,)
        Via-point phases in [0, 1].
    width : float
        Basis width (phase units).
    sets : ndarray, shape (n_sets, k, d)
        The points, in the weights' units.
    variance : float
        Added to every observed coordinate's variance (units²).
    noise : ndarray, shape (k, d, d) or (0, d, d)
        Per-point covariances added too (none for the second shape).
    rcond : float
        Eigenvalues of the innovation covariance at or below ``rcond`` times
        the largest are dropped (pseudo-inverse).
    out : ndarray, shape (n_sets * n_weights + k * d * n_weights + n_sets * k * d,)
        Written, one after the other: the conditioned means (n_sets,
        n_weights); ``Z = Lᵀ H Σ`` (k·d, n_weights; ``L Lᵀ`` the innovation
        covariance's pseudo-inverse, a zero row per dropped direction), from
        which :func:`conditioned_covariance` forms ``Σ' = Σ − Zᵀ Z``; each
        set's offset from the prior mean in the dropped directions (n_sets,
        k·d).

    Returns
    -------
    int
        Directions dropped, or −1 for a point that is not finite or a phase
        outside [0, 1] (nothing written: the caller's full checks say which).
    """
    n_sets, k, d = sets.shape
    b, n_weights, m = len(scaled_centres), len(mean), k * d
    if not (np.all((phases >= 0.0) & (phases <= 1.0)) and np.all(np.isfinite(sets))):
        return -1
    means, root_h, lost, columns, root_h_t = _out_parts(out, n_sets, n_weights, m, d)
    bumps = np.exp(-0.5 * np.square(scaled_centres - (phases / width)[:, None]))
    features = bumps / bumps.sum(axis=1, keepdims=True)
    # Σ Hᵀ: column (i, c) is Σ[:, c-block] φ(s_i); one 2-D product, then reordered.
    cov_h = (cov.reshape(n_weights * d, b) @ features.T).reshape(n_weights, d, k)
    observed = cov_h.transpose(0, 2, 1).reshape(n_weights, m)
    # H Σ Hᵀ: row (i, c) is φ(s_i)ᵀ (Σ Hᵀ)[c-block, :].
    by_block = observed.reshape(d, b, m).transpose(0, 2, 1).reshape(d * m, b)
    gram = (by_block @ features.T).reshape(d, m, k).transpose(2, 0, 1).reshape(m, m)
    gram.flat[:: m + 1] += variance
    for i in range(len(noise)):
        gram[i * d : (i + 1) * d, i * d : (i + 1) * d] += noise[i]
    gram = 0.5 * (gram + gram.T)
    # Pseudo-inverse by eigen-decomposition: the directions it drops are those
    # the model cannot move in, and what of a via-point's offset lies there is missed.
    if m > _SMALL_EIGH:
        from lfdkit.core.threads import one_blas_thread  # threadpoolctl: 13 ms to import

        with one_blas_thread():
            values, vectors = np.linalg.eigh(gram)
    else:
        values, vectors = np.linalg.eigh(gram)
    kept = values > rcond * max(float(values[-1]), _TINY)
    dropped = vectors[:, ~kept]
    # S⁺ = L Lᵀ: Σ' = Σ − Zᵀ Z and μ' = μ + Zᵀ Lᵀ (y − H μ), Z = Lᵀ H Σ.
    root = vectors * np.where(kept, 1.0 / np.sqrt(np.where(kept, values, 1.0)), 0.0)
    root_h[...] = root.T @ observed.T
    prior = (features @ mean.reshape(d, b).T).reshape(m)
    offsets = sets.reshape(n_sets, m) - prior
    means[...] = mean + (offsets @ root) @ root_h
    lost[...] = (offsets @ dropped) @ dropped.T
    columns[...] = means.reshape(n_sets, d, b).transpose(0, 2, 1)
    root_h_t[...] = root_h.reshape(m * d, b).T
    return int(dropped.shape[1])


def condition_point(
    prior: np.ndarray, phase: float, point: np.ndarray, variance: float, out: np.ndarray
) -> int:
    """:func:`condition_weights` for one via-point (``point`` (1, d), ``phase`` a float) with
    a variance, the model given as :meth:`ProMP._kernel_prior`'s ``[width, rcond, mean,
    cov]`` (``out``'s length gives the weights): the twin of
    :func:`lfdkit.imitate._promp_kernels.condition_point`."""
    d = point.shape[1]
    n = (len(out) - d) // (2 * (1 + d))
    width, rcond = float(prior[0]), float(prior[1])
    return condition_weights(
        prior[2 : 2 + n],
        prior[2 + n : 2 + n + n * n].reshape(n, n),
        _scaled_centres(n // d, width),
        np.array([phase]),
        width,
        point.reshape(1, 1, d),
        variance,
        _no_noise(d),
        rcond,
        out,
    )


def condition_points(
    prior: np.ndarray, phases: np.ndarray, points: np.ndarray, variance: float, out: np.ndarray
) -> int:
    """:func:`condition_weights` for one set of ``k`` via-points (``points`` (k, d),
    ``phases`` (k,)) with a variance, the model given as :func:`condition_point`'s:
    the twin of :func:`lfdkit.imitate._promp_kernels.condition_points`."""
    k, d = points.shape
    m = k * d
    n = (len(out) - m) // (2 * (1 + m))
    width, rcond = float(prior[0]), float(prior[1])
    return condition_weights(
        prior[2 : 2 + n],
        prior[2 + n : 2 + n + n * n].reshape(n, n),
        _scaled_centres(n // d, width),
        phases,
        width,
        points.reshape(1, k, d),
        variance,
        _no_noise(d),
        rcond,
        out,
    )


def conditioned_covariance(
    prior: np.ndarray, out: np.ndarray, start: int, m: int, result: np.ndarray
) -> int:
    """``Σ' = Σ − Zᵀ Z`` into ``result`` (n, n) from :func:`condition_point`'s model ``prior``
    and :func:`condition_weights`' buffer ``out`` (``Z`` (m, n) at ``start``): the twin of
    :func:`lfdkit.imitate._promp_kernels.conditioned_covariance`."""
    n = len(result)
    root_h = out[start : start + m * n].reshape(m, n)
    np.subtract(prior[2 + n : 2 + n + n * n].reshape(n, n), root_h.T @ root_h, out=result)
    return 0


def conditioned_covariance_rows(
    prior: np.ndarray, out: np.ndarray, start: int, m: int, result: np.ndarray
) -> int:
    """:func:`conditioned_covariance` for an exactly symmetric ``Σ``: the twin of
    :func:`lfdkit.imitate._promp_kernels.conditioned_covariance_rows` (NumPy's product
    needs no other form)."""
    return conditioned_covariance(prior, out, start, m, result)


def _variances(cov: np.ndarray, products: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """Variances of each coordinate, shape (n_points, n_dims), from :meth:`ProMP._grid_products`.

    Only the upper triangles of the diagonal blocks ``Σ_w[k-block, k-block]``
    matter: one gather and one product with the activations' pairwise products,
    the off-diagonal ones doubled (a product per block, a multiply and a sum
    were 2.4× the time).
    """
    return products @ cov.take(pairs)


def _out_size(n_sets: int, n_weights: int, m: int) -> int:
    """Length of :func:`condition_weights`' buffer for ``m`` observed coordinates."""
    return 2 * (n_sets + m) * n_weights + n_sets * m


def _out_parts(
    out: np.ndarray, n_sets: int, n_weights: int, m: int, n_dims: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Views of :func:`condition_weights`' buffer: means (n_sets, n_weights), ``Z = Lᵀ H Σ``
    (m, n_weights), lost (n_sets, m), the means basis-major (n_sets, b, n_dims) and ``Z``
    split by dimension, transposed (b, m · n_dims)."""
    b = n_weights // n_dims
    root_at = n_sets * n_weights
    lost_at = root_at + m * n_weights
    columns_at = lost_at + n_sets * m
    root_t_at = columns_at + n_sets * n_weights
    return (
        out[:root_at].reshape(n_sets, n_weights),
        out[root_at:lost_at].reshape(m, n_weights),
        out[lost_at:columns_at].reshape(n_sets, m),
        out[columns_at:root_t_at].reshape(n_sets, b, n_dims),
        out[root_t_at:].reshape(b, m * n_dims),
    )


@functools.lru_cache(maxsize=16)
def _summing(n_rows: int, n_dims: int) -> np.ndarray:
    """``n_rows`` identities of size ``n_dims`` stacked, shape (n_rows · n_dims, n_dims):
    a product with it sums every ``n_dims``-th column (read-only: shared)."""
    return _frozen(np.tile(np.eye(n_dims), (n_rows, 1)))


@functools.lru_cache(maxsize=8)
def _no_noise(n_dims: int) -> np.ndarray:
    """No per-point covariance, shape (0, n_dims, n_dims) (read-only: shared)."""
    return _frozen(np.zeros((0, n_dims, n_dims)))


def _frozen(array: np.ndarray) -> np.ndarray:
    """``array`` made read-only: the per-phase factors and the sampling root kept
    on a model are valid only while its weight arrays do not change in place."""
    array.flags.writeable = False
    return array


def _floats(values: Any) -> np.ndarray:
    """``values`` as a float array: a float array as it is (a third of the conversion's cost)."""
    if type(values) is np.ndarray and values.dtype == float:
        return values
    return np.asarray(values, dtype=float)


def _even_phases(n_points: Any) -> np.ndarray:
    return np.linspace(0.0, 1.0, check_count(n_points, "n_points", minimum=1))


@functools.lru_cache(maxsize=64)
def _centres(n_basis: int) -> np.ndarray:
    """Evenly spaced basis centres over [0, 1] (read-only: the cache shares them)."""
    centres = np.linspace(0.0, 1.0, n_basis)
    centres.flags.writeable = False
    return centres


def _activations(phase: np.ndarray, centres: np.ndarray, width: float) -> np.ndarray:
    """Normalised Gaussian bumps of standard deviation ``width``, shape (n, n_basis)."""
    bumps = np.exp(-0.5 * ((phase[:, None] - centres) / width) ** 2)
    return bumps / bumps.sum(axis=1, keepdims=True)


@functools.lru_cache(maxsize=64)
def _scaled_centres(n_basis: int, width: float) -> np.ndarray:
    """Centres over the width, for one phase's activations in three ufunc calls."""
    scaled = _centres(n_basis) / width
    scaled.flags.writeable = False
    return scaled


@functools.lru_cache(maxsize=64)
def _grid_features(n_basis: int, width: float, n_points: int) -> np.ndarray:
    """Activations at ``n_points`` even phases: paths, bands and samples reuse them."""
    features = _activations(np.linspace(0.0, 1.0, n_points), _centres(n_basis), width)
    features.flags.writeable = False
    return features


def _check_phases(phases: Any, name: str) -> np.ndarray:
    """Phases as a 1-D array, each in [0, 1]; one-line error naming the first outside."""
    s = check_values(phases, name)
    inside = (s >= 0.0) & (s <= 1.0)
    if not inside.all():
        i = int(np.flatnonzero(~inside)[0])
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


def _check_covariance(covariance: Any, n_via: int, n_dims: int) -> float | np.ndarray:
    """A variance for every coordinate (float) or per-point covariances (n_via, n_dims, n_dims)."""
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
        return variance
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
    # Read-only like the model's weights: the compiled kernel is then typed (and compiled) once.
    return _frozen(np.array(arr))
