"""Smoke tests for lfdkit.app.plot's emulation figures: scene, reward contours, panels, grid."""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest
from matplotlib.colors import to_rgb
from matplotlib.contour import ContourSet
from matplotlib.figure import Figure

from lfdkit.app.plot import (
    CLASS_COLORS,
    EXTRA_CLASS_COLORS,
    PLAN_COLORS,
    draw_reward,
    draw_scene,
    emulation_figure,
    emulation_grid,
)
from lfdkit.emulate import Reward, plan_path
from lfdkit.model.scene import Obstacle, Scene

matplotlib.use("Agg")


def _nominal(n=60):
    t = np.linspace(0.0, 1.0, n)
    return np.column_stack((t, 0.15 * np.sin(np.pi * t)))


@pytest.fixture(scope="module")
def setting():
    nominal = _nominal()
    reward = Reward(10.0, {"cup": [300.0, 300.0], "marker": [800.0, 150.0]})
    scene = Scene((Obstacle("cup", [0.35, 0.17], 0.03), Obstacle("marker", [0.7, 0.1], 0.0)))
    plan = plan_path(reward, nominal, scene)
    mpc = plan_path(reward, nominal, scene, horizon=8)
    demos = [plan.points + np.array([0.0, dy]) for dy in (-0.01, 0.0, 0.01)]
    return reward, nominal, scene, plan, mpc, demos


def _legend_labels(fig):
    assert len(fig.legends) == 1
    return [t.get_text() for t in fig.legends[0].get_texts()]


def _contours(ax):
    return [c for c in ax.collections if isinstance(c, ContourSet)]


# ----------------------------------------------------------------- draw_scene
def test_draw_scene_2d_one_legend_entry_per_class():
    scene = Scene(
        (
            Obstacle("cup", [0.0, 0.0], 0.05),
            Obstacle("cup", [1.0, 0.0], 0.05),
            Obstacle("marker", [0.5, 0.5], 0.0),
            Obstacle("bowl", [0.5, -0.5], 0.1),
        )
    )
    fig = Figure()
    ax = fig.add_subplot()
    draw_scene(ax, scene)
    assert len(ax.patches) == 3  # filled circles; the radius-0 marker is a line
    assert len(ax.lines) == 1
    # Each outline is its obstacle's circle: every vertex at the radius from the centre.
    for patch, obstacle in zip(ax.patches, [o for o in scene if o.radius > 0], strict=True):
        distance = np.linalg.norm(patch.get_xy() - obstacle.position, axis=1)
        np.testing.assert_allclose(distance, obstacle.radius)
    _, labels = ax.get_legend_handles_labels()
    assert sorted(labels) == ["bowl", "cup", "marker"]
    cup, _, bowl = ax.patches
    assert cup.get_facecolor()[:3] == pytest.approx(to_rgb(CLASS_COLORS["cup"]))
    assert bowl.get_facecolor()[:3] == pytest.approx(to_rgb(EXTRA_CLASS_COLORS[0]))
    assert ax.lines[0].get_color() == CLASS_COLORS["marker"]
    # The patches set the data limits.
    ax.autoscale_view()
    assert ax.get_xlim()[0] <= -0.05 and ax.get_ylim()[0] <= -0.6


def test_draw_scene_colour_override_and_empty_scene():
    fig = Figure()
    ax = fig.add_subplot()
    draw_scene(ax, Scene((Obstacle("cup", [0.0, 0.0], 0.05),)), colors={"cup": "#000000"})
    assert ax.patches[0].get_facecolor()[:3] == pytest.approx((0.0, 0.0, 0.0))
    draw_scene(ax, Scene())
    assert len(ax.patches) == 1


def test_draw_scene_3d_spheres():
    scene = Scene(
        (
            Obstacle("cup", [0.0, 0.0, 0.0], 0.05),
            Obstacle("cup", [1.0, 0.0, 0.0], 0.05),
            Obstacle("marker", [0.5, 0.5, 0.5], 0.0),
        )
    )
    fig = Figure()
    ax = fig.add_subplot(projection="3d")
    draw_scene(ax, scene)
    assert len(ax.collections) == 2  # one sphere per obstacle with a radius
    assert len(ax.lines) == 2  # centres, one line per class
    assert sorted(ax.get_legend_handles_labels()[1]) == ["cup", "marker"]


