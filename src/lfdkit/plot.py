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
    "mean_path_figure",
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
