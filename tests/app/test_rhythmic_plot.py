"""The rhythmic figure draws the demonstration, the learned cycle and the rollout it is given."""

from __future__ import annotations

import matplotlib
import numpy as np

from lfdkit.app.rhythmic_plot import rhythmic_figure
from lfdkit.core.rotations import exp
from lfdkit.imitate import QuaternionRhythmicDMP, RhythmicDMP

matplotlib.use("Agg")


def test_the_figure_shows_the_cycle_the_rollout_and_the_rotation(tmp_path) -> None:
    t = np.linspace(0.0, 3.0, 301)
    u = 2 * np.pi * t
    demo = np.c_[10.0 * np.sin(u), 3.0 * np.sin(2 * u)]  # centimetres
    tilt = exp(np.outer(0.2 * np.sin(u), [1.0, 0.0, 0.0]))
    dmp = RhythmicDMP(period=1.0).fit(demo, t)
    turning = QuaternionRhythmicDMP(period=1.0).fit(tilt, t)
    run, turn = dmp.rollout(2.0, 0.01), turning.rollout(2.0, 0.01)
    fig = rhythmic_figure(
        dmp,
        demo,
        t,
        run,
        orientation=turning,
        demo_orientations=tilt,
        orientation_run=turn,
        units="cm",
    )
    fig.savefig(tmp_path / "rhythm.png", dpi=40)
    plane, along, speed, rotation = fig.axes
    assert along.get_ylabel() == "position [cm]"
    assert plane.get_aspect() == 1.0 and plane.get_xlabel() == "x [cm]"
    labels = {text.get_text() for text in plane.get_legend().get_texts()}
    assert labels == {"demonstration", "rollout", "learned cycle", "centre"}
    drawn = {line.get_label(): line for line in plane.get_lines()}
    np.testing.assert_array_equal(np.c_[drawn["rollout"].get_data()], run.positions)
    # The cycle drawn is the learned one: the demonstration's figure-eight.
    cycle = np.c_[drawn["learned cycle"].get_data()]
    np.testing.assert_allclose(np.abs(cycle).max(axis=0), [10.0, 3.0], rtol=1e-3)
    assert speed.get_ylabel() == "speed [cm/s]"
    assert rotation.get_ylabel() == "rotation from centre [rad]"
    # Rotation about x swings ±0.4 rad (twice the half-angle 0.2).
    swing = max(np.abs(line.get_ydata()).max() for line in rotation.get_lines())
    assert abs(swing - 0.4) < 0.01
