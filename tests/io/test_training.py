"""Training files read into one Demo record per demonstration, split clean / around obstacles."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.io import save_demos
from lfdkit.io.scenes import save_scenes
from lfdkit.io.training import read_training_data
from lfdkit.model.demos import Demo
from lfdkit.model.scene import Obstacle, Scene


def _files(tmp_path, *, orientations=True):
    rng = np.random.default_rng(5)
    demos = [np.cumsum(rng.uniform(0.1, 1.0, size=(n, 2)), axis=0) for n in (7, 9, 8, 6)]
    times = [np.linspace(0.0, 0.5 * (j + 1), len(d)) for j, d in enumerate(demos)]
    quats = [
        np.tile([0.0, 0.0, np.sin(0.1 * j), np.cos(0.1 * j)], (len(d), 1))
        for j, d in enumerate(demos)
    ]
    ids = ["a", 7, "cup-1", "b"]
    demos_path = save_demos(
        tmp_path / "demos.csv",
        demos,
        times=times,
        ids=ids,
        orientations=quats if orientations else None,
    )
    cup = Scene((Obstacle("cup", [1.0, 2.0], radius=0.25),))
    scenes_path = save_scenes(tmp_path / "scenes.json", {"cup-1": cup, "b": Scene(())})
    return demos_path, scenes_path, demos, times, quats, ids, cup


def test_each_demonstration_is_one_record_with_what_was_recorded_with_it(tmp_path):
    demos_path, scenes_path, demos, times, quats, _, cup = _files(tmp_path)
    data = read_training_data(demos_path, scenes_path)
    assert all(isinstance(d, Demo) for d in data.clean + data.around_obstacles)
    # An empty scene is a clean demonstration; the file's order is kept in each part.
    assert [d.id for d in data.clean] == ["a", 7, "b"]
    assert [d.id for d in data.around_obstacles] == ["cup-1"]
    for record, j in zip(data.clean, (0, 1, 3), strict=True):
        np.testing.assert_array_equal(record.points, demos[j])
        np.testing.assert_array_equal(record.times, times[j])
        np.testing.assert_allclose(record.orientations, quats[j], atol=1e-15)
    obstacle = data.around_obstacles[0]
    np.testing.assert_array_equal(obstacle.points, demos[2])
    assert obstacle.scene.labels == cup.labels
    np.testing.assert_array_equal(obstacle.scene.positions, cup.positions)


def test_the_field_views_list_the_records_in_step(tmp_path):
    demos_path, scenes_path, *_ = _files(tmp_path)
    data = read_training_data(demos_path, scenes_path)
    assert data.free_ids == [d.id for d in data.clean]
    assert all(v is d.points for v, d in zip(data.free_demos, data.clean, strict=True))
    assert all(v is d.times for v, d in zip(data.free_times, data.clean, strict=True))
    assert all(v is d.orientations for v, d in zip(data.free_orientations, data.clean, strict=True))
    assert data.obstacle_ids == ["cup-1"]
    assert data.scenes == [data.around_obstacles[0].scene]
    assert data.obstacle_demos[0] is data.around_obstacles[0].points
    (tmp_path / "plain").mkdir()
    without = read_training_data(_files(tmp_path / "plain", orientations=False)[0])
    assert without.free_orientations == [None] * 4 and not without.around_obstacles


def test_a_scene_for_an_unknown_demonstration_is_refused_naming_it(tmp_path):
    demos_path, *_ = _files(tmp_path)
    stray = save_scenes(tmp_path / "stray.json", {"zz": Scene(())})
    with pytest.raises(ValueError, match=r"stray\.json: demo 'zz' is not in .*demos\.csv"):
        read_training_data(demos_path, stray)
