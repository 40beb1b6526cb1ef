"""The via-point figure: where the demonstrations let a skill go, and where it was sent.

One panel (2-D) or a 3-D view: the demonstrations (grey), the band of their
spread around the nominal (the ProMP's ±2σ across the path, light), the
nominal bent through the via-points with the band left around it (darker,
pinched at the ends and at each via-point), a few samples of that
conditioned band, the plan, and the via-points (stars) with their phases.
Equal aspect: the band's width is a length.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.patches import Polygon

from lfdkit.app.plot import draw_demos, draw_scene, label_axes
from lfdkit.core.geometry import left_normals
from lfdkit.imitate.via_points import ViaPath

__all__ = ["draw_band", "via_figure"]

BAND_COLOR = "#1f77b4"
PLAN_COLOR = "#d62728"
VIA_STYLE = {
    "marker": "*",
    "markersize": 15,
    "color": "#ffbf00",
    "markeredgecolor": "k",
    "linestyle": "none",
    "zorder": 7,
}


def draw_band(
    ax: Axes, bent: ViaPath, *, n_std: float = 2.0, alpha: float = 0.3, label: str | None = None
) -> None:
    """The band ``±n_std·σ`` across a 2-D path (σ along the path's normal at each sample).

    Parameters
    ----------
    ax : Axes
        2-D axes.
    bent : ViaPath
        The path and its deformation (:meth:`lfdkit.skill.Skill.via_path`).
    n_std : float
        Half-width of the band in standard deviations.
    alpha : float
        Opacity of the fill.
    label : str, optional
        Legend entry.
    """
    points = bent.points
    keep = np.r_[True, np.linalg.norm(np.diff(points, axis=0), axis=1) > 0.0]
    points, phases = points[keep], bent.phases[keep]
    normals = left_normals(points)
    cov = bent.spread.covariance_at(phases)
    sigma = np.sqrt(np.clip(np.einsum("ni,nij,nj->n", normals, cov, normals), 0.0, None))
    upper = points + n_std * sigma[:, None] * normals
    lower = points - n_std * sigma[:, None] * normals
    outline = np.vstack([upper, lower[::-1]])
    ax.add_patch(Polygon(outline, closed=True, color=BAND_COLOR, alpha=alpha, lw=0, label=label))


def via_figure(
    free: ViaPath,
    bent: ViaPath,
    via: Sequence[tuple[float, Sequence[float]]],
    *,
    plan: np.ndarray | None = None,
    demos: Sequence[np.ndarray] = (),
    scene=None,
    n_samples: int = 5,
    seed: int = 0,
    units: str = "m",
    title: str = "",
) -> Figure:
    """Demonstrations, their band, the nominal bent through via-points, samples and the plan.

    Parameters
    ----------
    free : ViaPath
        The nominal with no via-point (:meth:`lfdkit.skill.Skill.via_path` of
        None): its band is the demonstrations' spread.
    bent : ViaPath
        The nominal bent through ``via`` (the same start and goal).
    via : sequence of (float, array_like (q,))
        The via-points, ``(phase, point)``.
    plan : ndarray, shape (n, q), optional
        The plan (around the scene's obstacles).
    demos : sequence of ndarray, each (n_j, q)
        Demonstrations to draw (grey).
    scene : Scene, optional
        Obstacles to draw.
    n_samples : int
        Paths drawn from the conditioned band (thin lines), seeded by ``seed``.
    units : str
        Unit of the coordinates.
    title : str

    Returns
    -------
    Figure
    """
    q = bent.points.shape[1]
    fig = Figure(figsize=(8.0, 5.4), layout="constrained")
    ax = fig.add_subplot(projection="3d" if q == 3 else None)
    if demos:
        draw_demos(ax, demos)
    if q == 2:
        draw_band(ax, free, alpha=0.15, label="demonstrations' spread (±2 std)")
        draw_band(ax, bent, alpha=0.35, label="left after the via-points (±2 std)")
    if scene is not None and len(scene):
        draw_scene(ax, scene)
    phases = np.linspace(0.0, 1.0, 200)
    # Each sample: the bent nominal plus a draw of the spread left around it.
    samples = bent.spread.sample(n_samples, len(phases), seed=seed)
    base = np.column_stack([np.interp(phases, bent.phases, bent.points[:, k]) for k in range(q)])
    for i, sample in enumerate(samples):
        ax.plot(
            *(base + sample).T,
            color=BAND_COLOR,
            linewidth=0.6,
            alpha=0.7,
            label="conditioned samples" if i == 0 else None,
        )
    ax.plot(*free.points.T, "k--", linewidth=1.2, label="nominal")
    ax.plot(*bent.points.T, color=BAND_COLOR, linewidth=2.0, label="nominal through via-points")
    if plan is not None:
        ax.plot(*np.asarray(plan).T, color=PLAN_COLOR, linewidth=1.6, label="plan")
    marks = np.array([entry[1] for entry in via], dtype=np.float64)  # any orientation aside
    ax.plot(*marks.T, **VIA_STYLE, label="via-points")
    if q == 2:
        for phase, point, *_ in via:
            ax.annotate(
                f"at {phase:.0%} of the time", point, xytext=(6, 8), textcoords="offset points"
            )
    label_axes(ax, q, units)
    if q == 2:
        ax.set_aspect("equal", adjustable="datalim")
    ax.legend(loc="best", fontsize=8)
    ax.set_title(title or "Via-points: the nominal bent the way the demonstrations varied")
    return fig
