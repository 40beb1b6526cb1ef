"""The via-point figure: where the demonstrations let a skill go, and where it was sent.

One panel (2-D) or a 3-D view: the demonstrations (grey), the band of their
spread around the nominal (the ProMP's ±2σ across the path, light), the
nominal bent through the via-points with the band left around it (darker,
pinched at the ends and at each via-point), a few samples of that
conditioned band, the plan, and the via-points (stars) with their phases.
Equal aspect: the band's width is a length (in 3-D too, so that frame axes
keep their angles).

A via-point with an orientation gets two small frames at the point: the
orientation asked (axes x red, y green, z blue; wide and light) and the
plan's where it passes the point (thin, dashed, on top: where they agree both
show; slerp between the plan's samples at its closest point), with the angle
between them in the legend, so that a reader sees the plan turns the tool as
asked. Axis length: 12 % of the drawing's extent.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.patches import Polygon

from lfdkit.app.plot import draw_demos, draw_scene, label_axes
from lfdkit.core.geometry import arc_length, left_normals, project_onto_polyline
from lfdkit.core.rotations import angle_between, matrix_from_quaternion, slerp
from lfdkit.imitate.via_points import ViaPath

__all__ = [
    "draw_band",
    "draw_frames_along",
    "draw_via_orientations",
    "orientation_where_passed",
    "via_figure",
]

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
AXIS_COLORS = ("#d62728", "#2ca02c", "#1f77b4")  # x, y, z
#: Frame axes' length, as a fraction of the drawing's largest extent.
FRAME_SHARE = 0.12


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


def orientation_where_passed(
    point: np.ndarray, plan: np.ndarray, orientations: np.ndarray
) -> np.ndarray:
    """The plan's orientation at its closest point to ``point``.

    Parameters
    ----------
    point : ndarray, shape (q,)
    plan : ndarray, shape (n, q)
        The plan's points.
    orientations : ndarray, shape (n, 4)
        Its unit quaternions ``[x, y, z, w]``, one per point.

    Returns
    -------
    ndarray, shape (4,)
        Slerp between the two samples around the closest point, by arc length.
    """
    along = project_onto_polyline(np.asarray(point, dtype=np.float64)[None], plan)[0][0]
    arc = arc_length(plan)
    k = int(np.clip(np.searchsorted(arc, along, side="right") - 1, 0, len(plan) - 2))
    span = arc[k + 1] - arc[k]
    t = 0.0 if span <= 0.0 else float(np.clip((along - arc[k]) / span, 0.0, 1.0))
    return slerp(orientations[k], orientations[k + 1], t)


def draw_via_orientations(
    ax: Axes,
    via: Sequence[tuple[float, Sequence[float], Sequence[float]]],
    length: float,
    *,
    plan: np.ndarray | None = None,
    plan_orientations: np.ndarray | None = None,
) -> list[float]:
    """Frames at the via-points that carry an orientation: asked (solid) and the plan's (dashed).

    Parameters
    ----------
    ax : Axes
        2-D axes (the frames' x and y axes projected) or 3-D axes.
    via : sequence of (float, array_like (q,), array_like (4,) or None)
        The via-points; those without a third item are skipped.
    length : float
        Length of each frame axis, in the plot's units.
    plan, plan_orientations : ndarray, shapes (n, q) and (n, 4), optional
        The plan and its orientations: the plan's frame is drawn where it
        passes each via-point.

    Returns
    -------
    list of float
        Angle in radians between the asked and the plan's orientation at each
        oriented via-point (empty without a plan's orientations).
    """
    angles = []
    for phase, point, *rest in via:
        if not rest or rest[0] is None:
            continue
        point = np.asarray(point, dtype=np.float64)
        asked = np.asarray(rest[0], dtype=np.float64)
        asked_label = f"orientation asked at {phase:.0%} (wide; x, y, z: red, green, blue)"
        frames = [(asked, "-", asked_label)]
        if plan is not None and plan_orientations is not None:
            passed = orientation_where_passed(point, np.asarray(plan), plan_orientations)
            angle = float(angle_between(asked, passed))
            angles.append(angle)
            frames.append((passed, "--", f"plan's orientation there ({1e3 * angle:.2g} mrad off)"))
        for quaternion, style, label in frames:
            axes = matrix_from_quaternion(quaternion)  # columns: the frame's x, y, z
            thick = style == "-"  # the asked frame wide and light: the plan's shows inside it
            for k in range(3):
                tip = point + length * axes[: len(point), k]
                ax.plot(
                    *np.column_stack([point, tip]),
                    style,
                    color=AXIS_COLORS[k],
                    linewidth=5.0 if thick else 1.5,
                    alpha=0.45 if thick else 1.0,
                    zorder=8,
                    label=label if k == 1 else None,  # green in the legend: not the red plan
                )
    return angles


def draw_frames_along(
    ax: Axes, plan: np.ndarray, orientations: np.ndarray, length: float, n_frames: int = 7
) -> None:
    """Thin frames at ``n_frames`` evenly spaced samples of a plan: how the tool turns.

    ``plan`` (n, q) points, ``orientations`` (n, 4) unit quaternions; axes
    ``length`` long in the plot's units, projected on x and y in 2-D.
    """
    q = plan.shape[1]
    picks = np.linspace(0, len(plan) - 1, n_frames).round().astype(int)
    axes = matrix_from_quaternion(orientations[picks])  # (n_frames, 3, 3), columns x, y, z
    for k in range(3):
        for j, i in enumerate(picks):
            tip = plan[i] + length * axes[j, :q, k]
            ax.plot(
                *np.column_stack([plan[i], tip]),
                color=AXIS_COLORS[k],
                linewidth=0.9,
                alpha=0.6,
                zorder=6,
                label="plan's orientation along the way" if (k == 1 and j == 0) else None,
            )


def _equal_3d(ax: Axes, points: np.ndarray) -> None:
    """Equal scales on 3-D axes: a cube around ``points`` (n, 3)."""
    low, high = points.min(axis=0), points.max(axis=0)
    centre, half = 0.5 * (low + high), 0.5 * float(np.max(high - low)) or 1.0
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_box_aspect((1.0, 1.0, 1.0))


def via_figure(
    free: ViaPath,
    bent: ViaPath,
    via: Sequence[tuple[float, Sequence[float]]],
    *,
    plan: np.ndarray | None = None,
    plan_orientations: np.ndarray | None = None,
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
    via : sequence of (float, array_like (q,)[, array_like (4,)])
        The via-points, ``(phase, point)`` or ``(phase, point, [x, y, z, w])``:
        an orientation is drawn as a frame (:func:`draw_via_orientations`).
    plan : ndarray, shape (n, q), optional
        The plan (around the scene's obstacles).
    plan_orientations : ndarray, shape (n, 4), optional
        The plan's orientations (a skill with orientation): its frame is drawn
        where it passes each oriented via-point.
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
    drawn = np.vstack([free.points, bent.points, marks, *demos])
    length = FRAME_SHARE * float(np.ptp(drawn, axis=0).max())
    if q == 3:
        ax.computed_zorder = False  # frames over the stars, as zorder says
    if plan is not None and plan_orientations is not None:
        draw_frames_along(ax, np.asarray(plan), plan_orientations, 0.6 * length)
    draw_via_orientations(ax, via, length, plan=plan, plan_orientations=plan_orientations)
    label_axes(ax, q, units)
    if q == 2:
        ax.set_aspect("equal", adjustable="datalim")
    else:
        _equal_3d(ax, drawn)
    ax.legend(loc="best", fontsize=8)
    ax.set_title(title or "Via-points: the nominal bent the way the demonstrations varied")
    return fig
