"""The demonstrations' mean tool orientation along a generalized path.

Every mimicking method gives a path of positions; demonstrations recorded
with the tool's orientation (``qx, qy, qz, qw`` columns, unit quaternions)
also say how the tool was held along it. :func:`mean_orientations` finds,
for each point of the path, where each demonstration corresponds to it and
averages the demonstrations' orientations there:

* **Correspondence.** The same as Mean-Path's: the nearest crossing of the
  path's normal hyperplane at the point with the demonstration, on a segment
  traversed in the path's direction (:class:`lfdkit.core.geometry.PolylineSet`);
  demonstrations recorded the other way round are reversed first
  (:func:`lfdkit.mimic.orientation.orient_demos`). Where the normal misses a
  demonstration (near the ends) its closest point is used instead. The
  orientation there is the slerp of the segment's end orientations at the
  crossing's fraction of the segment.
* **Average.** A proper rotation average: with ``robust=True`` (default)
  :func:`lfdkit.core.rotations.robust_mean_quaternion` (Markley's eigenvector
  mean, iteratively reweighted by each rotation's geodesic distance to it,
  full weight within 4 robust scales, none beyond 8: the redescending rule of
  Mean-Path's adaptive centre), else the plain Markley mean.
* **Signs** are chosen continuous along the path (``q`` and ``-q`` are the
  same rotation; consecutive means have a non-negative dot product).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from lfdkit.core.geometry import PolylineSet, arc_length, point_tangents, project_onto_polyline
from lfdkit.core.rotations import (
    angle_between,
    check_quaternions,
    continuous,
    mean_quaternion,
    robust_mean_quaternion,
    slerp,
)
from lfdkit.core.validation import check_demos, check_path
from lfdkit.mimic.orientation import orient_demos

__all__ = ["PathOrientations", "mean_orientations"]


@dataclass(frozen=True)
class PathOrientations:
    """The mean orientation at each point of a path, and how it was found.

    Attributes
    ----------
    orientations : ndarray, shape (n_points, 4)
        Unit quaternions ``[x, y, z, w]``, signs continuous along the path.
    samples : ndarray, shape (n_points, n_demos, 4)
        Each demonstration's orientation at its corresponding point.
    weights : ndarray, shape (n_points, n_demos)
        The weight each demonstration had in the mean (1, or less for an
        outlying orientation with ``robust``; 0 for one given no say).
    crossed : ndarray of bool, shape (n_points, n_demos)
        Whether the correspondence is a normal crossing (else the closest point).
    spread : ndarray, shape (n_points,)
        Median geodesic distance (radians) of the demonstrations' orientations
        to the mean: how much they agree there.
    """

    orientations: np.ndarray
    samples: np.ndarray
    weights: np.ndarray
    crossed: np.ndarray
    spread: np.ndarray


def _at(quats: np.ndarray, segment: np.ndarray, fraction: np.ndarray) -> np.ndarray:
    """The slerp of segment ``k``'s end orientations at ``fraction``, per query."""
    return slerp(quats[segment], quats[segment + 1], fraction)


def mean_orientations(
    path: Any,
    demos: Sequence[Any],
    orientations: Sequence[Any],
    *,
    robust: bool = True,
) -> PathOrientations:
    """Average the demonstrations' orientations at each point of a generalized path.

    Parameters
    ----------
    path : array_like, shape (n_points, q)
        The generalized path (e.g. ``MeanPath().fit(demos).path_``).
    demos : sequence of array_like, each shape (n_j, q)
        The demonstrations' positions.
    orientations : sequence of array_like, each shape (n_j, 4)
        Their orientations, unit quaternions ``[x, y, z, w]``.
    robust : bool
        Down-weight outlying orientations (see the module notes).

    Returns
    -------
    PathOrientations

    Raises
    ------
    ValueError
        If shapes disagree, a quaternion is NaN or not unit, or the
        demonstrations' directions cannot be decided (as the mimicking
        methods refuse them).
    """
    ref = check_path(path, "path")
    arrs = check_demos(demos, "demos", n_dims=ref.shape[1])
    if len(orientations) != len(arrs):
        raise ValueError(
            f"orientations: expected one array per demonstration ({len(arrs)}), "
            f"got {len(orientations)}"
        )
    quats = [
        continuous(check_quaternions(o, f"orientations[{j}]", n=len(d)))
        for j, (o, d) in enumerate(zip(orientations, arrs, strict=True))
    ]
    oriented, flipped = orient_demos(arrs, reference=ref, method="mean_orientations")
    quats = [q[::-1] if f else q for q, f in zip(quats, flipped, strict=True)]

    tangents = point_tangents(ref)
    hits = PolylineSet(oriented).intersect(ref, tangents, same_direction=True)
    n, m = len(ref), len(oriented)
    samples = np.empty((n, m, 4))
    crossed = hits.segment >= 0
    for j, (demo, q) in enumerate(zip(oriented, quats, strict=True)):
        seg = hits.segment[:, j].copy()
        frac = np.zeros(n)
        ok = seg >= 0
        if ok.any():
            a, b = demo[seg[ok]], demo[seg[ok] + 1]
            d = b - a
            len2 = np.einsum("ij,ij->i", d, d)
            rel = np.einsum("ij,ij->i", hits.points[ok, j] - a, d)
            frac[ok] = np.clip(np.divide(rel, len2, out=np.zeros_like(rel), where=len2 > 0), 0, 1)
        if (~ok).any():  # closest point instead, by its arc-length position
            s, _, _ = project_onto_polyline(ref[~ok], demo)
            arc = arc_length(demo)
            k = np.clip(np.searchsorted(arc, s, side="right") - 1, 0, len(demo) - 2)
            step = arc[k + 1] - arc[k]
            seg[~ok] = k
            frac[~ok] = np.clip(
                np.divide(s - arc[k], step, out=np.zeros_like(s), where=step > 0), 0, 1
            )
        samples[:, j] = _at(q, seg, frac)

    means = np.empty((n, 4))
    weights = np.ones((n, m))
    spread = np.empty(n)
    near = None
    for i in range(n):
        if robust:
            means[i], weights[i] = robust_mean_quaternion(samples[i], near=near)
        else:
            means[i] = mean_quaternion(samples[i], near=near)
        near = means[i]
        spread[i] = float(np.median(angle_between(samples[i], means[i])))
    return PathOrientations(continuous(means), samples, weights, crossed, spread)
