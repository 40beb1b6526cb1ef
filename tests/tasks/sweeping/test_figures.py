"""Tests for lfdkit.tasks.sweeping.figures: top views of simulated sweeps."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from lfdkit.app.plot import PLAN_COLORS
from lfdkit.model.scene import Scene
from lfdkit.tasks.sweeping.figures import sweep_figure
from lfdkit.tasks.sweeping.scenarios import Dustpan, obstacle
from lfdkit.tasks.sweeping.sim import SweepResult


def fake_run(success: bool) -> SweepResult:
    """A sweep along y = 0.45 whose cube came to rest at x = 0.35."""
    x = np.linspace(-0.3, 0.32, 20)
    return SweepResult(
        success=success,
        cube_in_dustpan=success,
        touched=[],
        cube_final=np.array([0.35, 0.45]),
        tool_trace=np.column_stack([x, np.full(20, 0.45), np.full(20, 0.192)]),
        cube_trace=np.column_stack([x + 0.03, np.full(20, 0.45)]),
    )


def test_sweep_figure_draws_the_dustpan_obstacles_and_each_run():
    pan = Dustpan((0.3, 0.45), 0.0)
    scene = Scene((obstacle("cup", [0.0, 0.55]), obstacle("marker", [0.1, 0.35])))
    not_run = SweepResult(success=False, cube_in_dustpan=False, touched=[], failures=["no"])
    fig = sweep_figure(
        pan, scene, {"learned": fake_run(True), "DMP": fake_run(False), "broken": not_run}
    )
    assert isinstance(fig, Figure)
    (ax,) = fig.axes
    labels = [line.get_label() for line in ax.get_lines()]
    assert "dustpan" in labels
    assert {"learned (ok)", "DMP (failed)", "broken (not run)"} <= set(labels)
    colours = {line.get_label(): line.get_color() for line in ax.get_lines()}
    assert colours["learned (ok)"] == PLAN_COLORS[0]
    assert colours["DMP (failed)"] == PLAN_COLORS[1]
    # The dustpan's outline: the floor's corners, the opening at x = 0.3.
    outline = next(line for line in ax.get_lines() if line.get_label() == "dustpan")
    np.testing.assert_allclose(outline.get_xdata(), [0.3, 0.42, 0.42, 0.3], atol=1e-12)
