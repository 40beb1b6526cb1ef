"""Fixtures of the moving-obstacle tests: the example skill (learned once), its sweep timing."""

from __future__ import annotations

import pytest

from lfdkit.emulate import Corridor
from lfdkit.tasks.sweeping.moving import SWEEP_DURATION
from tests.conftest import example_skill_copy


@pytest.fixture(scope="session")
def skill(example_skill_once):
    return example_skill_copy(example_skill_once)


@pytest.fixture(scope="session")
def setting(skill):
    """The nominal sweep (K, 2) and when the brush is at each of its points (K,)."""
    times = skill.point_times(SWEEP_DURATION)
    nominal = Corridor.from_path(skill.nominal(), int(skill.n_points)).points
    return nominal, times
