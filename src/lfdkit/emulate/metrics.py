"""Quality measures of a generalized path (thesis §4.6.1, §6.2).

Conventions
-----------
* Distances are measured along normals, as in the thesis: the normal
  hyperplane at a point of one path is intersected with the other polyline and
  the nearest crossing is taken (:mod:`lfdkit.core.geometry`). Where a normal meets
  nothing, the point is left out of :func:`e1` (reported by ``return_misses``)
  and, in :func:`e2`, replaced by the Euclidean distance to the closest point of
  the estimate, so that an estimate that stops short is still penalised.
* Sums run over sample points, so they depend on how densely a path is sampled:
  compare methods with the same number of points (the thesis uses M = 100).
* Units are those of the paths (e1 in units², e2 and e3 in units).
"""

from __future__ import annotations

import numpy as np

from lfdkit.core.geometry import (
    PolylineSet,
    arc_length,
    left_normals,
    path_length,
    point_tangents,
    polyline_distances,
    project_onto_polyline,
    resample,
)
from lfdkit.core.validation import check_count, check_demos, check_path, check_positive
from lfdkit.model.scene import Scene

__all__ = [
    "clearance",
    "collisions",
    "demonstration_spread",
    "discrete_frechet",
    "distance_space",
    "e1",
    "e2",
    "e3",
    "held_out_distances",
    "improvement",
    "mse_paths",
    "parameter_errors",
    "penetration",
]


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


# --------------------------------------------------------------------- emulation
# Measures of emulation (thesis §5.5, §6.3–6.4): how close reproduced paths are
# to the demonstrations, how much that improves on replaying the generalized
# path, how far a path keeps from the obstacles, and how well a fitted reward
# recovers known parameters.


def _paths_for(paths, n_demos: int, n_dims: int) -> list[np.ndarray]:
    """One path per demonstration: a single (m, q) path is repeated ``n_demos`` times."""
    if isinstance(paths, np.ndarray) and paths.ndim == 2:
        return [check_path(paths, "paths", n_dims=n_dims)] * n_demos
    checked = check_demos(paths, "paths", n_dims=n_dims)
    if len(checked) != n_demos:
        raise ValueError(
            f"paths: expected one path per demonstration ({n_demos}), got {len(checked)}; "
            "pass a single (m, q) array to compare one path with every demonstration"
        )
    return checked


def mse_paths(paths, demos, n_points: int = 100) -> float:
    """Mean squared distance between reproduced paths and demonstrations (thesis MSE_R).

    ``MSE = 1/(n m) Σ_d Σ_i |ζ_{d,i} − ζ_{R,i}|²`` over the ``n`` demonstrations
    and the ``m = n_points`` points of each, both paths resampled to points
    equally spaced in arc length, so point ``i`` of one is compared with point
    ``i`` of the other.

    Parameters
    ----------
    paths : list of array_like, each (m_d, q), or one ndarray (m, q)
        ``paths[d]`` is the reproduction of ``demos[d]`` (e.g. the plan in that
        demonstration's scene). A single 2-D array is compared with every
        demonstration: replaying the generalized path gives MSE_Mp.
    demos : list of array_like, each (n_d, q)
    n_points : int
        Points each path is resampled to (the thesis uses 100).

    Returns
    -------
    float
        Mean squared distance per point and per path, in units².

    Raises
    ------
    ValueError
        For mismatched numbers of paths and demonstrations or dimensions, a path of
        zero length, or ``n_points < 2``.
    """
    demos = check_demos(demos, "demos")
    n_dims = demos[0].shape[1]
    paths = _paths_for(paths, len(demos), n_dims)
    n_points = check_positive(n_points, "n_points", integer=True)
    if n_points < 2:
        raise ValueError(f"n_points: needs at least 2, got {n_points}")
    check_count(n_points, "n_points", minimum=2)  # at most MAX_POINTS
    total = 0.0
    for d, (path, demo) in enumerate(zip(paths, demos, strict=True)):
        for arr, name in ((path, f"paths[{d}]"), (demo, f"demos[{d}]")):
            if path_length(arr) <= 0:
                raise ValueError(f"{name}: has zero length (all points coincide)")
        diff = resample(path, n_points) - resample(demo, n_points)
        total += float(np.einsum("iq,iq->", diff, diff))
    return total / (len(demos) * n_points)


