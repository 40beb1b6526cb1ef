"""One direction for all demonstrations, and a check that they show one motion.

Every mimicking method (:class:`~lfdkit.mimic.MeanPath`, :class:`~lfdkit.mimic.GMR`,
:class:`~lfdkit.mimic.NLPCA`, :func:`~lfdkit.mimic.pointwise_average`) calls the
same two functions, so reversed and multi-motion demonstrations are handled
alike whatever the method:

* :func:`orient_demos` before fitting: a demonstration recorded in the
  direction opposite to the majority is reversed, with a
  :class:`DemoOrientationWarning`; one whose direction cannot be told
  (it looks the same both ways round, e.g. a there-and-back stroke) is refused
  with a ``ValueError`` naming it, and a group of demonstrations that fits
  the rest as badly forwards as backwards (motions into one goal from
  different sides, LASA's ``Multi_Models``) with :class:`SeveralMotionsError`.
* :func:`check_one_motion` after fitting: a generalized path shorter than
  :data:`MIN_LENGTH_RATIO` times the median demonstration length means the
  method averaged several different motions into a stub, and raises
  :class:`SeveralMotionsError`. A path whose length is outside
  :data:`LENGTH_WARNING_RANGE` (0.8 to 1.25 times the median) gets a
  :class:`PathLengthWarning` with the reason, unless the demonstrations'
  own lengths differ that much (partial demonstrations) and the path lies
  among them: a path cut short or run past the demonstrations' ends is
  wrong in a way no error measured along normals shows.

Direction is decided from the whole path, not from its end points: each
demonstration is resampled evenly in arc length and compared point by point
with every other one, as recorded and reversed. Closed or nearly closed
demonstrations (a handwritten "o", start ≈ end) are therefore oriented as
reliably as open ones.
"""

from __future__ import annotations

import itertools
import warnings
from collections.abc import Sequence

import numpy as np

from lfdkit.core.geometry import arc_length, path_length
from lfdkit.core.threads import one_blas_thread

__all__ = [
    "LENGTH_WARNING_RANGE",
    "MIN_LENGTH_RATIO",
    "DemoOrientationWarning",
    "PathLengthWarning",
    "SeveralMotionsError",
    "check_one_motion",
    "orient_demos",
]

#: A generalized path shorter than this fraction of the median demonstration is refused.
MIN_LENGTH_RATIO = 0.3
#: A generalized path outside this range of the median demonstration length is
#: warned about (unless partial demonstrations explain it).
LENGTH_WARNING_RANGE = (0.8, 1.25)
#: Samples per demonstration for the direction comparison (arc-length resampled).
_N_SAMPLES = 64
#: A demonstration whose forward and reversed distances to the others differ by
#: less than this fraction of their sum has no decidable direction.
_MIN_MARGIN = 0.02
#: A group of demonstrations fitting the rest forwards and backwards within this
#: fraction of the distances is taken for another motion.
_MIN_SPLIT_MARGIN = 0.1
#: Chords through which a demonstration's length is measured (check_one_motion).
_LENGTH_CHORDS = 16
#: Up to this many demonstrations every assignment of directions is tried.
_EXHAUSTIVE = 12


class DemoOrientationWarning(UserWarning):
    """Some demonstrations were reversed to follow the majority's direction."""


class PathLengthWarning(UserWarning):
    """A generalized path much shorter or longer than the demonstrations."""


class SeveralMotionsError(ValueError):
    """The demonstrations look like several different motions, not one."""


