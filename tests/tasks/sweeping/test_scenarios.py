"""Tests for lfdkit.tasks.sweeping.scenarios: the one description of the scene, and its scenarios.

Every number of the sweeping scene is read from the description; the cup and
marker radii are the synthetic demonstrator's. The dustpan's frame and the
cube's placement are checked against their documented geometry, the scenario
generators against theirs (dustpan moved within its bounds and facing the
start, a cup and a marker near the straight line at the stated fractions of
the way).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from lfdkit.datasets.emulation import SWEEP_GOAL, SWEEP_START, sweeping
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.tasks.sweeping.scenarios import (
    BRUSH,
    CUBE,
    DEFAULT_OBSTACLE_CLASS,
    GOAL_DEPTH,
    NEW_GOAL,
    NOMINAL_DUSTPAN,
    OBSTACLE_CLASSES,
    UNSEEN_DESIGNS,
    Dustpan,
    SweepingTask,
    SweepScenario,
    obstacle,
    obstacle_class,
    random_scenarios,
    unseen_scenes,
)

PAN = Dustpan((0.3, 0.45), 0.0)


def straight_path(start=(-0.3, 0.45), end=None, n: int = 50) -> np.ndarray:
    """A straight table path from ``start`` to ``end`` (default: the dustpan's goal)."""
    end = PAN.goal() if end is None else np.asarray(end, dtype=np.float64)
    return np.linspace(start, end, n)


def cup(x: float, y: float) -> Scene:
    return Scene((Obstacle("cup", np.array([x, y]), 0.03),))


def positions(scenarios: list[SweepScenario]) -> np.ndarray:
    return np.array(
        [np.concatenate([s.dustpan.position, s.scene.positions.ravel()]) for s in scenarios]
    )


# ------------------------------------------------------------------ the classes
def test_obstacle_classes_are_the_demonstrators_with_a_height_mass_and_colour():
    assert set(OBSTACLE_CLASSES) == {"cup", "marker"}
    assert OBSTACLE_CLASSES["cup"].radius == 0.03
    assert OBSTACLE_CLASSES["marker"].radius == 0.01
    # The demonstrator's scenes carry the same radii.
    data = sweeping(seed=0, n_cup=1, n_marker=1, n_free=0, plan_points=20)
    for scene in data.scenes:
        assert scene.radii[0] == OBSTACLE_CLASSES[scene.labels[0]].radius
    for kind in OBSTACLE_CLASSES.values():
        assert kind.height > 0 and kind.mass > 0 and len(kind.rgba) == 4
    with pytest.raises(TypeError):
        OBSTACLE_CLASSES["bowl"] = DEFAULT_OBSTACLE_CLASS  # read-only


def test_an_unknown_class_stands_as_a_cup_and_radius_zero_takes_the_class_radius():
    assert obstacle_class("bowl") is DEFAULT_OBSTACLE_CLASS is OBSTACLE_CLASSES["cup"]
    assert obstacle_class("marker") is OBSTACLE_CLASSES["marker"]
    marker = OBSTACLE_CLASSES["marker"]
    assert marker.cylinder_radius(Obstacle("marker", np.zeros(2))) == 0.01
    assert marker.cylinder_radius(Obstacle("marker", np.zeros(2), 0.015)) == 0.015
    made = obstacle("marker", [0.1, 0.4])
    assert (made.label, made.radius) == ("marker", 0.01)
    np.testing.assert_array_equal(made.position, [0.1, 0.4])


def test_the_nominal_dustpan_is_the_one_the_demonstrators_sweep_ends_in():
    pan = Dustpan(NOMINAL_DUSTPAN, 0.0)
    np.testing.assert_array_equal(pan.goal(), SWEEP_GOAL)
    assert pan.contains(pan.goal())
    assert not pan.contains(SWEEP_START)


def test_for_sweep_faces_the_start_and_ends_at_the_goal():
    start = np.array([-0.4, 0.45])
    pan = Dustpan.for_sweep(start, NEW_GOAL)
    np.testing.assert_allclose(pan.goal(), NEW_GOAL, atol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(NEW_GOAL - pan.position), GOAL_DEPTH, atol=1e-15)
    local = pan.local(start)
    assert local[0] < 0
    assert local[1] == pytest.approx(0.0, abs=1e-12)


def test_unseen_scenes_place_the_designs_along_the_sweep():
    start = np.array([-0.4, 0.45])
    scenes = unseen_scenes(start)
    assert len(scenes) == len(UNSEEN_DESIGNS)
    line = NEW_GOAL - start
    normal = np.array([-line[1], line[0]]) / np.linalg.norm(line)
    for scene, design in zip(scenes, UNSEEN_DESIGNS, strict=True):
        assert scene.labels == tuple(label for label, _, _ in design)
        for o, (label, u, across) in zip(scene, design, strict=True):
            assert o.radius == OBSTACLE_CLASSES[label].radius
            np.testing.assert_allclose(o.position, start + u * line + across * normal, atol=1e-15)


# ------------------------------------------------------------------ dustpan
def test_dustpan_frame_with_yaw_zero():
    pan = Dustpan((0.3, 0.45), 0.0)
    inside = np.array([0.35, 0.45])
    np.testing.assert_allclose(pan.local(inside), [0.05, 0.0], atol=1e-15)
    assert pan.contains(inside)
    assert pan.contains([0.3 + pan.depth - 1e-9, 0.45 + 0.5 * pan.width - 1e-9])  # a corner
    assert not pan.contains([0.3 + pan.depth + 0.01, 0.45])  # beyond the back wall
    assert not pan.contains([0.35, 0.45 + 0.5 * pan.width + 0.01])  # beside the side wall
    assert not pan.contains([0.29, 0.45])  # in front of the opening
    np.testing.assert_allclose(pan.goal(), [0.32, 0.45], atol=1e-15)
    np.testing.assert_allclose(pan.goal(0.05), [0.35, 0.45], atol=1e-15)
    # Batches of points keep their leading shape.
    local = pan.local(np.array([[0.3, 0.45], [0.3, 0.5], [0.2, 0.45]]))
    np.testing.assert_allclose(local, [[0.0, 0.0], [0.0, 0.05], [-0.1, 0.0]], atol=1e-15)


def test_dustpan_frame_with_yaw_quarter_turn():
    pan = Dustpan((0.1, 0.5), math.pi / 2)  # opening faces -y, the cube arrives along +y
    np.testing.assert_allclose(pan.axes, [[0.0, 1.0], [-1.0, 0.0]], atol=1e-15)
    inside = np.array([0.1, 0.55])
    np.testing.assert_allclose(pan.local(inside), [0.05, 0.0], atol=1e-15)
    assert pan.contains(inside)
    assert not pan.contains([0.1, 0.5 + pan.depth + 0.01])  # beyond the back wall
    beside = np.array([0.1 + 0.5 * pan.width + 0.01, 0.55])
    np.testing.assert_allclose(pan.local(beside), [0.05, -0.09], atol=1e-15)
    assert not pan.contains(beside)
    assert not pan.contains([0.1, 0.49])  # in front of the opening
    np.testing.assert_allclose(pan.goal(), [0.1, 0.52], atol=1e-15)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"position": (np.nan, 0.45), "yaw": 0.0}, "position"),
        ({"position": (0.3, 0.45, 0.0), "yaw": 0.0}, "position"),
        ({"position": (0.3, 0.45), "yaw": np.inf}, "yaw"),
        ({"position": (0.3, 0.45), "yaw": 0.0, "depth": 0.0}, "depth"),
        ({"position": (0.3, 0.45), "yaw": 0.0, "depth": -0.1}, "depth"),
        ({"position": (0.3, 0.45), "yaw": 0.0, "width": 0.0}, "width"),
    ],
)
def test_dustpan_rejects_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        Dustpan(**kwargs)


