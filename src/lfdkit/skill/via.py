"""Via-points of a skill: the nominal bent through them, and how closely a plan passes them.

A plan may pass a via-point up to :data:`VIA_TOLERANCE` of its extent away
before a warning says so (the planner's resampling cuts the bent nominal by
well under that; an obstacle may pull it farther).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np

from lfdkit.core.geometry import (
    arc_length,
    polyline_distances,
    project_onto_polyline,
)
from lfdkit.imitate.via_points import (
    ViaPath,
    check_via,
    through_via_points,
)

#: How far a plan may pass from a via-point, as a share of the plan's extent, before a
#: warning says so: the nominal passes exactly, the planner's resampling at constant
#: speed cuts it by well under this (the issue-33 benchmark), an obstacle may by more.
VIA_TOLERANCE = 0.01


class ViaPoints:
    """Via-points of a :class:`~lfdkit.skill.Skill`: the nominal bent through them."""

    def via_path(
        self,
        via: Sequence[tuple[float, Any]] | None = None,
        start: Any = None,
        goal: Any = None,
    ) -> ViaPath:
        """The nominal bent through via-points, with the band the demonstrations leave around it.

        The DMP carries the path to ``start`` and ``goal`` (:meth:`nominal`);
        a deformation in the basis of :attr:`promp_`, with the demonstrations'
        weight covariance, is conditioned to be 0 at both ends and to reach
        each via-point (:func:`lfdkit.imitate.via_points.through_via_points`):
        where the demonstrations varied, the path moves as they did.

        Parameters
        ----------
        via : sequence of (float, array_like (q,)), optional
            ``(phase, point)`` pairs, phase strictly between 0 and 1 (the
            fraction of the movement's duration). None: no via-point (the
            nominal, with the band of the demonstrations' spread).
        start, goal : array_like, shape (q,), optional
            Default: the generalized path's own.

        Returns
        -------
        ViaPath
            ``points`` (the nominal's samples plus one per via-point, which is
            the via-point itself), their ``phases`` (fractions of the
            nominal's length, the ProMP's phase), the conditioned
            ``deformation``, the demonstrations' ``spread`` left around it
            (its ``covariance_at(phases)`` is the band, units²)
            and each via-point's ``miss`` (0 unless a warning said otherwise).
        """
        start, goal = self._ends(start, goal)
        nominal = self._nominal(start, goal)
        if via is None:
            phases, points = np.zeros(0), np.zeros((0, self.n_dims_))
        else:
            phases, points = check_via(via, self.n_dims_)
        # The rollout is at equal time steps: the via-points' phases are fractions of
        # time; the bending's (and the ProMP's) are fractions of the length travelled.
        travelled = arc_length(nominal)
        length = travelled / travelled[-1]
        at = np.interp(phases, np.linspace(0.0, 1.0, len(nominal)), length)
        return through_via_points(nominal, length, at, points, getattr(self, "promp_", None))


def passing_phases(
    points: np.ndarray, times: np.ndarray, via: Sequence[tuple[Any, ...]], phases: np.ndarray
) -> np.ndarray:
    """When the timed plan passes each oriented via-point, as fractions of its duration.

    The plan is timed by its own length (:meth:`SpeedProfile.time_path`), so it
    passes a via-point a little off the phase asked (measured: 0.317 for 0.3,
    where the orientation would then be 1.8° off); the orientation is turned to
    be exact where the tool *is* at the point. A via-point the plan misses by
    more than :data:`VIA_TOLERANCE` of its extent (warned) keeps the phase asked.
    """
    oriented = [entry for entry in via if len(entry) > 2 and entry[2] is not None]
    _, targets = check_via([(entry[0], entry[1]) for entry in oriented], points.shape[1])
    along, _, miss = project_onto_polyline(targets, points)
    passing = np.interp(along, arc_length(points), times) / times[-1]
    near = (miss <= VIA_TOLERANCE * path_extent(points)) & (passing > 0.0) & (passing < 1.0)
    return np.where(near, passing, phases)


def warn_via_missed(points: np.ndarray, via: Sequence[tuple[float, Any]], units: str) -> None:
    """A warning naming the via-points a plan passes farther than :data:`VIA_TOLERANCE` from."""
    _, targets = check_via(via, points.shape[1])
    miss = polyline_distances(targets, points)
    limit = VIA_TOLERANCE * path_extent(points)
    far = np.flatnonzero(miss > limit)
    if far.size:
        i = int(far[0])
        warnings.warn(
            f"via[{i}]: the plan passes {miss[i]:.3g} {units} from it ({far.size} of "
            f"{len(targets)} via-points farther than {limit:.3g} {units}): an obstacle (its "
            "learned response) or the planner's action bound pulls the plan away; move the "
            "via-point or the obstacle, or raise max_slope",
            UserWarning,
            stacklevel=3,
        )


def path_extent(path: np.ndarray) -> float:
    return float(np.max(np.ptp(path, axis=0))) or 1.0
