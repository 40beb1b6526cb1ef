"""Via-points: bend a path through given points the way the demonstrations varied.

What: a path ``y(s)`` at phases ``s`` in [0, 1] (a DMP's nominal; the skill
uses the fraction of its length, as its ProMP does) plus a
deformation ``δ(s) = Ψ(s) Δw`` in a ProMP's basis, ``Δw ~ N(0, Σ)``, is
conditioned (:meth:`lfdkit.imitate.ProMP.condition`, exact) on

- ``δ(0) = 0`` and ``δ(1) = 0``: the start and goal stay where they were put;
- ``δ(s_i) = p_i − y(s_i)`` for each via-point ``(s_i, p_i)``.

The conditioned mean bends the path through every via-point; the conditioned
covariance is the band left around it (pinched to zero at the ends and at
each via-point).

Why this design:

- **The DMP keeps the start, goal and shape; the ProMP says how to bend it.**
  ``Σ`` is the weight covariance of the demonstrations
  (:attr:`lfdkit.imitate.ProMP.weights_cov_`): a via-point where the
  demonstrations varied is reached by moving the path as they moved (a wider
  swing lifts the whole arc, not a spike). Conditioning a ProMP's own mean
  instead would lose the DMP's retargeting to a new start and goal, which
  the ProMP does only within the demonstrations' spread.
- **Always exact.** ``Σ`` has rank ``n_demos − 1`` at most: three 2-D
  constraints (start, goal, one via-point) already need 6 directions. An
  isotropic part, :data:`ISOTROPIC_SHARE` times ``Σ``'s mean variance (or,
  for identical demonstrations or a skill without a ProMP,
  ``(1e-3 · extent)²``), lets the smooth basis reach any point; a direction
  the demonstrations used much is still far cheaper (one dominant direction
  among 2 × 15 weights: 30 times), so it is used first. Only via-points
  closer in phase than the basis resolves (about ``1 / n_basis``) still
  conflict, and :meth:`~lfdkit.imitate.ProMP.condition` warns with the
  distance missed.
- **How much to trust the demonstrations' directions** (the share, 1) was
  measured held out (``benchmarks/via_points.py``, 5 folds of walking, 4 of
  da_vinci): at 0.01 the bending follows the demonstrations' covariance
  closely and lands farther from the held-out demonstration (walking, 3
  via-points: 4.9 cm RMS) than at 1 (4.0 cm); a smooth bending with no
  preferred direction does as well or better on these real sets (3.9 cm),
  so the covariance is only allowed to lead, not to dominate. On shapes the
  demonstrations truly share (arches of different heights) it is what makes
  the whole arch rise instead of a bump (tests/imitate/test_via_points.py).
- **The via-point is a sample of the result**, inserted at its phase: the
  conditioning reaches it to rounding (1e-13 of its scale), and the sample is
  then set to it, as the ends are set to the path's own, exactly.
- **An orientation at a via-point** (``(phase, point, [x, y, z, w])``,
  :func:`orientations_through_via`) bends the orientation movement ``q(u)``
  by a rotation field: ``q'(u) = exp(c(u)) ⊗ q(u)``, with ``c`` (half-angle
  rotation vectors, the log map of :mod:`lfdkit.core.rotations`) the same
  smooth isotropic basis conditioned to 0 at both ends and to
  ``log(q_i ⊗ q(s_i)⁻¹)`` at each via-point. Start and goal orientation stay
  exact, each via-point's is met to rounding (then set to the bit), the result
  is unit and continuous; the correction is spread over ±0.1 of the movement
  as the position's is (a via-point within 0.1 of an end is overshot by up to
  14 % of its turn between, as the basis rises from 0 that quickly). No
  demonstrated covariance: the skill learns no orientation ProMP.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from lfdkit.core.rotations import UNIT_NORM_TOLERANCE, conjugate, exp, log, multiply, stable_norm
from lfdkit.core.validation import check_path, check_values
from lfdkit.imitate.promp import ProMP

__all__ = [
    "DEFORMATION_BASIS",
    "ISOTROPIC_SHARE",
    "SPREAD_SHARE",
    "ViaPath",
    "check_via",
    "check_via_orientations",
    "orientations_through_via",
    "through_via_points",
]

#: Basis functions per dimension of the deformation when no ProMP is given
#: (and of the skill's ProMP, :attr:`lfdkit.skill.Skill.promp_`): 15 resolve
#: via-points about 0.07 apart in phase; the bending spreads over ±0.1 of the
#: movement around each.
DEFORMATION_BASIS = 15

#: The isotropic part of the deformation's weight covariance, as a share of the
#: demonstrations' mean weight variance (see the module notes: measured held out).
ISOTROPIC_SHARE = 1.0

#: The isotropic share of the band's covariance (:attr:`ViaPath.spread`): small, so
#: the band is the demonstrations' (within 2 % at the top of the tested arches), yet
#: enough that pinning the ends does not hang on rounding in directions they never used.
SPREAD_SHARE = 0.01


@dataclass(frozen=True)
class ViaPath:
    """A path bent through via-points.

    Attributes
    ----------
    points : ndarray, shape (n + n_via, q)
        The path with one sample inserted at each via-point's phase, bent.
    phases : ndarray, shape (n + n_via,)
        Phase of each sample, non-decreasing, 0 to 1.
    deformation : ProMP
        The conditioned deformation ``δ``: its mean is ``points`` minus the
        input path (its covariance includes the isotropic part that makes
        every point reachable).
    spread : ProMP
        The demonstrations' spread alone (their weight covariance, zero mean)
        conditioned on the same points: its
        :meth:`~lfdkit.imitate.ProMP.covariance_at` is the band left around
        the result (units²), pinched at the ends and at each via-point
        (with :data:`SPREAD_SHARE` of isotropic variance); with no ProMP, a
        band of about 1e-3 of the path's extent.
    miss : ndarray, shape (n_via,)
        Distance from each via-point to the result's sample at its phase
        (units): 0 (the sample is the via-point, to the bit), unless a
        :class:`UserWarning` said it cannot be reached.
    """

    points: np.ndarray
    phases: np.ndarray
    deformation: ProMP
    spread: ProMP
    miss: np.ndarray

    def std(self) -> np.ndarray:
        """Standard deviation of each coordinate at each sample, shape (n + n_via, q), units."""
        cov = self.spread.covariance_at(self.phases)
        return np.sqrt(np.clip(np.einsum("nii->ni", cov), 0.0, None))


def check_via(via: Any, n_dims: int, name: str = "via") -> tuple[np.ndarray, np.ndarray]:
    """Via-points as phases and points, each checked; one-line errors naming the entry.

    Parameters
    ----------
    via : sequence of (float, array_like (n_dims,)[, array_like (4,)])
        ``(phase, point)`` pairs: the phase is the fraction of the movement's
        duration (strictly between 0 and 1) at which it passes ``point``; an
        optional third item, the orientation there, is checked by
        :func:`check_via_orientations`.
    n_dims : int
        Coordinates of a point.
    name : str
        The argument's name in messages.

    Returns
    -------
    phases : ndarray, shape (n_via,)
    points : ndarray, shape (n_via, n_dims)

    Raises
    ------
    ValueError
        For an entry that is not a pair, a phase outside (0, 1) or not a
        number, or a point of the wrong dimension or not finite.
    """
    if isinstance(via, (str, bytes)) or not hasattr(via, "__len__") or len(via) == 0:
        raise ValueError(
            f"{name}: expected a list of (phase, point) pairs, got {via!r:.60}; "
            "e.g. [(0.5, (0.3, 0.2))]"
        )
    phases, points = [], []
    for i, entry in enumerate(via):
        where = f"{name}[{i}]"
        if (
            isinstance(entry, (str, bytes))
            or not hasattr(entry, "__len__")
            or len(entry) not in (2, 3)
        ):
            raise ValueError(
                f"{where}: expected a (phase, point) pair or (phase, point, orientation), "
                f"got {entry!r:.60}"
            )
        phase, point = entry[0], entry[1]
        if isinstance(phase, bool) or not isinstance(phase, (int, float, np.number)):
            raise ValueError(f"{where}: phase: expected a number in (0, 1), got {phase!r:.30}")
        phase = float(phase)
        if not 0.0 < phase < 1.0:
            raise ValueError(
                f"{where}: phase {phase:g} is outside (0, 1); give the fraction of the "
                "movement's duration at which to pass the point (0 is the start, 1 the goal: "
                "set those as start and goal)"
            )
        coords = check_values(point, f"{where}: point")
        if coords.shape != (n_dims,):
            raise ValueError(
                f"{where}: point has {coords.size} coordinates; this skill is {n_dims}-D"
            )
        phases.append(phase)
        points.append(coords)
    return np.array(phases), np.array(points)


def check_via_orientations(via: Any, name: str = "via") -> tuple[np.ndarray, np.ndarray]:
    """The via-points' orientations (the entries that give one), checked; one-line errors.

    Parameters
    ----------
    via : sequence
        As :func:`check_via` takes it (checked there); an entry's third item,
        if given and not None, is a unit quaternion ``[x, y, z, w]``.
    name : str
        The argument's name in messages.

    Returns
    -------
    phases : ndarray, shape (n_oriented,)
    orientations : ndarray, shape (n_oriented, 4)
        Normalised (norms within :data:`lfdkit.core.rotations.UNIT_NORM_TOLERANCE`
        of 1 are accepted, as for a start orientation).

    Raises
    ------
    ValueError
        For an orientation that is not 4 finite numbers of norm 1.
    """
    phases, turns = [], []
    for i, entry in enumerate(via):
        if len(entry) < 3 or entry[2] is None:
            continue
        where = f"{name}[{i}]: orientation"
        q = check_values(entry[2], where).ravel()
        if q.shape != (4,):
            raise ValueError(
                f"{where}: has {q.size} values; give a unit quaternion [x, y, z, w] (4 values)"
            )
        norm = float(stable_norm(q))
        if abs(norm - 1.0) > UNIT_NORM_TOLERANCE:
            raise ValueError(
                f"{where}: has norm {norm:.6g}; a unit quaternion's norm is 1 (within "
                f"{UNIT_NORM_TOLERANCE:g}): normalise it"
            )
        phases.append(float(entry[0]))
        turns.append(q / norm)
    return np.array(phases), np.array(turns).reshape(-1, 4)


def orientations_through_via(
    phases: Any,
    orientations: Any,
    via_phases: np.ndarray,
    via_orientations: np.ndarray,
    at_via: np.ndarray,
) -> np.ndarray:
    """Bend an orientation movement through via-orientations, keeping its ends (module notes).

    Parameters
    ----------
    phases : array_like, shape (n,)
        Phase of each orientation, in [0, 1].
    orientations : array_like, shape (n, 4)
        The movement ``q(u)`` at ``phases``, unit quaternions ``[x, y, z, w]``.
    via_phases : ndarray, shape (n_via,)
        Strictly between 0 and 1 (:func:`check_via_orientations`).
    via_orientations : ndarray, shape (n_via, 4)
        Unit quaternions to have at ``via_phases``.
    at_via : ndarray, shape (n_via, 4)
        The movement ``q(u)`` at ``via_phases`` (unbent).

    Returns
    -------
    ndarray, shape (n, 4)
        ``exp(c(u)) ⊗ q(u)``: unchanged at phases 0 and 1, exactly
        ``via_orientations[i]`` (up to sign) at ``via_phases[i]``.

    Warns
    -----
    UserWarning
        When via-points closer in phase than the basis resolves ask for
        different turns (:meth:`lfdkit.imitate.ProMP.condition`).
    """
    u = np.asarray(phases, dtype=np.float64)
    q = np.asarray(orientations, dtype=np.float64)
    if len(via_phases) == 0:
        return q.copy()
    # The turn still needed at each via-point, as a left (world-frame) rotation.
    turns = log(multiply(via_orientations, conjugate(at_via)))
    prior = _deformation_prior(None, 3, np.pi, ISOTROPIC_SHARE)
    targets = np.concatenate([np.zeros((2, 3)), turns])
    field = prior.condition(targets, np.concatenate([[0.0, 1.0], via_phases]))
    out = multiply(exp(field.mean_at(u)), q)
    out /= stable_norm(out, keepdims=True)
    out[u <= 0.0], out[u >= 1.0] = q[u <= 0.0], q[u >= 1.0]
    # Met to rounding (1e-13 rad): set to the bit where a sample is at a via-point.
    for s, target in zip(via_phases, via_orientations, strict=True):
        hit = u == s
        out[hit] = np.where((out[hit] @ target < 0.0)[:, None], -target, target)
    return out


def through_via_points(
    path: Any,
    phases: Any,
    via_phases: np.ndarray,
    via_points: np.ndarray,
    promp: ProMP | None = None,
) -> ViaPath:
    """Bend ``path`` through via-points, keeping its ends (see the module notes).

    Parameters
    ----------
    path : array_like, shape (n, q)
        The path, e.g. a DMP rollout at equal time steps.
    phases : array_like, shape (n,)
        Phase of each sample of ``path``, non-decreasing from 0 to 1 (a
        repeated phase where the path rests), in the ProMP's phase.
    via_phases, via_points : ndarray, shapes (n_via,) and (n_via, q)
        As :func:`check_via` returns them.
    promp : ProMP, optional
        A ProMP fitted on the demonstrations, in the same units and dimension:
        its weight covariance shapes the bending. Default: a smooth bending in
        :data:`DEFORMATION_BASIS` basis functions, with no preferred direction.

    Returns
    -------
    ViaPath

    Warns
    -----
    UserWarning
        From :meth:`lfdkit.imitate.ProMP.condition` when via-points too close
        in phase ask for different points (the message names the first).
    """
    path = check_path(path, "path", min_points=2)
    q = path.shape[1]
    s = check_values(phases, "phases")
    if s.shape != (len(path),) or s[0] != 0.0 or s[-1] != 1.0 or np.any(np.diff(s) < 0.0):
        raise ValueError("phases: expected one non-decreasing phase per path sample, from 0 to 1")
    extent = float(np.ptp(path, axis=0).max())
    prior = _deformation_prior(promp, q, extent, ISOTROPIC_SHARE)
    # One sample at each via-point's phase, so the result passes through it.
    order = np.argsort(np.concatenate([s, via_phases]), kind="stable")
    inserted = np.column_stack([np.interp(via_phases, s, path[:, k]) for k in range(q)])
    all_phases = np.concatenate([s, via_phases])[order]
    base = np.concatenate([path, inserted])[order]
    ends = np.array([0.0, 1.0])
    targets = np.concatenate([np.zeros((2, q)), via_points - inserted])
    pinned = np.concatenate([ends, via_phases])
    bent = prior.condition(targets, pinned)
    with warnings.catch_warnings():
        # The band: the demonstrations' own spread, pinned where the path is; what
        # it cannot reach was said (or not) by the bending's conditioning above.
        warnings.simplefilter("ignore")
        zero = np.zeros_like(targets)
        spread = _deformation_prior(promp, q, extent, SPREAD_SHARE).condition(zero, pinned)
    points = base + bent.mean_at(all_phases)
    position = np.empty_like(order)
    position[order] = np.arange(len(order))  # where each input sample went
    at_via = position[len(s) :]
    miss = np.linalg.norm(points[at_via] - via_points, axis=1)
    # The conditioning is exact to rounding: make it exact to the bit where it is.
    points[0], points[-1] = path[0], path[-1]
    scale = max(float(np.abs(base).max()), float(np.abs(via_points).max(initial=0.0)), 1e-300)
    reached = miss <= 1e-9 * scale
    points[at_via[reached]] = via_points[reached]
    miss[reached] = 0.0
    return ViaPath(points, all_phases, bent, spread, miss)


def _deformation_prior(promp: ProMP | None, n_dims: int, extent: float, share: float) -> ProMP:
    """A zero-mean ProMP: the demonstrations' weight covariance plus an isotropic part."""
    if promp is not None and promp.n_dims_ != n_dims:
        raise ValueError(
            f"promp: is {promp.n_dims_}-D, the path {n_dims}-D; fit it on the same demonstrations"
        )
    if promp is None:
        state = ProMP(n_basis=DEFORMATION_BASIS).get_params()
        n_weights = n_dims * DEFORMATION_BASIS
        cov = np.zeros((n_weights, n_weights))
        width = 1.0 / (DEFORMATION_BASIS - 1)
        n_demos, residual = 0, 0.0
    else:
        state = promp.get_params()
        cov = promp.weights_cov_
        n_weights = len(cov)
        width, n_demos, residual = promp.width_, promp.n_demos_, promp.residual_rms_
    floor = (1e-3 * max(extent, np.finfo(float).tiny)) ** 2
    isotropic = max(share * float(np.trace(cov)) / n_weights, floor)
    return ProMP.from_state(
        {
            "params": state,
            "width": width,
            "n_dims": n_dims,
            "n_demos": n_demos,
            "residual_rms": residual,
            "weights_mean": np.zeros(n_weights),
            "weights_cov": cov + isotropic * np.eye(n_weights),
        }
    )
