"""The figure of a task-frame skill's plan: its path, its frames and the demonstrations.

``lfdkit plot SKILL --frame NAME=POSE ...`` draws it (:func:`task_frame_figure`):
each task frame as its two (2-D) or three (3-D) axes at its origin, with its
name; the plan from its start (a dot) to its end; and, with ``--demos``, the
demonstrations with their own frames faintly, so that what the skill carried
from them to the new poses is visible. Equal aspect, lengths in the skill's unit.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

__all__ = ["task_frame_figure"]

#: Axis colours of a frame: x, y, z.
_AXIS_COLOURS = ("tab:red", "tab:green", "tab:blue")


def task_frame_figure(
    plan: np.ndarray,
    frames: Mapping[str, Any],
    demos: Sequence[tuple[np.ndarray, Mapping[str, Any]]] = (),
    *,
    orientations: np.ndarray | None = None,
    units: str = "m",
    title: str | None = None,
):
    """A figure of ``plan`` (n, d) among its task ``frames`` (name → TaskFrame).

    Parameters
    ----------
    plan : ndarray, shape (n, d), d 2 or 3
        The planned path, in ``units``.
    frames : mapping of str to TaskFrame
        The frames it was planned for.
    demos : sequence of (ndarray (m, d), mapping of str to TaskFrame)
        Demonstrations with their own frames, drawn faintly (optional).
    orientations : ndarray, shape (n, 4), optional
        The plan's tool orientations (unit quaternions ``[x, y, z, w]``): the
        tool's x axis is drawn at every tenth point (in 2-D, its projection on
        the plane).
    units : str
        Unit of the lengths, for the axes' labels.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
        Not registered with pyplot (save it with ``fig.savefig``).
    """
    from matplotlib.figure import Figure

    plan = np.asarray(plan, dtype=np.float64)
    d = plan.shape[1]
    everything = [plan, *(np.asarray(points) for points, _ in demos)]
    extent = float(np.ptp(np.vstack(everything), axis=0).max()) or 1.0
    arrow = 0.08 * extent
    # A Figure of its own, no pyplot state: headless, and a user's backend left alone.
    fig = Figure(figsize=(7.0, 6.0), layout="constrained")
    ax = fig.add_subplot(projection="3d" if d == 3 else None)

    def draw_frame(name: str | None, frame: Any, alpha: float) -> None:
        origin = np.asarray(frame.origin, dtype=np.float64)
        for axis in range(d):
            tip = origin + arrow * np.asarray(frame.matrix)[:, axis]
            ax.plot(*np.c_[origin, tip], color=_AXIS_COLOURS[axis], lw=2.0, alpha=alpha)
        if name is not None:
            ax.text(*(origin + 0.3 * arrow), name, fontsize=9)

    for j, (points, own) in enumerate(demos):
        points = np.asarray(points, dtype=np.float64)
        label = "demonstrations (their frames faint)" if j == 0 else None
        ax.plot(*points.T, color="0.6", lw=1.0, label=label)
        for frame in own.values():
            draw_frame(None, frame, 0.25)
    ax.plot(*plan.T, color="tab:orange", lw=2.2, label="plan")
    if orientations is not None:
        from lfdkit.core.rotations import matrix_from_quaternion

        every = slice(0, len(plan), max(1, len(plan) // 10))
        axes = matrix_from_quaternion(np.asarray(orientations)[every])[:, :d, 0]
        tips = plan[every] + 0.6 * arrow * axes
        for k, (base, tip) in enumerate(zip(plan[every], tips, strict=True)):
            label = "tool's x axis" if k == 0 else None
            ax.plot(*np.c_[base, tip], color="tab:purple", lw=1.2, label=label)
    ax.plot(*plan[0], "o", color="tab:orange", ms=5, label="plan's start")
    for name, frame in frames.items():
        draw_frame(name, frame, 1.0)
    # The frames' axes in the legend: x red, y green (z blue).
    for axis in range(d):
        ax.plot([], [], color=_AXIS_COLOURS[axis], lw=2.0, label=f"frame {'xyz'[axis]} axis")
    ax.set_xlabel(f"x ({units})")
    ax.set_ylabel(f"y ({units})")
    if d == 3:
        ax.set_zlabel(f"z ({units})")
        lows = np.vstack(everything).min(axis=0)
        highs = np.vstack(everything).max(axis=0)
        ax.set_box_aspect(np.maximum(highs - lows, 1e-3 * extent))
    else:
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    ax.set_title(title or "task-frame skill: the plan in its frames")
    return fig
