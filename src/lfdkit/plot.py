"""Figures a user wants to look at, one function each.

Functions that draw into an existing ``Axes`` are named ``draw_*``; functions that
build a whole figure are named ``*_figure`` and return a
:class:`matplotlib.figure.Figure` (no pyplot state, so they work headless and in
threads; save with ``fig.savefig(path)``).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

__all__ = [
    "METHOD_COLORS",
    "comparison_figure",
    "draw_demos",
    "draw_distance_space",
    "draw_gmr_tube",
    "draw_paths",
    "draw_residual_history",
    "draw_rollouts",
    "mean_path_figure",
    "retargeting_figure",
]

#: Consistent colours per method across every figure.
METHOD_COLORS = {
    "Mean-Path": "#d62728",
    "Mean-Path (median)": "#ff7f0e",
    "Mean-Path (biweight)": "#bcbd22",
    "GMR (BIC)": "#1f77b4",
    "gmr (package)": "#17becf",
    "NLPCA": "#2ca02c",
    "arc-length average": "#9467bd",
    "DBA (tslearn)": "#8c564b",
    "soft-DTW (tslearn)": "#e377c2",
}
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
        ax.plot(*_xy(path), color=METHOD_COLORS.get(name), linewidth=1.6, label=name)


def _axis_labels(ax: Axes, q: int, units: str) -> None:
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
    _axis_labels(ax, q, units)
    if q == 2:
        ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(title)
    ax.legend(fontsize=8, loc="best")
    return fig


def draw_residual_history(ax: Axes, mean_path) -> None:
    """e1 per accepted iteration (left axis) and e3 (right axis), like thesis Fig 4.9."""
    it = np.arange(len(mean_path.residual_history_))
    ax.plot(it, mean_path.residual_history_, "o-", color="#d62728", label="e1 (residual)")
    ax.set_xlabel("iteration")
    ax.set_ylabel("e1 [units²]", color="#d62728")
    twin = ax.twinx()
    twin.plot(it, mean_path.innovation_history_, "s--", color="k", label="e3 (update size)")
    twin.set_ylabel("e3 [units]")
    twin.set_yscale("log")
    ax.set_title("Mean-Path convergence")


def draw_distance_space(ax: Axes, mean_path, units: str = "m") -> None:
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
    ax.axhline(0.0, color=METHOD_COLORS["Mean-Path"], linewidth=1.6, label="Mean-Path")
    ax.set_xlabel("Mean-Path point index")
    ax.set_ylabel(f"normal distance [{units}]")
    ax.set_title("Distance-Space")
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
        color=METHOD_COLORS["GMR (BIC)"],
        alpha=0.2,
        label=f"GMR ±{n_std:g} sd",
    )
    ax.plot(mean[:, 0], mean[:, 1], color=METHOD_COLORS["GMR (BIC)"], linewidth=1.4)


def mean_path_figure(
    demos: Sequence[np.ndarray],
    mean_path,
    *,
    units: str = "m",
    nominal: np.ndarray | None = None,
    gmr=None,
    title: str = "",
) -> Figure:
    """Three panels: demos with the Mean-Path (and GMR tube), Distance-Space, convergence."""
    fig = Figure(figsize=(15.0, 4.6), layout="constrained")
    ax0, ax1, ax2 = fig.subplots(1, 3)
    draw_demos(ax0, demos)
    if gmr is not None and demos[0].shape[1] == 2:
        draw_gmr_tube(ax0, gmr)
    draw_paths(ax0, {"Mean-Path": mean_path.path_}, nominal=nominal)
    ax0.set_aspect("equal", adjustable="datalim")
    _axis_labels(ax0, 2, units)
    ax0.set_title(title or "Demonstrations and generalized path")
    ax0.legend(fontsize=8)
    draw_distance_space(ax1, mean_path, units)
    draw_residual_history(ax2, mean_path)
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
    _axis_labels(ax, q, units)
    if q == 2:
        ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=8, loc="best")
    ax.set_title(title)
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
