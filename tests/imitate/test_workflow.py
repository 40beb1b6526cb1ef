"""The thesis's workflow (§3.4): demonstrations → generalized path → DMP → new goal."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.core.geometry import project_onto_polyline
from lfdkit.datasets import load_dataset
from lfdkit.imitate import DMP
from lfdkit.mimic import GMR, MeanPath


@pytest.fixture(scope="module")
def walking():
    return load_dataset("walking", seed=0)


def mean_distance(points: np.ndarray, polyline: np.ndarray) -> float:
    return float(np.mean(project_onto_polyline(points, polyline)[2]))


def test_mean_path_to_dmp_reproduces_the_generalized_path_and_reaches_new_goals(walking) -> None:
    path = MeanPath().fit(walking.demos).path_
    dmp = DMP(n_basis=20, scaling="spatial").fit(path, timing="minimum_jerk", duration=5.0)
    reproduction = dmp.rollout(n_steps=500).positions
    size = float(np.max(np.ptp(path, axis=0)))
    assert mean_distance(reproduction, path) < 2e-3 * size
    # As close to the demonstrations as the generalized path itself.
    for demo in walking.demos[:5]:
        assert mean_distance(demo, reproduction) < 1.05 * mean_distance(demo, path) + 1e-3 * size
    goal = path[-1] + np.array([1.5, 2.0])
    assert np.allclose(dmp.rollout(goal=goal).positions[-1], goal, atol=1e-7 * size)


def test_gmr_path_with_its_own_timing_feeds_a_dmp(walking) -> None:
    gmr = GMR(n_components=8, random_state=0).fit(walking.demos)
    phase = np.linspace(0.0, 1.0, 200)
    path = gmr.predict(phase)
    dmp = DMP(n_basis=30).fit(path, phase * 5.0)
    run = dmp.rollout(n_steps=200)
    size = float(np.max(np.ptp(path, axis=0)))
    assert mean_distance(run.positions, path) < 1e-2 * size
    assert run.times[-1] == pytest.approx(5.0)