def demonstration_spread(path, demos, n_points: int = 100) -> float:
    """How far demonstrations stray from the path learned from them: their noise, units².

    :func:`mse_paths` of ``path`` against each of ``demos``, times
    ``n / (n - 1)`` for ``n`` demonstrations (the path is fitted to them, so
    it sits closer to them than to a new one; the correction of a sample
    variance). Where the person had nothing to avoid, this is the squared
    distance any model's plan is expected to stay from a new demonstration of
    theirs even if it were exact: the noise floor of a replanning error.
    Demonstrations from different starts or to different goals are compared
    each with the path carried to its own (a list of paths, e.g. the skill's
    nominal for each): against the one learned path their spread is mostly the
    starts' (issue 34's stress set, starts 30 cm apart and 2 mm of noise:
    18,506 mm² against the path, 4.6 mm² against each one's own nominal).

    Parameters
    ----------
    path : array_like, shape (m, q), or list of array_like, one per demonstration
        The path learned from ``demos`` (e.g. :attr:`lfdkit.skill.Skill.path_`),
        or that path carried to each demonstration's start and goal.
    demos : list of array_like, each (n_d, q)
        At least 2 demonstrations, run in the path's direction.
    n_points : int
        Points each path is resampled to.

    Returns
    -------
    float
        Mean squared distance per point, in units², corrected for the fit.

    Raises
    ------
    ValueError
        For fewer than 2 demonstrations, or as :func:`mse_paths`.
    """
    demos = check_demos(demos, "demos", min_demos=2)
    n = len(demos)
    return mse_paths(path, demos, n_points) * n / (n - 1)


def discrete_frechet(a, b) -> float:
    """Discrete Fréchet distance between two polylines' vertices (Eiter and Mannila, 1994).

    The shortest leash that lets one walker step along ``a`` and another along
    ``b``, each only forward, from first to last vertex. Unlike a closest-point
    distance it sees order: a path that retraces or skips part of the other is
    far from it even where the two overlap.

    Parameters
    ----------
    a : array_like, shape (n, q)
    b : array_like, shape (m, q)

    Returns
    -------
    float
        In the paths' units.
    """
    a = check_path(a, "a", min_points=1)
    b = check_path(b, "b", min_points=1, n_dims=a.shape[1])
    d = np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2)
    n, m = d.shape
    # leash[i + 1, j + 1] is cell (i, j); the infinite border stands for "no predecessor"
    # and the zero corner lets (0, 0) take its own distance.
    leash = np.full((n + 1, m + 1), np.inf)
    leash[0, 0] = 0.0
    # Sweep anti-diagonals: every cell depends only on the previous two.
    for k in range(n + m - 1):
        i = np.arange(max(0, k - m + 1), min(n, k + 1))
        j = k - i
        before = np.minimum(np.minimum(leash[i, j + 1], leash[i + 1, j]), leash[i, j])
        leash[i + 1, j + 1] = np.maximum(d[i, j], before)
    return float(leash[-1, -1])


def held_out_distances(path, demo, n_points: int = 200) -> dict[str, float]:
    """How far a generalized path is from a held-out demonstration.

    Both are resampled to ``n_points`` points evenly spaced in arc length.

    Parameters
    ----------
    path : array_like, shape (m, q)
        The generalized path (or its reproduction).
    demo : array_like, shape (n, q)
        The held-out demonstration.
    n_points : int
        Points each is resampled to (2 to ``MAX_POINTS``).

    Returns
    -------
    dict
        ``mean``: the symmetric mean closest-point distance (half the mean
        distance from the demonstration's points to the path plus half the
        reverse, so a path cut short or running past the demonstration is
        penalised); ``max``: the Hausdorff distance (the larger of the two
        directions' maxima); ``frechet``: :func:`discrete_frechet`. All in the
        paths' units.
    """
    path = check_path(path, "path")
    demo = check_path(demo, "demo", n_dims=path.shape[1])
    check_count(n_points, "n_points", minimum=2)
    for arr, name in ((path, "path"), (demo, "demo")):
        if path_length(arr) <= 0:
            raise ValueError(f"{name}: has zero length (all points coincide)")
    p, h = resample(path, n_points), resample(demo, n_points)
    to_path = polyline_distances(h, p)
    to_demo = polyline_distances(p, h)
    return {
        "mean": float(0.5 * (to_path.mean() + to_demo.mean())),
        "max": float(max(to_path.max(), to_demo.max())),
        "frechet": discrete_frechet(p, h),
    }