def orient_demos(
    demos: Sequence[np.ndarray],
    *,
    reference: np.ndarray | None = None,
    method: str = "mimic",
) -> tuple[list[np.ndarray], np.ndarray]:
    """Reverse the demonstrations that run against the majority's direction.

    Parameters
    ----------
    demos : sequence of ndarray, each shape (n_j, q)
        Validated demonstrations (finite, at least 2 points each, any q).
    reference : ndarray, shape (n, q), optional
        A path (e.g. a given initial path) that decides which of the two
        directions the demonstrations, once they agree, are given: all are
        reversed together when the majority runs against it. It never
        decides a single demonstration.
    method : str
        Name of the caller, for the messages.

    Returns
    -------
    oriented : list of ndarray
        The demonstrations, the reversed ones as reversed copies.
    reversed_mask : ndarray of bool, shape (n_demos,)
        Which demonstrations were reversed.

    Raises
    ------
    ValueError
        If the direction of a demonstration cannot be decided (it is about as
        close to the others forwards as backwards); the message names it.
    SeveralMotionsError
        If a group of demonstrations fits the rest about as badly forwards as
        backwards (e.g. motions into one goal from different sides); the
        message names the smaller group. With a ``reference``, such groups
        are oriented against it one by one instead.

    Warns
    -----
    DemoOrientationWarning
        When any demonstration is reversed (the message names them).

    Notes
    -----
    With ``D⁺ᵢⱼ`` and ``D⁻ᵢⱼ`` the mean distance between demonstrations ``i``
    and ``j`` resampled evenly in arc length, with ``j`` as recorded and
    reversed, the directions ``xᵢ = ±1`` maximise
    ``Σᵢⱼ xᵢ xⱼ (D⁻ᵢⱼ − D⁺ᵢⱼ)``; then the sign is chosen so that most
    demonstrations keep their recorded direction (on a tie, demonstration 0).
    A demonstration that never moves has no direction and is left as it is.
    """
    n = len(demos)
    sampled = [_sample(d) for d in demos]
    moving = np.array([path_length(d) > 0 for d in demos])
    signs = np.ones(n)
    index = np.flatnonzero(moving)
    if index.size >= 2:
        m = index.size
        stack = np.array([sampled[j] for j in index])  # (m, samples, q)
        fwd = np.zeros((m, m))
        bwd = np.zeros((m, m))
        if stack.shape[2] == 2 and stack.shape[1] <= 128:  # compiled: the same numbers, 2 ms not 25
            from lfdkit.mimic._mean_path_kernels import pair_distances

            pair_distances(stack, fwd, bwd)
        else:
            for a in range(m - 1):
                # Demonstration a against every later one, forwards and backwards.
                fwd[a, a + 1 :] = _mean_distances(stack[a], stack[a + 1 :])
                bwd[a, a + 1 :] = _mean_distances(stack[a], stack[a + 1 :, ::-1])
        fwd += fwd.T
        bwd += bwd.T
        x = _best_signs(bwd - fwd)
        n_flipped = np.count_nonzero(x < 0)
        if n_flipped * 2 > m or (n_flipped * 2 == m and x[0] < 0):
            x = -x
        # Each demonstration against the others, as oriented.
        agree = x[:, None] * x[None, :] > 0
        same = np.where(agree, fwd, bwd).sum(axis=1)
        other = np.where(agree, bwd, fwd).sum(axis=1)
        undecided = _margin(same, other) < _MIN_MARGIN
        if reference is None:
            _refuse_undecided(index, undecided, method, "the other demonstrations")
            _refuse_split(index, x, bwd - fwd, bwd + fwd, method)
        else:
            try:
                _refuse_split(index, x, bwd - fwd, bwd + fwd, method)
            except SeveralMotionsError:
                undecided[:] = True  # groups that do not overlap: the reference decides each
        signs[index] = x
    else:
        undecided = np.zeros(index.size, dtype=bool)
    if reference is not None and index.size:
        # The reference gives the agreeing demonstrations their direction and decides,
        # one by one, those the others could not (e.g. demonstrations that do not overlap).
        ref = _sample(reference)
        with_ref = np.array([_mean_distance(ref, sampled[j]) for j in index])
        against_ref = np.array([_mean_distance(ref, sampled[j][::-1]) for j in index])
        if np.sum((signs[index] * (against_ref - with_ref))[~undecided]) < 0:
            signs[index] = -signs[index]
        alone = _margin(with_ref, against_ref)
        signs[index[undecided]] = np.where(alone[undecided] < 0, -1.0, 1.0)
        _refuse_undecided(
            index, undecided & (np.abs(alone) < _MIN_MARGIN), method, "the initial path"
        )
    flipped = signs < 0
    oriented = [d[::-1].copy() if f else d for d, f in zip(demos, flipped, strict=True)]
    if flipped.any():
        which = ", ".join(str(j) for j in np.flatnonzero(flipped))
        warnings.warn(
            f"{method}: reversed demonstration(s) {which} of {n} to run in the "
            + ("direction of the initial path" if reference is not None else "others' direction"),
            DemoOrientationWarning,
            stacklevel=3,
        )
    return oriented, flipped


