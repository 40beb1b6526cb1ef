"""Figures of the sweeping task: top views of simulated sweeps.

Drawing that is not particular to sweeping (scenes, plans, rewards, colours)
is :mod:`lfdkit.app.plot`'s; this module adds the dustpan and the brush's and the
cube's traces of :class:`~lfdkit.tasks.sweeping.sim.SweepResult`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from lfdkit.app.plot import draw_scene, label_axes, plan_colors
from lfdkit.model.scene import Scene
from lfdkit.tasks.sweeping.scenarios import Dustpan

if TYPE_CHECKING:
    from lfdkit.tasks.sweeping.sim import SweepResult

__all__ = ["draw_dustpan", "dustpan_outline", "sweep_figure"]


def dustpan_outline(dustpan: Dustpan) -> np.ndarray:
    """The dustpan floor's walls in the world, (4, 2): one side, the back, the other side.

    The open side (from the last corner back to the first) is left out.
    """
    corners = np.array([[0.0, -0.5], [dustpan.depth, -0.5], [dustpan.depth, 0.5], [0.0, 0.5]]) * [
        1.0,
        dustpan.width,
    ]
    return dustpan.position + corners @ dustpan.axes


def draw_dustpan(ax: Axes, dustpan: Dustpan) -> None:
    """The dustpan's floor as an outline; its open side dashed."""
    world = dustpan_outline(dustpan)
    ax.plot(*world.T, color="0.25", linewidth=2.0, label="dustpan", zorder=2)
    ax.plot(*world[[3, 0]].T, color="0.25", linewidth=1.0, linestyle=":", zorder=2)


def sweep_figure(
    dustpan: Dustpan,
    scene: Scene,
    runs: Mapping[str, SweepResult],
    *,
    ax: Axes | None = None,
    title: str = "",
    legend: bool = True,
) -> Figure:
    """Top view of simulated sweeps: the brush's and the cube's traces, dustpan and obstacles.

    Parameters
    ----------
    dustpan : Dustpan
    scene : Scene
        Obstacles at their start positions.
    runs : mapping of str to SweepResult
        One or more simulated sweeps in this scene, by planner name.
    ax : Axes, optional
        Draw into these axes (default: a new figure).
    title : str
    legend : bool
        Draw a legend in the axes (off when a figure collects one legend for
        several panels).

    Returns
    -------
    Figure

    Notes
    -----
    Each run's flange trace is a solid line, the cube's a dotted line of the
    same colour ending in a square where the cube came to rest; the legend
    says whether the run succeeded.
    """
    if ax is None:
        fig = Figure(figsize=(8.5, 3.4), layout="constrained")
        ax = fig.add_subplot()
    else:
        fig = ax.figure
    draw_dustpan(ax, dustpan)
    draw_scene(ax, scene)
    colors = plan_colors(list(runs))
    for name, result in runs.items():
        color = colors[name]
        verdict = "ok" if result.success else "failed"
        if len(result.tool_trace):
            ax.plot(
                *result.tool_trace[:, :2].T,
                color=color,
                linewidth=1.6,
                label=f"{name} ({verdict})",
                zorder=4,
            )
            ax.plot(*result.cube_trace.T, color=color, linewidth=1.0, linestyle=":", zorder=4)
            ax.plot(
                *result.cube_final, "s", color=color, markeredgecolor="k", markersize=6, zorder=5
            )
        else:
            ax.plot([], [], color=color, label=f"{name} (not run)")
    ax.set_aspect("equal")
    label_axes(ax, 2, "m")  # the simulation's unit
    ax.grid(True, alpha=0.3)
    if title:
        ax.set_title(title, fontsize=10)
    if legend:
        ax.legend(fontsize=7, loc="best")
    return fig
