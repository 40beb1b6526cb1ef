"""Fixtures of the moving-obstacle tests: the example skill (learned once), its sweep timing."""

from __future__ import annotations

import pytest

from lfdkit.emulate import Corridor
from lfdkit.skill import learn
from lfdkit.tasks.sweeping import example_files
from lfdkit.tasks.sweeping.moving import SWEEP_DURATION


@pytest.fixture(scope="session")
def skill():
    files = example_files()
    return learn(files["demos"], files["scenes"])


@pytest.fixture(scope="session")
def setting(skill):
    """The nominal sweep (K, 2) and when the brush is at each of its points (K,)."""
    times = skill.point_times(SWEEP_DURATION)
    nominal = Corridor.from_path(skill.nominal(), int(skill.n_points)).points
    return nominal, times
