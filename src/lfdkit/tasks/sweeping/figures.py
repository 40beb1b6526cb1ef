"""Figures of the sweeping task: top views of simulated sweeps, and MuJoCo's picture.

Drawing that is not particular to sweeping (scenes, plans, rewards, colours)
is :mod:`lfdkit.app.plot`'s; this module adds the dustpan and the brush's and the
cube's traces of :class:`~lfdkit.tasks.sweeping.sim.SweepResult`. The top view
and the render share one key: obstacles in their MuJoCo class colours, the cube
green, its path dark grey (:data:`~lfdkit.tasks.sweeping.sim.RENDER_TRACES`), the
first run's brush path in the first plan colour; legends sit outside the data.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from lfdkit.app.plot import draw_scene, label_axes, plan_colors
from lfdkit.model.scene import Scene
from lfdkit.tasks.sweeping.scenarios import CUBE, Dustpan, obstacle_class
from lfdkit.tasks.sweeping.sim import RENDER_TRACES

if TYPE_CHECKING:
    from lfdkit.tasks.sweeping.sim import SweepResult

__all__ = [
    "draw_dustpan",
    "dustpan_outline",
    "mujoco_class_colors",
    "render_figure",
    "sweep_figure",
]


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
    Each run's flange trace is a solid line in the run's colour, the cube's a
    dark grey dotted line ending in a green square (edged in the run's colour)
    where the cube came to rest; the legend says whether each run succeeded
    and names the cube's path and rest; it sits to the right of the axes.
    """
    if ax is None:
        fig = Figure(figsize=(8.5, _top_view_height(dustpan, scene, runs)), layout="constrained")
        ax = fig.add_subplot()
    else:
        fig = ax.figure
    draw_dustpan(ax, dustpan)
    # A half-space is drawn over all the view shows (the runs are drawn later).
    points = _top_view_points(dustpan, scene, runs)
    low, high = points.min(axis=0), points.max(axis=0)
    grow = 0.1 * (high - low)
    draw_scene(ax, scene, mujoco_class_colors(scene), region=(low - grow, high + grow))
    colors = plan_colors(list(runs))
    cube_path = RENDER_TRACES["cube's path"]
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
            ax.plot(*result.cube_trace.T, color=cube_path, linewidth=1.2, linestyle=":", zorder=4)
            ax.plot(
                *result.cube_final,
                "s",
                color=CUBE.rgba,
                markeredgecolor=color,
                markeredgewidth=1.5,
                markersize=6,
                zorder=5,
            )
        else:
            ax.plot([], [], color=color, label=f"{name} (not run)")
    if any(len(result.tool_trace) for result in runs.values()):
        ax.plot([], [], color=cube_path, linewidth=1.2, linestyle=":", label="cube's path")
        ax.plot([], [], "s", color=CUBE.rgba, markeredgecolor="k", label="cube at rest")
    ax.set_aspect("equal")
    label_axes(ax, 2, "m")  # the simulation's unit
    ax.grid(True, alpha=0.3)
    if title:
        ax.set_title(title, fontsize=10)
    if legend:
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    return fig


def _top_view_points(dustpan: Dustpan, scene: Scene, runs: Mapping[str, SweepResult]):
    """Every point the top view must show: outlines, traces, a point of each half-space."""
    points = [dustpan_outline(dustpan)]
    for o in scene:  # an unbounded obstacle (a half-space): its plane's point, no outline
        bounded = np.all(np.isfinite(np.stack(o.bounds())))
        points.append(o.outline() if bounded else o.position[None, :2])
    points += [r.tool_trace[:, :2] for r in runs.values() if len(r.tool_trace)]
    return np.vstack(points)


def _top_view_height(dustpan: Dustpan, scene: Scene, runs: Mapping[str, SweepResult]) -> float:
    """Figure height (in) that fits the drawing at equal scale in 8.5 in, legend at the side."""
    width, height = np.ptp(_top_view_points(dustpan, scene, runs), axis=0)
    # About 5.8 in of the width is the axes (the rest: labels and the legend).
    return float(np.clip(5.8 * height / max(width, 1e-9) + 1.3, 2.6, 7.0))


def mujoco_class_colors(scene: Scene) -> dict[str, tuple[float, ...]]:
    """Each obstacle class's colour in MuJoCo (:func:`obstacle_class`), by label."""
    return {label: tuple(obstacle_class(label).rgba) for label in scene.classes}


def render_figure(image: np.ndarray, scene: Scene | None = None, *, title: str = "") -> Figure:
    """MuJoCo's picture of a sweep with its key below: the traces, the cube, the obstacles.

    Parameters
    ----------
    image : ndarray, shape (height, width, 3)
        :attr:`~lfdkit.tasks.sweeping.sim.SweepResult.image`.
    scene : Scene, optional
        The sweep's obstacles: their classes, and a moving one's track, join the key.
    title : str

    Returns
    -------
    Figure
        The same colours as :func:`sweep_figure`'s for one run.
    """
    height, width = image.shape[:2]
    fig = Figure(figsize=(8.0, 8.0 * height / width + 0.9), layout="constrained")
    ax = fig.add_subplot()
    ax.imshow(image)
    ax.set_axis_off()
    if title:
        ax.set_title(title, fontsize=10)
    names = ["brush path (planned)", "cube's path"]
    if scene is not None and any(o.moving for o in scene):
        names.append("moving obstacle's track")
    handles = [
        Line2D([], [], linestyle="none", marker="o", color=RENDER_TRACES[n], label=n) for n in names
    ]
    handles.append(Line2D([], [], linestyle="none", marker="s", color=CUBE.rgba, label="cube"))
    handles.append(Line2D([], [], linestyle="none", marker="s", color="0.25", label="dustpan"))
    for label, rgba in (mujoco_class_colors(scene) if scene is not None else {}).items():
        handles.append(Line2D([], [], linestyle="none", marker="s", color=rgba, label=label))
    fig.legend(
        handles=handles,
        loc="outside lower center",
        ncols=min(len(handles), 6),
        fontsize=8,
        frameon=False,
    )
    return fig
