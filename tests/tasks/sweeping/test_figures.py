"""Tests for lfdkit.tasks.sweeping.figures: top views of simulated sweeps."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from lfdkit.app.plot import PLAN_COLORS
from lfdkit.model.scene import Scene
from lfdkit.tasks.sweeping.figures import sweep_figure
from lfdkit.tasks.sweeping.scenarios import Dustpan, obstacle
from lfdkit.tasks.sweeping.sim import RENDER_TRACES, SweepResult


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
    # The render's key is the top view's: its brush path in the first run's colour.
    assert RENDER_TRACES["brush path (planned)"] == PLAN_COLORS[0]
    assert colours["cube's path"] == RENDER_TRACES["cube's path"]
    # The dustpan's outline: the floor's corners, the opening at x = 0.3.
    outline = next(line for line in ax.get_lines() if line.get_label() == "dustpan")
    np.testing.assert_allclose(outline.get_xdata(), [0.3, 0.42, 0.42, 0.3], atol=1e-12)


def test_sweep_figure_draws_the_part_of_a_wall_it_shows():
    from lfdkit.model.half_space import HalfSpace

    wall = HalfSpace("wall", [0.0, 0.6], 0.0, [0.0, -1.0])  # beyond the sweep, facing it
    fig = sweep_figure(Dustpan((0.3, 0.45), 0.0), Scene((wall,)), {"learned": fake_run(True)})
    (ax,) = fig.axes
    (part,) = [p.get_xy() for p in ax.patches if p.get_label() == "wall"]
    assert part[:, 1].min() == np.float64(0.6)  # from its surface outwards
    assert part[:, 0].min() <= -0.3 and part[:, 0].max() >= 0.42  # under all that is drawn


def _figures() -> dict[str, tuple[Figure, set[str]]]:
    """Each figure lfdkit writes for a sweep, with the legend entries it must have."""
    from lfdkit.app.plot import comparison_figure, mean_path_figure, retargeting_figure
    from lfdkit.mimic import MeanPath
    from lfdkit.tasks.sweeping.figures import render_figure

    t = np.linspace(0.0, 1.0, 40)
    curve = np.column_stack([0.6 * t, 0.2 * np.sin(np.pi * t), 0.05 + 0.1 * t])
    demos3 = [curve + np.array([0.0, dy, 0.0]) for dy in (-0.01, 0.0, 0.012)]
    demos2 = [d[:, :2] for d in demos3]
    pan = Dustpan((0.3, 0.45), 0.0)
    scene = Scene((obstacle("cup", [0.0, 0.55]), obstacle("marker", [0.1, 0.35])))
    image = np.full((72, 96, 3), 0.5)
    return {
        "comparison 3-D": (
            comparison_figure(demos3, {"Mean-Path": curve}, nominal=curve),
            {"demonstrations", "ground truth", "Mean-Path"},
        ),
        "retargeting 3-D": (
            retargeting_figure(demos3, curve, t, [(t, curve + [0.0, 0.0, 0.05] * t[:, None])]),
            {"demonstrations", "generalized path", "DMP → B\u2032"},
        ),
        "mean path": (
            mean_path_figure(demos2, MeanPath().fit(demos2)),
            {"demonstrations", "Mean-Path", "e3/n"},
        ),
        "sweep top view": (
            sweep_figure(pan, scene, {"learned skill": fake_run(True)}),
            {"dustpan", "cup", "marker", "learned skill (ok)", "cube's path", "cube at rest"},
        ),
        "render": (
            render_figure(image, scene),
            {"brush path (planned)", "cube's path", "cube", "dustpan", "cup", "marker"},
        ),
    }


def test_every_figure_keys_what_it_draws_outside_the_data_and_labels_its_axes():
    """Issue 31: a legend lists every labelled line, sits clear of the axes; axes are named."""
    import matplotlib.pyplot as plt

    for name, (fig, expected) in _figures().items():
        try:
            fig.draw_without_rendering()
            legends = [*fig.legends, *(a.get_legend() for a in fig.axes if a.get_legend())]
            assert len(legends) == 1, name
            (legend,) = legends
            keyed = {text.get_text() for text in legend.get_texts()}
            assert expected <= keyed, (name, expected - keyed)
            box = legend.get_window_extent()
            for ax in fig.axes:
                drawn = {label for label in ax.get_legend_handles_labels()[1]}
                assert drawn <= keyed, (name, drawn - keyed)  # every method drawn is keyed
                assert not box.overlaps(ax.get_window_extent()), name  # outside the data
                if ax.axison:
                    # A panel over a shared x axis hides its x ticks; the one below names it.
                    x_ticked = any(t.get_visible() and t.get_text() for t in ax.get_xticklabels())
                    assert ax.get_xlabel() or not x_ticked, name
                    assert ax.get_ylabel(), name
                    if ax.name == "3d":
                        assert ax.get_zlabel(), name
        finally:
            plt.close(fig)