# ------------------------------------------------------------------ task
def test_for_path_places_cube_ahead_of_the_brush():
    ahead = 0.5 * BRUSH.thickness + 0.5 * CUBE.size + 0.004
    direction = np.array([3.0, 4.0]) / 5.0
    path = np.array([0.0, 0.4]) + np.linspace(0.0, 0.3, 20)[:, None] * direction
    task = SweepingTask.for_path(path, PAN)
    np.testing.assert_allclose(task.cube, path[0] + ahead * direction, atol=1e-12)
    assert task.cube_yaw == pytest.approx(math.atan2(4.0, 3.0), abs=1e-12)
    assert len(task.scene) == 0
    assert task.dustpan is PAN


def test_for_path_going_in_minus_x_puts_cube_at_smaller_x():
    ahead = 0.5 * BRUSH.thickness + 0.5 * CUBE.size + 0.004
    path = straight_path(start=(0.2, 0.45), end=(-0.2, 0.45))
    task = SweepingTask.for_path(path, PAN, cup(0.0, 0.6))
    assert task.cube[0] < path[0, 0]
    np.testing.assert_allclose(task.cube, [0.2 - ahead, 0.45], atol=1e-12)
    assert abs(task.cube_yaw) == pytest.approx(math.pi, abs=1e-12)
    assert len(task.scene) == 1