# ----------------------------------------------------------------- draw_reward
def test_draw_reward_contours_cover_nominal_and_obstacles(setting):
    reward, nominal, scene, *_ = setting
    fig = Figure()
    ax = fig.add_subplot()
    cs = draw_reward(ax, reward, nominal, scene, resolution=50, levels=12, margin=0.1)
    assert isinstance(cs, ContourSet)
    assert _contours(ax) == [cs]
    assert len(cs.levels) == 13
    # The reward is highest (0) on the nominal; the colour scale goes up to it.
    assert -0.05 < cs.levels[-1] <= 0.0
    assert cs.extend == "neither"  # the whole range fits the scale
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    pad = 0.1 * 1.0  # margin × larger side (x: 0 … 1)
    assert (x0, x1) == pytest.approx((-pad, 1.0 + pad))
    assert y0 == pytest.approx(0.0 - pad) and y1 == pytest.approx(0.2 + pad)
    fig.colorbar(cs, ax=ax)
    # Far from the nominal the nominal term dwarfs the obstacles: the colour scale
    # stops one unit below the lowest obstacle centre and the rest is "extend".
    wide = draw_reward(Figure().add_subplot(), reward, nominal, scene, resolution=30, margin=1.0)
    at_centres = reward.value(scene.positions, nominal, scene).min()
    assert wide.levels[0] == pytest.approx(at_centres - 1.0)
    assert wide.extend == "min"


def test_draw_reward_explicit_extent_and_vmin(setting):
    reward, nominal, scene, *_ = setting
    fig = Figure()
    ax = fig.add_subplot()
    cs = draw_reward(ax, reward, nominal, scene, resolution=20, extent=(0, 1, -1, 1), vmin=-50.0)
    assert ax.get_xlim() == pytest.approx((0, 1)) and ax.get_ylim() == pytest.approx((-1, 1))
    assert cs.levels[0] == pytest.approx(-50.0)
    assert cs.extend == "neither"


def test_draw_reward_bad_inputs(setting):
    reward, nominal, scene, *_ = setting
    ax = Figure().add_subplot()
    nominal3 = np.column_stack((nominal, nominal[:, 0]))
    with pytest.raises(ValueError, match="nominal: draw_reward draws 2-D rewards only"):
        draw_reward(ax, reward, nominal3, scene)
    with pytest.raises(ValueError, match="resolution"):
        draw_reward(ax, reward, nominal, scene, resolution=1)
    with pytest.raises(ValueError, match="margin"):
        draw_reward(ax, reward, nominal, scene, margin=-0.1)
    with pytest.raises(ValueError, match="levels"):
        draw_reward(ax, reward, nominal, scene, levels=0)
    with pytest.raises(ValueError, match="extent"):
        draw_reward(ax, reward, nominal, scene, extent=(1, 0, 0, 1))
    with pytest.raises(ValueError, match="never learned"):
        draw_reward(ax, reward, nominal, Scene((Obstacle("bowl", [0.5, 0.0]),)))


# ----------------------------------------------------------------- emulation_figure
def test_emulation_figure_2d(setting, tmp_path):
    reward, nominal, scene, plan, mpc, demos = setting
    fig = emulation_figure(
        reward,
        nominal,
        scene,
        demos=demos,
        plans={"full horizon": plan.points, "MPC H=8": mpc},  # a Plan is accepted too
        title="synthetic",
    )
    out = tmp_path / "emulation.png"
    fig.savefig(out, dpi=60)
    assert out.stat().st_size > 10_000
    (ax,) = fig.axes
    assert ax.get_title() == "synthetic"
    assert ax.get_xlabel() == "x [m]" and ax.get_ylabel() == "y [m]"
    assert ax.get_aspect() == 1.0
    assert len(_contours(ax)) == 1
    assert len(ax.patches) == 1  # the cup; the radius-0 marker is a line
    # demos + nominal + 2 plans + the marker
    assert len(ax.lines) == len(demos) + 1 + 2 + 1
    plan_lines = [line for line in ax.lines if line.get_label() in ("full horizon", "MPC H=8")]
    assert [line.get_color() for line in plan_lines] == list(PLAN_COLORS[:2])
    np.testing.assert_allclose(plan_lines[1].get_xydata(), mpc.points)
    nominal_line = next(line for line in ax.lines if line.get_label() == "nominal")
    assert nominal_line.get_linestyle() == "--"
    (cax,) = ax.child_axes  # the colour bar
    assert cax.get_ylabel() == "reward"
    assert sorted(_legend_labels(fig)) == sorted(
        ["cup", "marker", "demonstrations", "nominal", "full horizon", "MPC H=8"]
    )


