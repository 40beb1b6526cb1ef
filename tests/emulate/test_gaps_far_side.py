"""Obstacles passed on their far side from the nominal, and the balls that block it (issue 26).

Along the x-axis from (0, 0) to (1, 0): a box of radius 5 cm centred 7 cm below
the path stands 2 cm clear of it; a path 16 cm below the path passes it on its
far side, one 3 cm above on the nominal's side. A box centred 4 cm above the
path touches it: either side is the nominal's, so it is never listed.
"""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.emulate.gaps import SIDE_BLOCKER, far_side_obstacles, nominal_side_blockers
from lfdkit.model.scene import Obstacle, Scene

X = np.linspace(0.0, 1.0, 101)
LINE = np.column_stack([X, np.zeros_like(X)])
SCENE = Scene(
    (Obstacle("box", [0.2, 0.04], radius=0.05), Obstacle("box", [0.5, -0.07], radius=0.05))
)


def _path(offset: float) -> np.ndarray:
    """The line bent to ``offset`` (units) at x = 0.5, zero at x = 0.1 and 0.9."""
    bump = np.clip(np.sin(np.pi * (X - 0.1) / 0.8), 0.0, None) * (X > 0.1) * (X < 0.9)
    return np.column_stack([X, offset * bump])


def test_a_clear_obstacle_passed_on_its_far_side_is_found() -> None:
    assert far_side_obstacles(_path(-0.16), LINE, SCENE) == [1]
    # On the nominal's side (above it), or the nominal itself: none.
    assert far_side_obstacles(_path(0.03), LINE, SCENE) == []
    assert far_side_obstacles(LINE, LINE, SCENE) == []
    # Walked the other way: the same sides.
    assert far_side_obstacles(_path(-0.16)[::-1], LINE[::-1], SCENE) == [1]
    # The touching box is never listed, whichever side the path takes.
    assert far_side_obstacles(_path(0.16), LINE, SCENE) == []
    # Outside 2-D: none.
    line3 = np.column_stack([LINE, np.zeros(len(X))])
    scene3 = Scene((Obstacle("box", [0.5, -0.07, 0.0], radius=0.05),))
    assert far_side_obstacles(line3 + np.array([0.0, -0.16, 0.0]), line3, scene3) == []


def test_nominal_side_blockers_block_the_far_side_only() -> None:
    ends = LINE[[0, -1]]
    balls = nominal_side_blockers(LINE, SCENE, [1], ends)
    assert balls and all(b.label == SIDE_BLOCKER for b in balls)
    # Below the box (its far side): the first touches its surface at (0.5, -0.12).
    first = balls[0]
    assert first.position[0] == pytest.approx(0.5)
    assert first.position[1] + first.radius == pytest.approx(-0.12)
    assert all(b.position[1] < -0.12 for b in balls)
    # A box above the nominal is blocked above.
    above = Scene((Obstacle("box", [0.5, 0.07], radius=0.05),))
    assert all(b.position[1] > 0.12 for b in nominal_side_blockers(LINE, above, [0], ends))
    assert nominal_side_blockers(LINE, SCENE, [], ends) == []