def check_one_motion(
    path: np.ndarray,
    demos: Sequence[np.ndarray],
    method: str = "mimic",
    *,
    times: Sequence[np.ndarray] | None = None,
    hint: str = "",
) -> float:
    """Refuse a generalized path much shorter than the demonstrations; warn of an odd length.

    Averaging demonstrations of different motions (e.g. into one goal from
    opposite sides) cancels them out into a short stub: a path shorter than
    :data:`MIN_LENGTH_RATIO` times the median demonstration length is refused.
    A path outside :data:`LENGTH_WARNING_RANGE` times that median gets a
    :class:`PathLengthWarning`, unless the demonstrations' lengths themselves
    spread beyond that range (some cover only part of the task) and the path's
    length lies between the shortest and the longest.

    Parameters
    ----------
    path : ndarray, shape (n, q)
        The fitted generalized path.
    demos : sequence of ndarray, each shape (n_j, q)
        The demonstrations it was fitted to.
    method : str
        Name of the caller, for the message.
    times : sequence of ndarray, each shape (n_j,), optional
        Sample times of the demonstrations, when their rows are not in time order.
    hint : str
        What the caller's user can change, appended to the warning.

    Returns
    -------
    float
        The path's length over the median demonstration length.

    Raises
    ------
    SeveralMotionsError
        With both lengths in the message.

    Notes
    -----
    Lengths are measured through :data:`_LENGTH_CHORDS` + 1 samples, evenly
    spaced in time order, of the path and of each demonstration: noise between
    neighbouring samples would lengthen a dense, noisy recording's full polyline
    many times over while the smooth path's stays as it is.
    """
    if times is not None:
        demos = [d[np.argsort(t, kind="stable")] for d, t in zip(demos, times, strict=True)]
    lengths = np.array([_coarse_length(d) for d in demos])
    median = float(np.median(lengths))
    length = _coarse_length(path)
    if not median > 0:
        return float("nan")
    ratio = length / median
    if not ratio >= MIN_LENGTH_RATIO:
        raise SeveralMotionsError(
            f"demos: the demonstrations look like several motions, not one: the {method} "
            f"path is {length:.4g} long, {ratio:.2f} times the median demonstration "
            f"length {median:.4g} (at least {MIN_LENGTH_RATIO} expected); learn each motion "
            "from its own demonstrations"
        )
    low, high = LENGTH_WARNING_RANGE
    shortest, longest = float(lengths.min()), float(lengths.max())
    partial = longest > high / low * shortest and shortest <= length <= longest
    if not low <= ratio <= high and not partial:
        reason = (
            "it stops short of where the demonstrations start or end"
            if ratio < low
            else "it runs past where the demonstrations start or end"
        )
        warnings.warn(
            f"{method}: the generalized path is {ratio:.2f} times the median demonstration "
            f"length ({length:.4g} against {median:.4g}; the demonstrations measure "
            f"{shortest:.4g} to {longest:.4g}), outside {low} to {high}: {reason}. Plot it "
            f"against the demonstrations before using it{hint}",
            PathLengthWarning,
            stacklevel=3,
        )
    return float(ratio)


def _coarse_length(demo: np.ndarray) -> float:
    picks = np.unique(np.linspace(0, len(demo) - 1, _LENGTH_CHORDS + 1).round().astype(int))
    return path_length(demo[picks])


def _sample(demo: np.ndarray) -> np.ndarray:
    """Evenly in arc length, any dimension (GMR and NLPCA accept 1-D demonstrations)."""
    s = arc_length(demo)
    if s[-1] <= 0:  # never moves: every sample is its one point
        return np.repeat(demo[:1], _N_SAMPLES, axis=0)
    grid = np.linspace(0.0, s[-1], _N_SAMPLES)
    return np.column_stack([np.interp(grid, s, demo[:, k]) for k in range(demo.shape[1])])


def _mean_distance(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.mean(np.linalg.norm(a - b, axis=1)))


def _mean_distances(a: np.ndarray, others: np.ndarray) -> np.ndarray:
    """:func:`_mean_distance` of ``a`` (samples, q) to each of ``others`` (k, samples, q)."""
    return np.mean(np.linalg.norm(others - a[None], axis=2), axis=1)


