"""Quality measures of a generalized path (thesis §4.6.1, §6.2).

Conventions
-----------
* Distances are measured along normals, as in the thesis: the normal
  hyperplane at a point of one path is intersected with the other polyline and
  the nearest crossing is taken (:mod:`lfdkit.geometry`). Where a normal meets
  nothing, the point is left out of :func:`e1` (reported by ``return_misses``)
  and, in :func:`e2`, replaced by the Euclidean distance to the closest point of
  the estimate, so that an estimate that stops short is still penalised.
* Sums run over sample points, so they depend on how densely a path is sampled:
  compare methods with the same number of points (the thesis uses M = 100).
* Units are those of the paths (e1 in units², e2 and e3 in units).
"""

from __future__ import annotations

import numpy as np

from lfdkit._validation import check_demos, check_path
from lfdkit.geometry import (
    PolylineSet,
    arc_length,
    left_normals,
    point_tangents,
    project_onto_polyline,
    resample,
)

__all__ = ["distance_space", "e1", "e2", "e3", "penetration"]


def distance_space(
    path: np.ndarray, demos: list[np.ndarray], *, same_direction: bool = True
) -> np.ndarray:
    """Signed vectors from each path point to each demonstration, along the path's normals.

    Parameters
    ----------
    path : array_like, shape (m, q)
    demos : list of array_like, each shape (n_j, q)
    same_direction : bool
        Match only demonstration segments traversed in the path's direction.

    Returns
    -------
    ndarray, shape (n_demos, m, q)
        ``intersection - path_point``; NaN rows where the normal misses.
    """
    path = check_path(path, "path")
    demos = check_demos(demos, "demos", n_dims=path.shape[1])
    hits = PolylineSet(demos).intersect(path, point_tangents(path), same_direction=same_direction)
    return np.transpose(hits.points - path[:, None, :], (1, 0, 2))


def e1(
    path: np.ndarray,
    demos: list[np.ndarray],
    *,
    same_direction: bool = True,
    return_misses: bool = False,
) -> float | tuple[float, int]:
    """Residual e1 = tr(ZᵀZ): summed squared normal distances from the path to the demos.

    Parameters
    ----------
    path : array_like, shape (m, q)
        The generalized path.
    demos : list of array_like, each shape (n_j, q)
    same_direction : bool
        Match only demonstration segments traversed in the path's direction.
    return_misses : bool
        Also return how many (point, demo) normals met nothing.

    Returns
    -------
    float or (float, int)
        e1 in units², and the number of misses if asked.
    """
    offsets = distance_space(path, demos, same_direction=same_direction)
    found = ~np.isnan(offsets[..., 0])
    value = float(np.sum(offsets[found] ** 2))
    return (value, int((~found).sum())) if return_misses else value


def e2(estimate: np.ndarray, nominal: np.ndarray, *, n_points: int | None = None) -> float:
    """Error e2 against a known nominal path: summed distances along the nominal's normals.

    Parameters
    ----------
    estimate : array_like, shape (m, q)
        The estimated generalized path.
    nominal : array_like, shape (n, q)
        The ground truth.
    n_points : int, optional
        Resample the nominal to this many points (evenly in arc length) first,
        so that e2 sums over a fixed number of points whatever the nominal's
        sampling; the nominal's own points are used when omitted.

    Returns
    -------
    float
        e2 in units. Where a nominal normal misses the estimate, the Euclidean
        distance to the estimate's closest point is used instead.
    """
    estimate = check_path(estimate, "estimate")
    nominal = check_path(nominal, "nominal", n_dims=estimate.shape[1])
    if n_points is not None:
        nominal = resample(nominal, n_points)
    # Same-direction matching: on a curved task the nominal's normal can also meet
    # the far side of the estimate, travelled the other way.
    hits = PolylineSet([estimate]).intersect(nominal, point_tangents(nominal), same_direction=True)
    dist = hits.distance[:, 0]
    missed = ~np.isfinite(dist)
    if missed.any():
        dist = dist.copy()
        dist[missed] = project_onto_polyline(nominal[missed], estimate)[2]
    return float(dist.sum())


def e3(innovation: np.ndarray) -> float:
    """Update size e3 = Σ|I_i| of one Mean-Path iteration, in units.

    Parameters
    ----------
    innovation : array_like, shape (m, q)
        The update vector of every path point.
    """
    innovation = check_path(innovation, "innovation", min_points=1)
    return float(np.linalg.norm(innovation, axis=1).sum())


def penetration(
    estimate: np.ndarray, nominal: np.ndarray, material_side: int, *, tolerance: float = 0.0
) -> tuple[float, float]:
    """How far a 2-D estimated profile goes into the workpiece (thesis §6.2, Fig 6.5).

    Each estimate point is projected onto the nominal profile (the workpiece's
    boundary); its signed distance is positive on the material side.

    Parameters
    ----------
    estimate : array_like, shape (m, 2)
    nominal : array_like, shape (n, 2)
        The workpiece boundary, in the direction of travel.
    material_side : {+1, -1}
        +1 if the material lies to the left of the nominal (the side of its left
        normal), -1 if to the right.
    tolerance : float
        Depths up to this (in units) do not count, e.g. below the machining or
        measuring precision; rounding (1e-9 of the profile's size) never counts.

    Returns
    -------
    depth : float
        Largest depth inside the material, in units (0 when the estimate never
        enters it; depths below 1e-9 of the profile's size count as rounding).
    fraction : float
        Fraction of the estimate's points inside the material.
    """
    estimate = check_path(estimate, "estimate", n_dims=2)
    nominal = check_path(nominal, "nominal", n_dims=2)
    if material_side not in (1, -1):
        raise ValueError(f"material_side: expected +1 or -1, got {material_side!r}")
    s_est, closest, dist = project_onto_polyline(estimate, nominal)
    # Orient each distance with the nominal's left normal at the closest point.
    normals = left_normals(nominal)
    s_nominal = arc_length(nominal)
    n_at = np.column_stack([np.interp(s_est, s_nominal, normals[:, k]) for k in range(2)])
    signed = np.sign(np.einsum("mq,mq->m", estimate - closest, n_at)) * dist
    inside = material_side * signed
    # Depths below 1e-9 of the profile's size are rounding, not penetration.
    tol = max(float(tolerance), 1e-9 * (float(np.abs(nominal).max()) + 1.0))
    depth = float(inside.max())
    return (depth if depth > tol else 0.0), float(np.mean(inside > tol))
