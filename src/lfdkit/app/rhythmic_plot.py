"""The rhythmic figure: a periodic demonstration, its learned cycle, and a run of it.

Left, the path in the plane of its first two coordinates (equal aspect: a
stroke's shape is a length): the demonstration (grey), the learned cycle
(black, dashed) and a rollout (blue; with a ramp it spirals out of the centre
and back). Right, each coordinate against time, and, for a rhythm with
orientation, the rotation from the centre (rotation vector components, rad)
of the demonstration and of the rollout, so that the period, the amplitude
and a smooth start and stop can be read off.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from lfdkit.core.rotations import conjugate, log, multiply
from lfdkit.imitate.rhythmic import QuaternionRhythmicDMP, RhythmicDMP
from lfdkit.model.timed_path import TimedPath

__all__ = ["rhythmic_figure"]

DEMO_COLOR = "0.6"
RUN_COLOR = "#1f77b4"
COMPONENT_STYLES = ("-", "--", ":")


def rhythmic_figure(
    dmp: RhythmicDMP,
    demo: np.ndarray | None,
    times: np.ndarray | None,
    run: TimedPath,
    *,
    orientation: QuaternionRhythmicDMP | None = None,
    demo_orientations: np.ndarray | None = None,
    orientation_run: TimedPath | None = None,
    units: str = "m",
    title: str = "",
) -> Figure:
    """Demonstration, learned cycle and a rollout; with orientation, their rotations too.

    Parameters
    ----------
    dmp : RhythmicDMP
        Fitted on ``demo``.
    demo : ndarray, shape (n, q), q >= 2, or None
        The demonstration's positions (None: the cycle and the run only).
    times : ndarray, shape (n,), or None
        Its times in seconds (None: the demonstration is drawn in the plane only).
    run : TimedPath
        A rollout of ``dmp`` (:meth:`RhythmicDMP.rollout`).
    orientation : QuaternionRhythmicDMP, optional
        Fitted on ``demo_orientations`` (n, 4); ``orientation_run`` its rollout.
    units : str
        Unit of the positions.
    title : str

    Returns
    -------
    Figure
    """
    if demo is not None:
        demo = np.asarray(demo, dtype=np.float64)
    if times is not None:
        times = np.asarray(times, dtype=np.float64) - float(times[0])
    timed = demo is not None and times is not None
    rows = 3 if orientation is not None else 2
    fig = Figure(figsize=(11.0, 2.4 * rows + 0.6), layout="constrained")
    grid = fig.add_gridspec(rows, 2, width_ratios=(1.0, 1.6))
    plane = fig.add_subplot(grid[:, 0])
    if demo is not None:
        plane.plot(demo[:, 0], demo[:, 1], color=DEMO_COLOR, lw=0.8, label="demonstration")
    cycle = dmp.cycle(np.linspace(0.0, 2.0 * np.pi, 400))
    plane.plot(*run.positions[:, :2].T, color=RUN_COLOR, lw=1.2, label="rollout")
    plane.plot(cycle[:, 0], cycle[:, 1], "k--", lw=1.4, label="learned cycle")
    plane.plot(*dmp.centre_[:2], "k+", markersize=10, label="centre")
    plane.set_xlabel(f"x [{units}]")
    plane.set_ylabel(f"y [{units}]")
    plane.set_aspect("equal", adjustable="datalim")
    plane.legend(loc="best", fontsize=8)
    plane.set_title(f"period {dmp.period_:.3g} s, {dmp.n_harmonics} harmonics")

    along = fig.add_subplot(grid[0, 1])
    for k in range(min(run.positions.shape[1], 3)):
        style = COMPONENT_STYLES[k]
        name = "xyz"[k]
        if timed:
            along.plot(times, demo[:, k], style, color=DEMO_COLOR, lw=0.8)
        along.plot(run.times, run.positions[:, k], style, color=RUN_COLOR, lw=1.0, label=name)
    along.set_ylabel(f"position [{units}]")
    heading = "rollout (demo grey)" if timed else "rollout"
    along.legend(loc="upper right", fontsize=8, ncols=3, title=heading)

    speed = fig.add_subplot(grid[1, 1], sharex=along)
    speed.plot(run.times, np.linalg.norm(run.velocities, axis=1), color=RUN_COLOR, lw=1.0)
    speed.set_ylabel(f"speed [{units}/s]")
    last = speed
    if orientation is not None and orientation_run is not None:
        turn = fig.add_subplot(grid[2, 1], sharex=along)
        shown = None
        if timed and demo_orientations is not None:
            shown = 2.0 * log(multiply(demo_orientations, conjugate(orientation.centre_)))
        for k in range(3):
            style = COMPONENT_STYLES[k]
            if shown is not None:
                turn.plot(times, shown[:, k], style, color=DEMO_COLOR, lw=0.8)
            turn.plot(
                orientation_run.times,
                orientation_run.positions[:, k],
                style,
                color=RUN_COLOR,
                lw=1.0,
                label=f"about {'xyz'[k]}",
            )
        turn.set_ylabel("rotation from centre [rad]")
        turn.legend(loc="upper right", fontsize=8, ncols=3)
        last = turn
    last.set_xlabel("time [s]")
    fig.suptitle(title or "A periodic movement: demonstration, learned cycle and a rollout")
    return fig