def improvement(mse_replay: float, mse_reproduced: float) -> float:
    """Improvement over replaying the generalized path, in percent (thesis Pr).

    ``Pr = (MSE_Mp − MSE_R) / MSE_Mp · 100``: 100 % for a perfect reproduction,
    0 % for no better than replaying, negative when worse.

    Parameters
    ----------
    mse_replay : float
        MSE_Mp, of the generalized path replayed in every scene (> 0).
    mse_reproduced : float
        MSE_R, of the reproduced (planned) paths (>= 0).
    """
    mse_replay = check_positive(mse_replay, "mse_replay")
    mse_reproduced = check_positive(mse_reproduced, "mse_reproduced", allow_zero=True)
    return (mse_replay - mse_reproduced) / mse_replay * 100.0


def _check_scene(scene, name: str = "scene") -> Scene:
    if not isinstance(scene, Scene):
        raise TypeError(f"{name}: expected an lfdkit.emulate.Scene, got {type(scene).__name__}")
    return scene


def clearance(path, scene, margin: float = 0.0) -> np.ndarray:
    """Distance from a path to the surface of every obstacle, minus a margin (negative inside).

    The path is taken as a polyline: the distance to an obstacle is the
    smallest over its segments, not only its vertices, so a coarse path that
    cuts through an obstacle between two points is caught.

    Parameters
    ----------
    path : array_like, shape (n, q), q 2 or 3
        One point is accepted (its distance to each centre).
    scene : Scene
        Obstacles of the same dimension as the path.
    margin : float, default 0
        Subtracted from every distance: the tool's clearance (the planner's
        ``clearance``), in the path's units.

    Returns
    -------
    ndarray, shape (n_obstacles,)
        Smallest distance from the polyline to each obstacle's surface
        (:meth:`lfdkit.model.scene.Obstacle.distance`; for a round obstacle its
        centre's distance minus its radius) minus ``margin``, in units: negative
        where the path comes closer than radius plus margin. The planner's
        :attr:`lfdkit.emulate.Plan.clearance` is this, for its own clearance.
    """
    path = check_path(path, "path", min_points=1)
    scene = _check_scene(scene)
    margin = check_positive(margin, "margin", allow_zero=True)
    if not len(scene.obstacles):
        return np.zeros(0)
    if scene.positions.shape[1] != path.shape[1]:
        raise ValueError(
            f"scene: {scene.positions.shape[1]}-D obstacles for a {path.shape[1]}-D path"
        )
    return scene.distances(path) - margin


def collisions(path, scene) -> int:
    """Number of obstacles whose radius the path polyline enters (:func:`clearance` < 0)."""
    return int(np.count_nonzero(clearance(path, scene) < 0.0))


def parameter_errors(fitted, true) -> dict[str, float]:
    """Relative errors of a fitted reward's parameters against known ones.

    Parameters
    ----------
    fitted, true : Reward
        ``true`` is the ground truth; ``fitted`` must know every class of
        ``true`` (extra classes of ``fitted`` are ignored).

    Returns
    -------
    dict of str to float
        ``|fitted − true| / |true|`` for ``"Q"`` (the nominal weight) and for each
        diagonal precision entry, keyed ``"<class>[<i>]"`` (e.g. ``"cup[0]"``), in
        the order of ``true``'s classes.

    Raises
    ------
    ValueError
        If a class of ``true`` is missing from ``fitted`` or their dimensions differ.
    """
    for reward, name in ((fitted, "fitted"), (true, "true")):
        if not hasattr(reward, "precisions") or not hasattr(reward, "nominal_weight"):
            raise TypeError(
                f"{name}: expected an lfdkit.emulate.Reward, got {type(reward).__name__}"
            )
    missing = [label for label in true.precisions if label not in fitted.precisions]
    if missing:
        raise ValueError(
            f"fitted: has no class {missing[0]!r} of the true reward; "
            f"fitted classes: {', '.join(fitted.precisions) or 'none'}"
        )
    errors = {"Q": abs(fitted.nominal_weight - true.nominal_weight) / abs(true.nominal_weight)}
    for label, matrix in true.precisions.items():
        other = fitted.precisions[label]
        if other.shape != matrix.shape:
            raise ValueError(
                f"fitted: class {label!r} is {other.shape[0]}-D, the true one {matrix.shape[0]}-D"
            )
        for i, (f_ii, t_ii) in enumerate(zip(np.diag(other), np.diag(matrix), strict=True)):
            errors[f"{label}[{i}]"] = float(abs(f_ii - t_ii) / abs(t_ii))
    return errors
