"""Figures a user wants to look at, one function each.

Functions that draw into an existing ``Axes`` are named ``draw_*``; functions that
build a whole figure are named ``*_figure`` and return a
:class:`matplotlib.figure.Figure` (no pyplot state, so they work headless and in
threads; save with ``fig.savefig(path)``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib import patheffects
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.patches import Polygon
from matplotlib.ticker import MaxNLocator

from lfdkit.core.validation import check_path, check_positive
from lfdkit.mimic import MIMIC_METHODS
from lfdkit.model.scene import Scene

__all__ = [
    "CLASS_COLORS",
    "PEER_COLORS",
    "comparison_figure",
    "draw_demos",
    "draw_distance_space",
    "draw_gmr_tube",
    "draw_paths",
    "draw_residual_history",
    "draw_reward",
    "draw_rollouts",
    "draw_scene",
    "emulation_figure",
    "emulation_grid",
    "label_axes",
    "mean_path_figure",
    "method_color",
    "plan_colors",
    "retargeting_figure",
]

#: Colours of the benchmarks' peer libraries; lfdkit's own methods carry theirs in
#: the registry (:data:`lfdkit.mimic.MIMIC_METHODS`), see :func:`method_color`.
PEER_COLORS = {
    "gmr (package)": "#17becf",
    "DBA (tslearn)": "#8c564b",
    "soft-DTW (tslearn)": "#e377c2",
}


def method_color(label: str) -> str | None:
    """Colour of a method by its label: a registered method's own, else a peer's, else None."""
    for method in MIMIC_METHODS.values():
        if method.label == label:
            return method.color
    return PEER_COLORS.get(label)


DEMO_COLOR = "0.65"
#: The generalized path a DMP is trained on, and its rollouts to new goals.
PATH_COLOR = "#1f77b4"
ROLLOUT_COLORS = ("#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2")
NOMINAL_STYLE = {"color": "k", "linestyle": "--", "linewidth": 1.4, "label": "ground truth"}


def _xy(path: np.ndarray) -> tuple[np.ndarray, ...]:
    return tuple(path[:, k] for k in range(path.shape[1]))


def draw_demos(ax: Axes, demos: Sequence[np.ndarray], *, label: str = "demonstrations") -> None:
    """Demonstrations as thin grey lines with their start points marked."""
    for j, demo in enumerate(demos):
        ax.plot(*_xy(demo), color=DEMO_COLOR, linewidth=0.8, label=label if j == 0 else None)
    starts = np.array([d[0] for d in demos])
    ax.plot(*_xy(starts), "o", color=DEMO_COLOR, markersize=2.5)


def draw_paths(
    ax: Axes,
    paths: Mapping[str, np.ndarray],
    *,
    nominal: np.ndarray | None = None,
    walls: Sequence[np.ndarray] = (),
) -> None:
    """Generalized paths in their method colours, the ground truth dashed, walls thick."""
    for k, wall in enumerate(walls):
        ax.plot(*_xy(wall), color="0.2", linewidth=2.5, label="walls" if k == 0 else None)
    if nominal is not None:
        ax.plot(*_xy(nominal), **NOMINAL_STYLE)
    for name, path in paths.items():
        ax.plot(*_xy(path), color=method_color(name), linewidth=1.6, label=name)


def label_axes(ax: Axes, q: int, units: str) -> None:
    """Name the axes of a ``q``-D plot of positions with their unit: ``x [mm]``, ``y [mm]``.

    Parameters
    ----------
    ax : Axes
        2-D axes, or 3-D axes when ``q`` is 3.
    q : int
        Dimension of the positions drawn, 2 or 3.
    units : str
        Their unit (:data:`lfdkit.core.units.UNITS`).
    """
    names = ("x", "y", "z")
    ax.set_xlabel(f"{names[0]} [{units}]")
    ax.set_ylabel(f"{names[1]} [{units}]")
    if q == 3:
        ax.set_zlabel(f"{names[2]} [{units}]")


def comparison_figure(
    demos: Sequence[np.ndarray],
    paths: Mapping[str, np.ndarray],
    *,
    nominal: np.ndarray | None = None,
    walls: Sequence[np.ndarray] = (),
    units: str = "m",
    title: str = "",
) -> Figure:
    """Demonstrations, ground truth and every method's generalized path in one panel.

    Parameters
    ----------
    demos : sequence of ndarray, each (n_j, q), q in {2, 3}
    paths : mapping of method name to ndarray (m, q)
    nominal : ndarray (n, q), optional
    walls : sequence of ndarray
    units : str
        Axis unit label.
    title : str
    """
    q = demos[0].shape[1]
    fig = Figure(figsize=(7.0, 5.6), layout="constrained")
    ax = fig.add_subplot(projection="3d" if q == 3 else None)
    draw_demos(ax, demos)
    draw_paths(ax, paths, nominal=nominal, walls=walls)
    label_axes(ax, q, units)
    if q == 2:
        ax.set_aspect("equal", adjustable="datalim")
    else:
        arrays = [*demos, *paths.values(), *([] if nominal is None else [nominal])]
        _equal_3d(ax, [np.asarray(a, dtype=np.float64) for a in arrays])
    ax.set_title(title)
    _figure_legend(fig, [ax], max_cols=4)
    return fig


def draw_residual_history(
    ax: Axes,
    mean_path,
    units: str = "m",
    *,
    ax_update: Axes | None = None,
    legend: bool = True,
) -> None:
    """How the Mean-Path settled, per iteration, on log scales (compare thesis Fig 4.9).

    In ``ax`` (red): the relative change of the residual e1 (the sum of squared
    normal distances to the demonstrations) from one iteration to the next,
    with the stopping tolerance ``tol`` dotted; iteration 0, the initial path,
    has no change yet. In ``ax_update`` (black; default a second y axis on
    the right of ``ax``): the mean length of the update the iteration
    computes at each path point (e3 divided by the number of points), in
    ``units``; it goes to zero at convergence. ``legend`` False leaves the
    legend to the figure (:func:`mean_path_figure` puts one below its panels).
    """
    e1 = np.asarray(mean_path.residual_history_, dtype=np.float64)
    e3 = np.asarray(mean_path.innovation_history_, dtype=np.float64)
    it = np.arange(len(e1))
    # Nothing below one rounding error can be told apart (and log scales refuse zeros).
    floor = np.finfo(np.float64).eps
    red = "#d62728"
    if len(e1) > 1:
        change = np.abs(np.diff(e1)) / np.maximum(np.abs(e1[1:]), floor)
        ax.plot(it[1:], np.maximum(change, floor), "o-", color=red, label="relative change of e1")
    tol = getattr(mean_path, "tol", None)
    if tol:
        ax.axhline(tol, color=red, linestyle=":", linewidth=1.2, label=f"tol {tol:g} (stop below)")
    ax.set_yscale("log")
    # Small labels: two of these panels stacked share the height of one.
    ax.set_ylabel("relative change of e1", color=red, fontsize=8)
    ax.set_title("Mean-Path convergence")
    twin = ax.twinx() if ax_update is None else ax_update
    twin.plot(it, np.maximum(e3 / len(mean_path.path_), floor), "s--", color="k", label="e3/n")
    twin.set_yscale("log")
    twin.set_ylabel(f"mean update e3/n [{units}]", fontsize=8)
    for axis in (ax, twin):
        axis.xaxis.set_major_locator(MaxNLocator(integer=True))
        axis.set_xlim(-0.3, max(len(e1) - 1, 1) + 0.3)
        axis.grid(True, which="major", alpha=0.3)
    if ax_update is None:
        ax.set_xlabel("iteration")
        handles, labels = ax.get_legend_handles_labels()
        more, more_labels = twin.get_legend_handles_labels()
        if legend:
            twin.legend(handles + more, labels + more_labels, fontsize=8, loc="upper right")
    else:
        ax.tick_params(labelbottom=False)
        if legend:
            ax.legend(fontsize=8, loc="best")
        ax_update.set_xlabel("iteration")


def draw_distance_space(ax: Axes, mean_path, units: str = "m", *, legend: bool = True) -> None:
    """The demonstrations in the Distance-Space of the Mean-Path (thesis Fig 4.7b).

    2-D paths: signed distance along the left normal against the path point
    index; NaN (a normal missing a demonstration) leaves a gap.
    """
    d = mean_path.distances_[..., 0]
    idx = np.arange(d.shape[1])
    for j, row in enumerate(d):
        ax.plot(
            idx, row, color=DEMO_COLOR, linewidth=0.8, label="demonstrations" if j == 0 else None
        )
    ax.axhline(0.0, color=MIMIC_METHODS["mean_path"].color, linewidth=1.6, label="Mean-Path")
    ax.set_xlabel("Mean-Path point index")
    ax.set_ylabel(f"signed normal distance [{units}]")
    ax.ticklabel_format(axis="y", style="plain", useOffset=False)
    ax.set_title("Distance-Space")
    if legend:
        ax.legend(fontsize=8)


def draw_gmr_tube(ax: Axes, gmr, n_points: int = 200, n_std: float = 2.0) -> None:
    """GMR mean path with a band of ±``n_std`` standard deviations across it (2-D)."""
    t = np.linspace(*gmr.time_range_, n_points)
    mean, cov = gmr.predict(t, return_cov=True)
    tangent = np.gradient(mean, axis=0)
    normal = np.column_stack((-tangent[:, 1], tangent[:, 0]))
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    sd = np.sqrt(np.einsum("ti,tij,tj->t", normal, cov, normal))
    upper, lower = mean + n_std * sd[:, None] * normal, mean - n_std * sd[:, None] * normal
    band = np.vstack((upper, lower[::-1]))
    ax.fill(
        band[:, 0],
        band[:, 1],
        color=MIMIC_METHODS["gmr"].color,
        alpha=0.2,
        label=f"GMR ±{n_std:g} sd",
    )
    ax.plot(mean[:, 0], mean[:, 1], color=MIMIC_METHODS["gmr"].color, linewidth=1.4, label="GMR")


def _scale_axes(ax: Axes, arrays: Sequence[np.ndarray]) -> bool:
    """Equal scale on 2-D axes, unless the data are so thin (a straight sweep) that their
    spread would vanish; then no offset on the ticks. Returns whether drawn to scale."""
    span = np.ptp(np.vstack([np.asarray(a)[:, :2] for a in arrays]), axis=0)
    to_scale = bool(span.min() >= 0.1 * span.max())
    if to_scale:
        ax.set_aspect("equal", adjustable="datalim")
    else:
        ax.ticklabel_format(style="plain", useOffset=False)
    return to_scale


#: Figure size (inches) of each :func:`mean_path_figure` layout.
_MEAN_PATH_LAYOUTS = {"row": (15.0, 4.6), "stacked": (9.6, 7.4)}


def mean_path_figure(
    demos: Sequence[np.ndarray],
    mean_path,
    *,
    units: str = "m",
    nominal: np.ndarray | None = None,
    gmr=None,
    title: str = "",
    layout: str = "row",
) -> Figure:
    """Demos with the Mean-Path (and GMR tube), the Distance-Space, the convergence.

    Parameters
    ----------
    demos : sequence of ndarray, each (n_j, 2)
        The demonstrations the Mean-Path was computed from.
    mean_path : fitted :class:`lfdkit.mimic.MeanPath`
    units : str
        Unit of the coordinates.
    nominal : ndarray (n, 2), optional
        The ground truth, dashed.
    gmr : fitted :class:`lfdkit.mimic.GMR`, optional
        Its ±2 sd tube is drawn.
    title : str
        Title of the first panel.
    layout : {"row", "stacked"}
        ``"row"``: the three side by side (15 in wide); ``"stacked"``: the
        demonstrations across the top, the other two below (9.6 in wide, for
        a long thin task or a page of limited width). The convergence is two
        panels, one above the other (:func:`draw_residual_history`).

    Notes
    -----
    The first panel is drawn to scale unless the demonstrations are so thin
    (a straight sweep) that their spread would vanish; its title then says
    that the axes are not to scale.
    """
    if layout not in _MEAN_PATH_LAYOUTS:
        raise ValueError(
            f"layout: expected one of {', '.join(map(repr, _MEAN_PATH_LAYOUTS))}, got {layout!r}"
        )
    fig = Figure(figsize=_MEAN_PATH_LAYOUTS[layout], layout="constrained")
    if layout == "row":
        grid = fig.add_gridspec(2, 3)
        ax0, ax1 = fig.add_subplot(grid[:, 0]), fig.add_subplot(grid[:, 1])
        ax2 = fig.add_subplot(grid[0, 2])
        ax3 = fig.add_subplot(grid[1, 2], sharex=ax2)
    else:
        grid = fig.add_gridspec(3, 2, height_ratios=(2.0, 1.0, 1.0))
        ax0, ax1 = fig.add_subplot(grid[0, :]), fig.add_subplot(grid[1:, 0])
        ax2 = fig.add_subplot(grid[1, 1])
        ax3 = fig.add_subplot(grid[2, 1], sharex=ax2)
    draw_demos(ax0, demos)
    if gmr is not None and demos[0].shape[1] == 2:
        draw_gmr_tube(ax0, gmr)
    draw_paths(ax0, {"Mean-Path": mean_path.path_}, nominal=nominal)
    to_scale = _scale_axes(ax0, demos)
    label_axes(ax0, 2, units)
    ax0.set_title(
        (title or "Demonstrations and generalized path")
        + ("" if to_scale else "\n(axes not to scale)")
    )
    draw_distance_space(ax1, mean_path, units, legend=False)
    draw_residual_history(ax2, mean_path, units, ax_update=ax3, legend=False)
    # One legend below the panels, outside the data; every label drawn is in it.
    _figure_legend(fig, [ax0, ax1, ax2, ax3], max_cols=7)
    return fig


def draw_rollouts(
    ax: Axes,
    path: np.ndarray,
    rollouts: Sequence[np.ndarray],
    *,
    goal_names: Sequence[str] | None = None,
) -> None:
    """The training path from A to B and DMP rollouts to new goals B′, B″, … (2-D or 3-D).

    Parameters
    ----------
    ax : Axes
    path : ndarray, shape (n, q)
        The generalized path the DMP was trained on.
    rollouts : sequence of ndarray, each (m, q)
        Rollout positions; each ends at its goal.
    goal_names : sequence of str, optional
        Name of each rollout's goal (default ``B′``, ``B″``, …), shown at the
        goal and in the legend as ``DMP → name``.
    """
    ax.plot(*_xy(path), color=PATH_COLOR, linewidth=2.0, label="generalized path")
    ax.plot(*_xy(path[:1]), "ko", markersize=5)
    ax.annotate("A", path[0, :2], textcoords="offset points", xytext=(-12, 4))
    ax.plot(*_xy(path[-1:]), "ks", markersize=5)
    ax.annotate("B", path[-1, :2], textcoords="offset points", xytext=(6, 4))
    for i, positions in enumerate(rollouts):
        color = ROLLOUT_COLORS[i % len(ROLLOUT_COLORS)]
        name = goal_names[i] if goal_names is not None else "B" + "\u2032" * (i + 1)
        ax.plot(*_xy(positions), "--", color=color, linewidth=1.6, label=f"DMP → {name}")
        ax.plot(*_xy(positions[-1:]), "s", color=color, markersize=5)
        ax.annotate(name, positions[-1, :2], textcoords="offset points", xytext=(6, -10))


def retargeting_figure(
    demos: Sequence[np.ndarray] | None,
    path: np.ndarray,
    path_times: np.ndarray,
    rollouts: Sequence[tuple[np.ndarray, np.ndarray]],
    *,
    units: str = "m",
    title: str = "",
    goal_names: Sequence[str] | None = None,
) -> Figure:
    """Demonstrations → generalized path → DMP to new goals, like thesis Fig 3.15 and 5.12.

    Left: the demonstrations, the generalized path from A to B and the DMP
    rollouts to new goals. Right: each coordinate over time, the path and the
    rollouts, so that timing and smoothness can be judged.

    Parameters
    ----------
    demos : sequence of ndarray, each (n_j, q), or None
    path : ndarray, shape (n, q)
        Generalized path (the DMP's training path), ``q`` 2 or 3.
    path_times : ndarray, shape (n,)
        Its times in seconds.
    rollouts : sequence of (times (m,), positions (m, q))
        DMP rollouts, times in seconds.
    units : str
        Unit of the coordinates.
    title : str
    goal_names : sequence of str, optional
        Name of each rollout's goal (default ``B′``, ``B″``, …).
    """
    q = path.shape[1]
    fig = Figure(figsize=(11.0, 4.8), layout="constrained")
    grid = fig.add_gridspec(q, 2, width_ratios=(1.25, 1.0))
    ax = fig.add_subplot(grid[:, 0], projection="3d" if q == 3 else None)
    if demos:
        draw_demos(ax, demos)
    draw_rollouts(ax, path, [positions for _, positions in rollouts], goal_names=goal_names)
    label_axes(ax, q, units)
    to_scale = True
    arrays = [path, *(demos or ()), *(p for _, p in rollouts)]
    if q == 2:
        to_scale = _scale_axes(ax, arrays)
    else:
        _equal_3d(ax, [np.asarray(a, dtype=np.float64) for a in arrays])
    _figure_legend(fig, [ax], max_cols=6)
    note = "" if to_scale else "(axes not to scale)"
    ax.set_title("\n".join(t for t in (title, note) if t))
    names = ("x", "y", "z")
    for k in range(q):
        axk = fig.add_subplot(grid[k, 1])
        axk.plot(path_times, path[:, k], color=PATH_COLOR, linewidth=2.0)
        for i, (times, positions) in enumerate(rollouts):
            color = ROLLOUT_COLORS[i % len(ROLLOUT_COLORS)]
            axk.plot(times, positions[:, k], "--", color=color, linewidth=1.4)
        axk.set_ylabel(f"{names[k]} [{units}]")
        if k == q - 1:
            axk.set_xlabel("time [s]")
        else:
            axk.tick_params(labelbottom=False)
    return fig


# --------------------------------------------------------------------- emulation
#: Colour of each obstacle class; classes not listed take ``EXTRA_CLASS_COLORS`` in turn.
CLASS_COLORS = {"obstacle": "#9a9a9a", "cup": "#17becf", "marker": "#2ca02c"}
EXTRA_CLASS_COLORS = ("#9467bd", "#e377c2", "#8c564b", "#7f7f7f", "#bcbd22")
#: Planned paths in an emulation figure, in turn.
PLAN_COLORS = ("#1f77b4", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#ff7f0e")
#: Colour map of the reward: hot (bright yellow) is high, dark is low.
REWARD_CMAP = "inferno"
EMULATION_NOMINAL_STYLE = {"color": "k", "linestyle": "--", "linewidth": 1.6, "label": "nominal"}
#: Demonstrations are drawn over the plans (dotted), so that a plan that reproduces one
#: does not hide it.
EMULATION_DEMO_STYLE = {"color": "k", "linestyle": (0, (1, 1.5)), "linewidth": 1.3, "zorder": 5}
#: The goal, where one is marked.
GOAL_STYLE = {
    "marker": "*",
    "markersize": 14,
    "color": "w",
    "markeredgecolor": "k",
    "linestyle": "none",
    "zorder": 6,
    "label": "goal",
}
#: Fixed objects of a task that are not obstacles (a dustpan), as dark lines.
OUTLINE_STYLE = {"color": "0.15", "linewidth": 2.2, "zorder": 3}
_PANEL_KEYS = ("reward", "nominal", "scene", "demos", "plans", "title", "goal", "outlines")


def _is_3d(ax: Axes) -> bool:
    return getattr(ax, "name", "") == "3d"


def _class_colors(classes: Sequence[str], colors: Mapping[str, str] | None) -> dict[str, str]:
    """Colour per class: ``colors``, then ``CLASS_COLORS``, then the extra colours in turn."""
    chosen = {**CLASS_COLORS, **(colors or {})}
    out, k = {}, 0
    for label in classes:
        if label in chosen:
            out[label] = chosen[label]
        else:
            out[label] = EXTRA_CLASS_COLORS[k % len(EXTRA_CLASS_COLORS)]
            k += 1
    return out


def _bounded_parts(scene, region: tuple[np.ndarray, np.ndarray] | None) -> list:
    """Each obstacle, or, where it is unbounded (a half-space), its part in ``region``.

    An unbounded obstacle is left out where no region is known.
    """
    parts = []
    for obstacle in scene:
        if np.all(np.isfinite(np.stack(obstacle.bounds()))):
            parts.append(obstacle)
        elif region is not None:
            parts.append(obstacle.clipped(*region))
    return parts


def _drawn_region(ax: Axes, scene, q: int) -> tuple[np.ndarray, np.ndarray] | None:
    """The box of what the axes show so far and the bounded obstacles, grown by 10 %."""
    boxes = []
    limits = [ax.dataLim] if not _is_3d(ax) else [ax.xy_dataLim, ax.zz_dataLim]
    if all(np.all(np.isfinite(b.get_points())) and b.width >= 0 for b in limits):
        if _is_3d(ax):
            (x0, y0), (x1, y1) = ax.xy_dataLim.get_points()
            z0, z1 = ax.zz_dataLim.get_points()[:, 0]
            boxes.append(np.array([[x0, y0, z0], [x1, y1, z1]]))
        else:
            boxes.append(ax.dataLim.get_points())
    for obstacle in scene:
        bounds = np.stack(obstacle.bounds())
        if np.all(np.isfinite(bounds)):
            boxes.append(bounds)
    boxes = [b[:, :q] for b in boxes if b.shape[1] >= q]
    if not boxes:
        return None
    lower, upper = np.min([b[0] for b in boxes], axis=0), np.max([b[1] for b in boxes], axis=0)
    pad = 0.1 * max(float((upper - lower).max()), 1e-9)
    return lower - pad, upper + pad


def draw_scene(
    ax: Axes,
    scene,
    colors: Mapping[str, str] | None = None,
    region: tuple[np.ndarray, np.ndarray] | None = None,
) -> None:
    """Obstacles as filled outlines (a round one's circle), one colour and legend entry per class.

    Parameters
    ----------
    ax : Axes
        2-D axes, or 3-D axes for a 3-D scene (spheres, centres marked).
    scene : Scene
    colors : mapping of class label to colour, optional
        Overrides :data:`CLASS_COLORS`; unlisted classes take
        :data:`EXTRA_CLASS_COLORS` in turn.
    region : (lower, upper), optional
        The box (two points of the scene's dimension) in which an unbounded
        obstacle (a half-space) is drawn; by default what the axes hold so far
        and the bounded obstacles, grown by 10 %.

    Notes
    -----
    An obstacle of radius 0 is drawn as a marker at its centre (and a line
    along a rod's axis). In 3-D each obstacle is drawn as its covering balls
    (:meth:`lfdkit.model.scene.Obstacle.balls`), a half-space as its surface.
    """
    palette = _class_colors(scene.classes, colors)
    if len(scene) and region is None:
        region = _drawn_region(ax, scene, scene.obstacles[0].n_dims)
    parts = _bounded_parts(scene, region)
    if _is_3d(ax):
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 24), np.linspace(0, np.pi, 12))
        sphere = np.stack((np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v)))
        for obstacle in parts:
            if getattr(obstacle, "region", None) is not None:  # a half-space's part: its surface
                face = obstacle.section()[1]
                if len(face) >= 3:
                    surface = Poly3DCollection(
                        [face], alpha=0.25, facecolor=palette[obstacle.label]
                    )
                    ax.add_collection3d(surface)
                continue
            for centre, radius in zip(*obstacle.balls(), strict=True):
                if radius > 0:
                    x, y, z = centre[:, None, None] + radius * sphere
                    ax.plot_surface(
                        x, y, z, color=palette[obstacle.label], alpha=0.35, linewidth=0, shade=True
                    )
        for label in scene.classes:
            centres = np.array([o.position for o in scene if o.label == label])
            ax.plot(*_xy(centres), "o", color=palette[label], markersize=5, label=label)
        return
    labelled: set[str] = set()
    for obstacle in parts:
        color = palette[obstacle.label]
        label = None if obstacle.label in labelled else obstacle.label
        labelled.add(obstacle.label)
        outline = obstacle.outline()
        if len(outline) < 2:  # a half-space with no part where the axes draw
            continue
        x, y = outline.T
        if obstacle.radius > 0 or abs(np.dot(x, np.roll(y, 1)) - np.dot(y, np.roll(x, 1))) > 0:
            # A radius, or an outline with an area (a sharp box): drawn as a solid.
            ax.add_patch(
                Polygon(
                    outline,
                    closed=True,
                    facecolor=color,
                    edgecolor="k",
                    linewidth=0.8,
                    alpha=0.9,
                    zorder=3,
                    label=label,
                )
            )
        else:
            axis = obstacle.outline(4)
            if np.ptp(axis, axis=0).max() > 0:  # a rod of radius 0: its axis
                ax.plot(*axis.T, "-", color=color, linewidth=1.5, zorder=3)
            ax.plot(
                *obstacle.position,
                "X",
                color=color,
                markeredgecolor="k",
                markersize=9,
                zorder=3,
                label=label,
            )


def _reward_extent(
    paths: Sequence[np.ndarray], scene, margin: float
) -> tuple[float, float, float, float]:
    """Box around the 2-D paths and obstacles, padded by ``margin`` × its larger side."""
    pts = [np.asarray(p, dtype=np.float64)[:, :2] for p in paths]
    for obstacle in scene:
        bounds = np.stack(obstacle.bounds())[:, :2]
        pts.append(bounds[np.all(np.isfinite(bounds), axis=1)])  # a half-space: its finite side
    allpts = np.vstack(pts)
    lo, hi = allpts.min(axis=0), allpts.max(axis=0)
    span = float((hi - lo).max()) or 1.0
    pad = margin * span
    return lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad


def draw_reward(
    ax: Axes,
    reward,
    nominal: np.ndarray,
    scene,
    *,
    resolution: int = 200,
    margin: float = 0.15,
    levels: int = 30,
    extent: tuple[float, float, float, float] | None = None,
    vmin: float | None = None,
):
    """Filled contours of a learned reward in a 2-D scene, like thesis Fig 5.7–5.8 and 6.11.

    Parameters
    ----------
    ax : Axes
    reward : Reward
    nominal : array_like, shape (n, 2)
        The nominal path the reward is relative to.
    scene : Scene
        Obstacles; every class must be known to ``reward``.
    resolution : int
        Grid points along each axis.
    margin : float
        Padding around the nominal and the obstacles, as a fraction of the larger
        side of their bounding box.
    levels : int
        Number of contour bands.
    extent : (xmin, xmax, ymin, ymax), optional
        Grid limits; replaces the box from the nominal, obstacles and ``margin``.
    vmin : float, optional
        Lowest reward of the colour scale; lower values take the lowest colour.
        Default: one unit (an obstacle's height) below the lowest reward at an
        obstacle centre, so that the steep nominal term far from the path does
        not wash out the obstacles; the whole range without obstacles.

    Returns
    -------
    matplotlib.contour.QuadContourSet
        The mappable, for a colour bar (``fig.colorbar(cs, ax=ax)``).

    Raises
    ------
    ValueError
        For a nominal that is not 2-D, or bad ``resolution``, ``margin`` or ``levels``.
    """
    nominal = check_path(nominal, "nominal")
    if nominal.shape[1] != 2:
        raise ValueError(
            f"nominal: draw_reward draws 2-D rewards only, got {nominal.shape[1]}-D points "
            "(use emulation_figure for a 3-D line plot)"
        )
    resolution = check_positive(resolution, "resolution", integer=True)
    if resolution < 2:
        raise ValueError(f"resolution: needs at least 2, got {resolution}")
    margin = check_positive(margin, "margin", allow_zero=True)
    levels = check_positive(levels, "levels", integer=True)
    if extent is None:
        extent = _reward_extent([nominal], scene, margin)
    x0, x1, y0, y1 = (float(v) for v in extent)
    if not (x1 > x0 and y1 > y0):
        raise ValueError(f"extent: expected xmin < xmax and ymin < ymax, got {extent}")
    gx, gy = np.meshgrid(np.linspace(x0, x1, resolution), np.linspace(y0, y1, resolution))
    values = reward.value(np.column_stack((gx.ravel(), gy.ravel())), nominal, scene)
    values = values.reshape(gx.shape)
    top, bottom = float(values.max()), float(values.min())
    if vmin is None:
        vmin = bottom
        if len(scene):
            vmin = max(bottom, float(reward.value(scene.positions, nominal, scene).min()) - 1.0)
    vmin = min(float(vmin), top - 1e-12 * max(1.0, abs(top)))
    bounds = np.linspace(vmin, top, levels + 1)
    return ax.contourf(
        gx,
        gy,
        values,
        levels=bounds,
        cmap=REWARD_CMAP,
        extend="min" if bottom < vmin else "neither",
        zorder=0,
    )


def _panel_data(reward, nominal, scene, demos, plans, index: str = ""):
    """Validated arrays of one emulation panel: nominal (n, q), demos, plans by name."""
    where = f"panels[{index}]." if index else ""
    nominal = check_path(nominal, f"{where}nominal")
    q = nominal.shape[1]
    if q not in (2, 3):
        raise ValueError(f"{where}nominal: expected 2-D or 3-D points, got {q}-D")
    if not isinstance(scene, Scene):
        raise TypeError(f"{where}scene: expected an lfdkit.emulate.Scene")
    if len(scene) and scene.positions.shape[1] != q:
        raise ValueError(f"{where}scene: {scene.positions.shape[1]}-D obstacles, {q}-D nominal")
    demos = [check_path(d, f"{where}demos[{j}]", n_dims=q) for j, d in enumerate(demos or ())]
    plans = {
        str(name): check_path(getattr(value, "points", value), f"{where}plans[{name!r}]", n_dims=q)
        for name, value in dict(plans or {}).items()
    }
    return nominal, demos, plans


def _panel_marks(goal, outlines, q: int, where: str = ""):
    """Validated goal (1, q) or None and outlines by name of one emulation panel."""
    if goal is not None:
        goal = check_path(np.atleast_2d(goal), f"{where}goal", min_points=1, n_dims=q)
    outlines = {
        str(name): check_path(points, f"{where}outlines[{name!r}]", n_dims=q)
        for name, points in dict(outlines or {}).items()
    }
    return goal, outlines


def _equal_3d(ax: Axes, arrays: Sequence[np.ndarray]) -> None:
    """Equal scale on the three axes: the box's sides in proportion to the data's ranges.

    Each range is padded by 5 % of the largest and kept at least 10 % of it, so
    that flat data (a path on a table) still gets a visible box.
    """
    pts = np.vstack([np.asarray(a, dtype=np.float64).reshape(-1, 3) for a in arrays])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    largest = float((hi - lo).max()) or 1.0
    ranges = np.maximum(hi - lo, 0.1 * largest) + 0.1 * largest
    centre = 0.5 * (lo + hi)
    ax.set_xlim(centre[0] - 0.5 * ranges[0], centre[0] + 0.5 * ranges[0])
    ax.set_ylim(centre[1] - 0.5 * ranges[1], centre[1] + 0.5 * ranges[1])
    ax.set_zlim(centre[2] - 0.5 * ranges[2], centre[2] + 0.5 * ranges[2])
    ax.set_box_aspect(tuple(ranges))
    # Ticks as dense on every axis: a short side gets few, not crowded, labels.
    for axis, extent in zip((ax.xaxis, ax.yaxis, ax.zaxis), ranges, strict=True):
        axis.set_major_locator(MaxNLocator(nbins=max(2, round(6 * extent / ranges.max()))))


def _emulation_panel(
    fig: Figure,
    ax: Axes,
    reward,
    nominal: np.ndarray,
    scene,
    demos: list[np.ndarray],
    plans: dict[str, np.ndarray],
    *,
    plan_colors: Mapping[str, str],
    class_colors: Mapping[str, str],
    units: str,
    title: str,
    plan_styles: Mapping[str, Mapping] | None = None,
    goal: np.ndarray | None = None,
    outlines: Mapping[str, np.ndarray] | None = None,
) -> None:
    q = nominal.shape[1]
    outlines = dict(outlines or {})
    if q == 2:
        marks = [*outlines.values(), *([] if goal is None else [goal])]
        extent = _reward_extent([nominal, *demos, *plans.values(), *marks], scene, 0.15)
        mappable = draw_reward(ax, reward, nominal, scene, extent=extent)
        cax = ax.inset_axes([1.03, 0.0, 0.035, 1.0])
        fig.colorbar(mappable, cax=cax, label="reward", ticks=MaxNLocator(6))
    drawn = np.vstack([nominal, *demos, *plans.values()])
    pad = 0.1 * max(float(np.ptp(drawn, axis=0).max()), 1e-9)
    region = (drawn.min(axis=0) - pad, drawn.max(axis=0) + pad)  # where a half-space is drawn
    draw_scene(ax, scene, colors=class_colors, region=region)
    for name, points in outlines.items():
        ax.plot(*_xy(points), **OUTLINE_STYLE, label=name)
    for j, demo in enumerate(demos):
        ax.plot(*_xy(demo), **EMULATION_DEMO_STYLE, label="demonstrations" if j == 0 else None)
    ax.plot(*_xy(nominal), **EMULATION_NOMINAL_STYLE)
    for name, path in plans.items():
        style = {"color": plan_colors[name], "linewidth": 1.8, "zorder": 4}
        style.update((plan_styles or {}).get(name, {}))
        halo = None
        if q == 2:  # a white rim, wider than the line, keeps it apart from the contours
            rim = float(style["linewidth"]) + 1.8
            halo = [patheffects.withStroke(linewidth=rim, foreground="w", alpha=0.9)]
        ax.plot(*_xy(path), label=name, path_effects=halo, **style)
    if goal is not None:
        ax.plot(*_xy(goal), **GOAL_STYLE)
    label_axes(ax, q, units)
    if q == 2:
        ax.set_aspect("equal", adjustable="box")
    else:
        boxes = [np.stack(o.bounds()) for o in scene]
        _equal_3d(
            ax, [nominal, *demos, *plans.values(), *(b for b in boxes if np.isfinite(b).all())]
        )
    ax.set_title(title)


def _panel_height(panels: Sequence[Mapping], data: Sequence[tuple], width: float = 5.6) -> float:
    """Inches per panel row: 2-D panels are drawn at equal scale, so wide scenes need less.

    ``data`` holds per panel the nominal and a list of every array drawn.
    """
    if any(nominal.shape[1] == 3 for nominal, _ in data):
        return 3.9
    aspects = []
    for panel, (_, arrays) in zip(panels, data, strict=True):
        x0, x1, y0, y1 = _reward_extent(arrays, panel["scene"], 0.15)
        aspects.append((y1 - y0) / (x1 - x0))
    # The axes' width is the panel's less about 1.5 in for the colour bar and the labels;
    # the height adds about 0.9 in for the title, the tick labels and the x label.
    return float(np.clip((width - 1.5) * max(aspects) + 0.9, 2.0, max(3.9, 0.7 * width)))


def _figure_legend(fig: Figure, axes: Sequence[Axes], max_cols: int) -> None:
    """One legend below the panels, each label once (the first panel's handle)."""
    entries: dict[str, object] = {}
    for ax in axes:
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            entries.setdefault(label, handle)
    if entries:
        fig.legend(
            list(entries.values()),
            list(entries),
            loc="outside lower center",
            ncols=min(len(entries), max_cols),
            fontsize=8,
            frameon=False,
        )


def plan_colors(names: Sequence[str]) -> dict[str, str]:
    """Colour per planned path, by name: :data:`PLAN_COLORS` in turn, a name once."""
    unique = list(dict.fromkeys(names))
    return {name: PLAN_COLORS[i % len(PLAN_COLORS)] for i, name in enumerate(unique)}


def emulation_figure(
    reward,
    nominal: np.ndarray,
    scene,
    *,
    demos: Sequence[np.ndarray] | None = None,
    plans: Mapping[str, np.ndarray] | None = None,
    units: str = "m",
    title: str = "",
    plan_styles: Mapping[str, Mapping] | None = None,
    goal: np.ndarray | None = None,
    outlines: Mapping[str, np.ndarray] | None = None,
) -> Figure:
    """A learned reward in a scene with demonstrations and planned paths (thesis Fig 5.7, 6.11).

    2-D: filled contours of the reward (hot is high) with a colour bar, the
    obstacles, the nominal path dashed, each planned path in its own colour
    and the demonstrations black dotted over them; a legend below. 3-D: the
    same paths and the obstacles as spheres, without contours.

    Parameters
    ----------
    reward : Reward
    nominal : array_like, shape (n, q), q 2 or 3
        The nominal path the reward is relative to.
    scene : Scene
    demos : sequence of array_like, each (n_j, q), optional
    plans : mapping of name to array_like (K, q) or Plan, optional
        Planned paths, e.g. ``{"MPC H=8": plan.points}``, in :data:`PLAN_COLORS`,
        drawn in this order.
    units : str
        Axis unit label.
    title : str
    plan_styles : mapping of plan name to mapping, optional
        Line properties that replace a plan's defaults (``color``,
        ``linewidth`` 1.8, ``zorder`` 4), e.g. ``{"reference": {"linewidth":
        5, "alpha": 0.5}}``: a wide band under a plan drawn after it, so that
        both stay visible where they coincide.
    goal : array_like, shape (q,), optional
        Marked with a star (legend ``goal``).
    outlines : mapping of name to array_like (k, q), optional
        Fixed objects of the task that are not obstacles (e.g. a dustpan's
        walls), drawn as dark lines under their names.

    Returns
    -------
    Figure
    """
    nominal, demos, plans = _panel_data(reward, nominal, scene, demos, plans)
    q = nominal.shape[1]
    goal, outlines = _panel_marks(goal, outlines, q)
    if q == 2:
        arrays = [nominal, *demos, *plans.values(), *outlines.values()]
        arrays += [] if goal is None else [goal]
        x0, x1, y0, y1 = _reward_extent(arrays, scene, 0.15)
        height = float(np.clip(5.6 * (y1 - y0) / (x1 - x0) + 1.9, 3.4, 8.0))
    else:
        height = 6.4
    fig = Figure(figsize=(7.4, height), layout="constrained")
    ax = fig.add_subplot(projection="3d" if q == 3 else None)
    _emulation_panel(
        fig,
        ax,
        reward,
        nominal,
        scene,
        demos,
        plans,
        plan_colors=plan_colors(list(plans)),
        class_colors=_class_colors(scene.classes, None),
        units=units,
        title=title,
        plan_styles=plan_styles,
        goal=goal,
        outlines=outlines,
    )
    _figure_legend(fig, [ax], max_cols=4)
    return fig


def emulation_grid(
    panels: Sequence[Mapping],
    *,
    ncols: int = 3,
    units: str = "m",
    title: str = "",
    plan_styles: Mapping[str, Mapping] | None = None,
    panel_width: float = 5.6,
) -> Figure:
    """Several emulation panels in one figure, e.g. transfer scenes (thesis Fig 6.12–6.13).

    A planned path's name and an obstacle class keep one colour across the
    panels, and one legend below lists them all.

    Parameters
    ----------
    panels : sequence of mapping
        One per panel, with the arguments of :func:`emulation_figure`: required
        ``"reward"``, ``"nominal"``, ``"scene"``; optional ``"demos"``,
        ``"plans"``, ``"title"``, ``"goal"`` and ``"outlines"``.
    ncols : int
        Panels per row.
    units : str
        Axis unit label.
    title : str
        Figure title.
    plan_styles : mapping of plan name to mapping, optional
        As :func:`emulation_figure`'s, for every panel.
    panel_width : float
        Width of one panel in inches, its colour bar included (the figure is
        ``ncols`` of them wide).

    Returns
    -------
    Figure

    Raises
    ------
    ValueError
        For no panels, or a panel with a missing or unknown key.
    """
    ncols = check_positive(ncols, "ncols", integer=True)
    panel_width = check_positive(panel_width, "panel_width")
    panels = list(panels)
    if not panels:
        raise ValueError("panels: needs at least one panel")
    data, marks = [], []
    for i, panel in enumerate(panels):
        if not isinstance(panel, Mapping):
            raise TypeError(f"panels[{i}]: expected a mapping, got {type(panel).__name__}")
        unknown = sorted(set(panel) - set(_PANEL_KEYS))
        if unknown:
            raise ValueError(
                f"panels[{i}]: unknown key {unknown[0]!r}; "
                f"expected some of {', '.join(_PANEL_KEYS)}"
            )
        missing = [k for k in ("reward", "nominal", "scene") if k not in panel]
        if missing:
            raise ValueError(f"panels[{i}]: missing key {missing[0]!r}")
        data.append(
            _panel_data(
                panel["reward"],
                panel["nominal"],
                panel["scene"],
                panel.get("demos"),
                panel.get("plans"),
                str(i),
            )
        )
        q = data[-1][0].shape[1]
        marks.append(_panel_marks(panel.get("goal"), panel.get("outlines"), q, f"panels[{i}]."))
    colors = plan_colors([name for _, _, plans in data for name in plans])
    class_colors = _class_colors(
        list(dict.fromkeys(c for panel in panels for c in panel["scene"].classes)), None
    )
    ncols = min(ncols, len(panels))
    nrows = -(-len(panels) // ncols)
    drawn = [
        (
            nominal,
            [nominal, *demos, *plans.values(), *outlines.values(), *([] if g is None else [g])],
        )
        for (nominal, demos, plans), (g, outlines) in zip(data, marks, strict=True)
    ]
    height = _panel_height(panels, drawn, panel_width)
    fig = Figure(figsize=(panel_width * ncols, height * nrows + 0.8), layout="constrained")
    axes = []
    for i, (panel, (nominal, demos, plans), (goal, outlines)) in enumerate(
        zip(panels, data, marks, strict=True)
    ):
        q = nominal.shape[1]
        ax = fig.add_subplot(nrows, ncols, i + 1, projection="3d" if q == 3 else None)
        _emulation_panel(
            fig,
            ax,
            panel["reward"],
            nominal,
            panel["scene"],
            demos,
            plans,
            plan_colors=colors,
            class_colors=class_colors,
            units=units,
            title=panel.get("title", ""),
            plan_styles=plan_styles,
            goal=goal,
            outlines=outlines,
        )
        axes.append(ax)
    _figure_legend(fig, axes, max_cols=8)
    if title:
        fig.suptitle(title)
    return fig