def test_emulation_figure_minimal_and_units(setting, tmp_path):
    reward, nominal, scene, *_ = setting
    fig = emulation_figure(reward, nominal, scene, units="mm")
    fig.savefig(tmp_path / "minimal.png", dpi=40)
    (ax,) = fig.axes
    assert ax.get_xlabel() == "x [mm]"
    assert sorted(_legend_labels(fig)) == ["cup", "marker", "nominal"]


def test_emulation_figure_3d(tmp_path):
    t = np.linspace(0.0, 1.0, 40)
    nominal = np.column_stack((t, 0.2 * t, 0.1 * np.sin(np.pi * t)))
    reward = Reward(10.0, {"cup": [300.0, 300.0, 300.0]})
    scene = Scene((Obstacle("cup", [0.5, 0.12, 0.13], 0.03),))
    plan = plan_path(reward, nominal, scene, horizon=8)
    fig = emulation_figure(
        reward, nominal, scene, demos=[plan.points], plans={"plan": plan}, units="mm"
    )
    fig.savefig(tmp_path / "emulation3d.png", dpi=40)
    (ax,) = fig.axes
    assert ax.name == "3d"
    assert not _contours(ax)
    assert ax.get_zlabel() == "z [mm]"
    assert len(ax.collections) == 1  # the sphere
    assert len(ax.lines) == 1 + 1 + 1 + 1  # centre marker, demo, nominal, plan
    # Equal scale: the box's sides in proportion to the limits' spans.
    spans = np.array([np.ptp(lim) for lim in (ax.get_xlim(), ax.get_ylim(), ax.get_zlim())])
    ratio = np.asarray(ax.get_box_aspect()) / spans
    assert ratio == pytest.approx([ratio[0]] * 3)
    assert sorted(_legend_labels(fig)) == ["cup", "demonstrations", "nominal", "plan"]


def test_emulation_figure_bad_inputs(setting):
    reward, nominal, scene, *_ = setting
    with pytest.raises(ValueError, match=r"demos\[0\]"):
        emulation_figure(reward, nominal, scene, demos=[np.zeros((5, 3))])
    with pytest.raises(ValueError, match=r"plans\['bad'\]"):
        emulation_figure(reward, nominal, scene, plans={"bad": np.zeros(4)})
    with pytest.raises(ValueError, match="nominal"):
        emulation_figure(reward, np.zeros((5, 4)), scene)
    with pytest.raises(ValueError, match="scene"):
        emulation_figure(reward, nominal, Scene((Obstacle("cup", [0.0, 0.0, 0.0]),)))


# ----------------------------------------------------------------- emulation_grid
def test_emulation_grid(setting, tmp_path):
    reward, nominal, scene, plan, mpc, demos = setting
    cluttered = Scene(
        (
            Obstacle("cup", [0.3, 0.12], 0.02),
            Obstacle("cup", [0.5, 0.2], 0.02),
            Obstacle("marker", [0.6, 0.1], 0.0),
            Obstacle("cup", [0.8, 0.05], 0.02),
        )
    )
    other = plan_path(reward, nominal, cluttered, horizon=8)
    t = np.linspace(0.0, 1.0, 30)
    nominal3 = np.column_stack((t, t, np.zeros_like(t)))
    reward3 = Reward(5.0, {"cup": [100.0, 100.0, 100.0]})
    panels = [
        {"reward": reward, "nominal": nominal, "scene": scene, "demos": demos, "title": "train"},
        {
            "reward": reward,
            "nominal": nominal,
            "scene": cluttered,
            "plans": {"MPC": other, "full": plan.points},
            "title": "cluttered",
        },
        {"reward": reward, "nominal": nominal, "scene": scene, "plans": {"MPC": mpc}},
        {"reward": reward3, "nominal": nominal3, "scene": Scene(), "plans": {"other": nominal3}},
    ]
    fig = emulation_grid(panels, ncols=3, title="transfer")
    fig.savefig(tmp_path / "grid.png", dpi=40)
    assert len(fig.axes) == 4
    assert fig.axes[0].get_subplotspec().get_geometry()[:2] == (2, 3)
    assert [ax.get_title() for ax in fig.axes] == ["train", "cluttered", "", ""]
    assert [len(_contours(ax)) for ax in fig.axes] == [1, 1, 1, 0]
    assert fig.axes[3].name == "3d"
    assert fig.get_suptitle() == "transfer"
    labels = _legend_labels(fig)
    assert len(labels) == len(set(labels))  # every label once
    assert set(labels) == {"cup", "marker", "demonstrations", "nominal", "MPC", "full", "other"}

    # A plan name keeps its colour across panels.
    def color_of(ax, name):
        return next(line.get_color() for line in ax.lines if line.get_label() == name)

    assert color_of(fig.axes[1], "MPC") == color_of(fig.axes[2], "MPC") == PLAN_COLORS[0]
    assert color_of(fig.axes[1], "full") == PLAN_COLORS[1]