def test_for_path_uses_the_first_two_centimetres_not_the_first_segment():
    # A rollout that creeps 0.1 mm sideways before heading along +x.
    path = np.array([[0.0, 0.45], [0.0, 0.4501], [0.1, 0.4501], [0.3, 0.4501]])
    task = SweepingTask.for_path(path, PAN)
    assert abs(task.cube_yaw) < 0.01  # the first segment alone would give π/2
    assert task.cube[0] > 0.02


def test_sweeping_task_rejects_bad_input():
    scene_3d = Scene((Obstacle("cup", np.array([0.0, 0.5, 0.0])),))
    with pytest.raises(ValueError, match="scene"):
        SweepingTask.for_path(straight_path(), PAN, scene_3d)
    with pytest.raises(ValueError, match="cube"):
        SweepingTask(np.array([np.nan, 0.45]), PAN)
    with pytest.raises(ValueError, match="cube"):
        SweepingTask(np.array([0.0, 0.45, 0.0]), PAN)
    with pytest.raises(TypeError, match="dustpan"):
        SweepingTask(np.array([0.0, 0.45]), (0.3, 0.45))
    with pytest.raises(ValueError, match="path"):
        SweepingTask.for_path([[0.0, 0.45], [np.nan, 0.45]], PAN)


# ------------------------------------------------------------------ scenarios
def test_random_scenarios_are_reproducible():
    first, again = random_scenarios(5, seed=3), random_scenarios(5, seed=3)
    np.testing.assert_array_equal(positions(first), positions(again))
    assert [o.label for s in first for o in s.scene] == [o.label for s in again for o in s.scene]
    other = random_scenarios(5, seed=4)
    assert not np.any(np.all(np.isclose(positions(first), positions(other)), axis=1))
    # A Generator seeded alike gives the same scenes.
    generated = random_scenarios(5, seed=np.random.default_rng(3))
    np.testing.assert_array_equal(positions(first), positions(generated))


def test_random_scenarios_put_a_cup_and_a_marker_near_the_line():
    lateral = 0.03
    scenarios = random_scenarios(5, seed=3, lateral=lateral)
    assert len(scenarios) == 5
    for s in scenarios:
        np.testing.assert_array_equal(s.start, [-0.4, 0.45])
        np.testing.assert_array_equal(s.goal, s.dustpan.goal())
        assert sorted(o.label for o in s.scene) == ["cup", "marker"]
        radius = {o.label: o.radius for o in s.scene}
        assert radius == {"cup": 0.03, "marker": 0.01}
        line = s.goal - s.start
        normal = np.array([-line[1], line[0]]) / np.linalg.norm(line)
        fractions = [(o.position - s.start) @ line / (line @ line) for o in s.scene]
        offsets = [abs((o.position - s.start) @ normal) for o in s.scene]
        assert 0.3 <= fractions[0] <= 0.45
        assert 0.55 <= fractions[1] <= 0.7
        assert max(offsets) <= lateral


def test_random_scenarios_dustpan_faces_the_start_within_its_shift():
    for s in random_scenarios(5, seed=3):
        shift = s.dustpan.position - NOMINAL_DUSTPAN
        assert -0.12 <= shift[0] <= 0.0
        assert abs(shift[1]) <= 0.08
        towards = s.dustpan.position - s.start
        assert s.dustpan.yaw == pytest.approx(math.atan2(towards[1], towards[0]), abs=1e-12)
        # The start lies straight in front of the opening, on the centre line.
        local = s.dustpan.local(s.start)
        assert local[0] < 0
        assert local[1] == pytest.approx(0.0, abs=1e-12)


def test_random_scenarios_rejects_bad_count():
    with pytest.raises(ValueError, match=r"^n: "):
        random_scenarios(0)