def _best_signs(gain: np.ndarray) -> np.ndarray:
    """Signs ``x`` maximising ``xᵀ G x`` (``G`` symmetric, zero diagonal), ``x[0] = +1``.

    Exhaustive for few demonstrations; otherwise the leading eigenvector's
    signs, improved one flip at a time until no flip helps.
    """
    n = gain.shape[0]
    if n <= _EXHAUSTIVE:
        best = np.ones(n)
        best_value = best @ gain @ best
        # Strictly better only: on a tie the assignment with fewer flips (listed first) stays.
        for rest in itertools.product((1.0, -1.0), repeat=n - 1):
            x = np.array((1.0, *rest))
            value = x @ gain @ x
            if value > best_value + 1e-12 * max(1.0, abs(best_value)):
                best, best_value = x, value
        return best
    with one_blas_thread():  # threaded BLAS stalls on a small matrix when cores are busy
        _, vectors = np.linalg.eigh(gain)
        x = np.where(vectors[:, -1] >= 0, 1.0, -1.0)
        for _ in range(n):
            # Flipping x_i changes xᵀGx by −4 x_i (G x)_i.
            change = -4.0 * x * (gain @ x)
            i = int(np.argmax(change))
            if change[i] <= 0:
                break
            x[i] = -x[i]
    return x * x[0]


def _refuse_split(
    index: np.ndarray, x: np.ndarray, gain: np.ndarray, total: np.ndarray, method: str
) -> None:
    """Refuse a group of demonstrations whose direction relative to the rest is a toss-up.

    Two motions into one goal from opposite sides agree within each group,
    but forwards and backwards fit the other group equally badly: no
    direction of one group against the other is right. Every split into two
    groups is tried (up to :data:`_EXHAUSTIVE` demonstrations; beyond, the
    sign split of the second eigenvector of the agreement matrix).
    """
    m = x.size
    agreement = x[:, None] * x[None, :] * gain
    if m <= _EXHAUSTIVE:
        bits = (np.arange(1, 2 ** (m - 1))[:, None] >> np.arange(m - 1)[None, :]) & 1
        groups = np.column_stack((np.zeros(len(bits), dtype=int), bits)).astype(float)
    else:
        with one_blas_thread():
            _, vectors = np.linalg.eigh(agreement)
        groups = np.vstack(((vectors[:, -2] >= 0).astype(float), np.eye(m)))
        groups = groups[(groups.sum(axis=1) > 0) & (groups.sum(axis=1) < m)]
    if not len(groups):
        return
    others = 1.0 - groups
    # One BLAS thread: threads spinning on busy cores cost 100 demonstrations 15 ms of
    # CPU against 2, for a product of (m + 1, m) by (m, m).
    with one_blas_thread():
        cross = np.sum((groups @ agreement) * others, axis=1)
        scale = np.sum((groups @ total) * others, axis=1)
    margin = np.divide(cross, scale, out=np.ones_like(cross), where=scale > 0)
    worst = int(np.argmin(margin))
    if margin[worst] < _MIN_SPLIT_MARGIN:
        members = groups[worst] if groups[worst].sum() <= m / 2 else others[worst]
        named = ", ".join(str(int(index[k])) for k in np.flatnonzero(members))
        raise SeveralMotionsError(
            f"demos: the demonstrations look like several motions, not one: demonstration(s) "
            f"{named} fit the others about as badly forwards as backwards, so {method} cannot "
            "tell which way they run (e.g. motions into one goal from different sides); "
            "learn each motion from its own demonstrations"
        )


def _margin(same: np.ndarray, other: np.ndarray) -> np.ndarray:
    """How much closer as oriented than reversed, as a fraction of both distances."""
    total = same + other
    return np.divide(other - same, total, out=np.zeros_like(total), where=total > 0)


def _refuse_undecided(index: np.ndarray, undecided: np.ndarray, method: str, against: str) -> None:
    """Refuse the first demonstration whose direction is a toss-up."""
    if undecided.any():
        j = int(index[np.argmax(undecided)])
        raise ValueError(
            f"demos[{j}]: its direction cannot be decided: it is about as close to {against} "
            f"forwards as backwards ({method} needs them all to run one way; a there-and-back "
            "stroke, or demonstrations of different motions?)"
        )