def test_emulation_grid_single_row_and_bad_panels(setting):
    reward, nominal, scene, *_ = setting
    panel = {"reward": reward, "nominal": nominal, "scene": scene}
    fig = emulation_grid([panel, panel], ncols=3)
    assert fig.axes[0].get_subplotspec().get_geometry()[:2] == (1, 2)
    with pytest.raises(ValueError, match="panels: needs at least one"):
        emulation_grid([])
    with pytest.raises(ValueError, match=r"panels\[1\]: unknown key 'plan'"):
        emulation_grid([panel, {**panel, "plan": {}}])
    with pytest.raises(ValueError, match=r"panels\[0\]: missing key 'scene'"):
        emulation_grid([{"reward": reward, "nominal": nominal}])
    with pytest.raises(TypeError, match=r"panels\[0\]"):
        emulation_grid([reward])
    with pytest.raises(ValueError, match=r"panels\[1\]\.demos\[0\]"):
        emulation_grid([panel, {**panel, "demos": [np.zeros((4, 3))]}])
    with pytest.raises(ValueError, match="ncols"):
        emulation_grid([panel], ncols=0)


def test_plan_styles_goal_and_outlines(setting, tmp_path):
    """A reference plan drawn as a wide band under the plan drawn after it; goal and fixtures."""
    reward, nominal, scene, plan, mpc, _ = setting
    walls = np.array([[0.95, 0.05], [1.1, 0.05], [1.1, 0.2], [0.95, 0.2]])
    styles = {"reference": {"linewidth": 6.0, "alpha": 0.4}}
    panel = {
        "reward": reward,
        "nominal": nominal,
        "scene": scene,
        "plans": {"reference": plan.points, "MPC": mpc},
        "goal": nominal[-1],
        "outlines": {"dustpan": walls},
    }
    fig = emulation_grid([panel, panel], ncols=1, plan_styles=styles, panel_width=8.0)
    fig.savefig(tmp_path / "styled.png", dpi=40)
    assert fig.get_size_inches()[0] == pytest.approx(8.0)
    ax = fig.axes[0]
    lines = {line.get_label(): line for line in ax.lines}
    assert lines["reference"].get_linewidth() == 6.0 and lines["reference"].get_alpha() == 0.4
    assert lines["MPC"].get_linewidth() == 1.8
    # The later plan is drawn over the band.
    assert lines["MPC"].get_zorder() >= lines["reference"].get_zorder()
    np.testing.assert_allclose(lines["goal"].get_xydata(), nominal[-1:])
    np.testing.assert_allclose(lines["dustpan"].get_xydata(), walls)
    # The reward is drawn over the outline too: the contours cover it.
    x0, x1 = ax.get_xlim()
    assert x0 <= walls[:, 0].min() and x1 >= walls[:, 0].max()
    assert set(_legend_labels(fig)) == {
        "cup",
        "marker",
        "nominal",
        "reference",
        "MPC",
        "goal",
        "dustpan",
    }
    with pytest.raises(ValueError, match=r"panels\[1\]\.goal"):
        emulation_grid([panel, {**panel, "goal": [1.0, 2.0, 3.0]}])
    with pytest.raises(ValueError, match="panel_width"):
        emulation_grid([panel], panel_width=0.0)


def test_demonstrations_are_drawn_over_the_plans(setting):
    reward, nominal, scene, plan, _, demos = setting
    fig = emulation_figure(reward, nominal, scene, demos=demos, plans={"plan": plan})
    (ax,) = fig.axes
    lines = {line.get_label(): line for line in ax.lines}
    assert lines["demonstrations"].get_zorder() > lines["plan"].get_zorder()
