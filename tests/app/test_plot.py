"""Tests for the mimic and imitate figures of lfdkit.app.plot: Mean-Path, convergence, DMP."""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

from lfdkit.app.plot import mean_path_figure, retargeting_figure
from lfdkit.mimic import MeanPath

matplotlib.use("Agg")


def _sweeps(n=5, seed=0):
    """Thin, nearly straight sweeps: a few millimetres of spread over 0.8 m."""
    rng = np.random.default_rng(seed)
    x = np.linspace(-0.4, 0.4, 90)
    return [
        np.column_stack((x, 0.45 + 0.002 * np.sin(3 * x + rng.uniform(0, 6)))) for _ in range(n)
    ]


@pytest.mark.parametrize(("layout", "width"), [("row", 15.0), ("stacked", 9.6)])
def test_mean_path_figure_layouts(layout, width, tmp_path):
    demos = _sweeps()
    fig = mean_path_figure(demos, MeanPath().fit(demos), nominal=demos[0], layout=layout)
    fig.savefig(tmp_path / "mean_path.png", dpi=40)
    assert fig.get_size_inches()[0] == pytest.approx(width)
    paths, distance, change, update = fig.axes[:4]
    # A thin task is not drawn to scale (its spread would vanish), and says so.
    assert paths.get_aspect() != 1.0
    assert paths.get_title().endswith("(axes not to scale)")
    assert distance.get_title() == "Distance-Space"
    assert change.get_title() == "Mean-Path convergence"
    assert change.get_yscale() == update.get_yscale() == "log"
    assert update.get_xlabel() == "iteration"
    assert "[m]" in update.get_ylabel()


def test_convergence_has_no_offset_and_whole_iterations(tmp_path):
    demos = _sweeps()
    mean_path = MeanPath().fit(demos)
    fig = mean_path_figure(demos, mean_path, layout="stacked")
    fig.savefig(tmp_path / "mean_path.png", dpi=40)  # tick labels are made at drawing
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            assert axis.get_offset_text().get_text() == "", ax.get_title()
    change, update = fig.axes[2:4]
    ticks = [t for t in update.get_xticks() if update.get_xlim()[0] <= t <= update.get_xlim()[1]]
    assert ticks == [round(t) for t in ticks]
    # The relative change starts at iteration 1; the update is shown from iteration 0.
    (line,) = [line for line in change.lines if line.get_label() == "relative change of e1"] or [
        None
    ]
    if mean_path.n_iter_:
        assert line.get_xdata()[0] == 1
    (updates,) = update.lines
    assert len(updates.get_xdata()) == mean_path.n_iter_ + 1


def test_mean_path_figure_bad_layout():
    demos = _sweeps()
    with pytest.raises(ValueError, match="layout"):
        mean_path_figure(demos, MeanPath().fit(demos), layout="grid")


def test_retargeting_figure_of_a_thin_task_is_not_to_scale(tmp_path):
    demos = _sweeps()
    path = demos[0]
    goal = path.copy()
    goal[:, 1] += np.linspace(0.0, 0.05, len(goal))
    fig = retargeting_figure(
        demos, path, np.linspace(0, 1, len(path)), [(np.linspace(0, 1, 90), goal)]
    )
    fig.savefig(tmp_path / "dmp.png", dpi=40)
    ax = fig.axes[0]
    assert ax.get_title() == "(axes not to scale)"
    assert ax.yaxis.get_offset_text().get_text() == ""


def test_the_mimic_figure_names_every_line_it_draws_in_its_legend() -> None:
    """Issue 31: GMR's mean line was drawn but not in the legend."""
    import matplotlib.pyplot as plt

    from lfdkit.mimic import GMR

    x = np.linspace(0.0, 1.0, 40)
    demos = [np.c_[x, 0.1 * np.sin(3 * x) + dy] for dy in (-0.01, 0.0, 0.012)]
    fig = mean_path_figure(
        demos, MeanPath().fit(demos), gmr=GMR(n_components=3, random_state=0).fit(demos)
    )
    try:
        labels = fig.axes[0].get_legend_handles_labels()[1]
        assert {"GMR", "GMR ±2 sd", "Mean-Path"} <= set(labels)
        assert fig.axes[0].get_xlabel() and fig.axes[0].get_ylabel()
    finally:
        plt.close(fig)
