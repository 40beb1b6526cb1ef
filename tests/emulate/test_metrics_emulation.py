"""The emulation measures of lfdkit.emulate.metrics: MSE_R, Pr, clearance, parameter errors."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.emulate import Reward, plan_path
from lfdkit.emulate.metrics import (
    clearance,
    collisions,
    improvement,
    mse_paths,
    parameter_errors,
)
from lfdkit.model.scene import Obstacle, Scene


def hline(x0, x1, y, n):
    """Horizontal segment from (x0, y) to (x1, y) with n points."""
    return np.column_stack((np.linspace(x0, x1, n), np.full(n, float(y))))


# ----------------------------------------------------------------- mse_paths
@pytest.mark.parametrize("h", [0.0, 0.05, 1.0, -3.0])
def test_mse_parallel_lines_is_h_squared(h):
    # Different samplings of the same line: resampling makes the points pair up.
    assert mse_paths([hline(0, 2, 0, 7)], [hline(0, 2, h, 31)]) == pytest.approx(h * h, abs=1e-12)


def test_mse_mean_over_paths_and_points():
    hs = [0.1, 0.2, 0.4]
    demos = [hline(0, 1, h, 20) for h in hs]
    paths = [hline(0, 1, 0, 5) for _ in hs]
    expected = np.mean(np.square(hs))
    assert mse_paths(paths, demos, n_points=50) == pytest.approx(expected)
    # One (m, q) array is the replayed path for every demonstration (MSE_Mp).
    assert mse_paths(hline(0, 1, 0, 5), demos) == pytest.approx(expected)
    # A 3-D stack of demonstrations works as a list.
    assert mse_paths(np.stack(paths), np.stack(demos)) == pytest.approx(expected)


def test_mse_identical_paths_is_zero():
    t = np.linspace(0, 1, 40)
    path = np.column_stack((t, np.sin(3 * t), t**2))
    assert mse_paths([path, path], [path, path.copy()]) == pytest.approx(0.0, abs=1e-24)


def test_mse_pairs_points_in_order_of_travel():
    # The same segment travelled backwards: point i meets point n − 1 − i.
    n = 11
    x = np.linspace(0.0, 1.0, n)
    expected = np.mean((1.0 - 2.0 * x) ** 2)
    assert mse_paths([hline(1, 0, 0, 3)], [hline(0, 1, 0, 3)], n_points=n) == pytest.approx(
        expected
    )


def test_mse_3d_parallel_lines():
    path = np.column_stack((np.linspace(0, 1, 9), np.zeros(9), np.zeros(9)))
    demo = path + np.array([0.0, 0.3, 0.4])
    assert mse_paths([path], [demo]) == pytest.approx(0.25)


def test_mse_bad_inputs_name_the_argument():
    demos = [hline(0, 1, 0, 5), hline(0, 1, 1, 5)]
    with pytest.raises(ValueError, match="paths: expected one path per demonstration"):
        mse_paths([hline(0, 1, 0, 5)], demos)
    with pytest.raises(ValueError, match="n_points"):
        mse_paths(demos, demos, n_points=1)
    with pytest.raises(ValueError, match=r"paths\[0\]"):
        mse_paths([np.zeros((3, 2)), hline(0, 1, 0, 5)], demos)
    with pytest.raises(ValueError, match=r"demos\[1\]"):
        mse_paths(demos, [demos[0], np.ones((4, 2))])
    with pytest.raises(ValueError, match="paths"):
        mse_paths([np.zeros((5, 3)), np.zeros((5, 3))], demos)
    with pytest.raises(ValueError, match=r"demos\[0\]"):
        mse_paths(demos, [np.full((5, 2), np.nan), demos[1]])


# ----------------------------------------------------------------- improvement
@pytest.mark.parametrize(
    ("replay", "reproduced", "expected"), [(4, 1, 75.0), (4, 4, 0.0), (4, 0, 100.0), (2, 3, -50.0)]
)
def test_improvement(replay, reproduced, expected):
    assert improvement(replay, reproduced) == pytest.approx(expected)


def test_improvement_bad_inputs():
    with pytest.raises(ValueError, match="mse_replay"):
        improvement(0.0, 1.0)
    with pytest.raises(ValueError, match="mse_reproduced"):
        improvement(1.0, -0.1)
    with pytest.raises(ValueError, match="mse_replay"):
        improvement(np.nan, 1.0)


def test_improvement_of_a_perfect_plan_is_100():
    nominal = hline(0, 1, 0, 50)
    reward = Reward(10.0, {"cup": [300.0, 300.0]})
    plan = plan_path(reward, nominal, Scene((Obstacle("cup", [0.5, 0.03], 0.02),)))
    demos = [plan.points]
    mse_replay = mse_paths(nominal, demos)
    assert mse_replay > 0
    assert improvement(mse_replay, mse_paths([plan.points], demos)) == pytest.approx(100.0)


# ----------------------------------------------------------------- clearance
def test_clearance_straight_segment():
    scene = Scene((Obstacle("cup", [0.0, 0.0], 0.04),))
    # Vertices 1 away; the segment itself passes at 0.1 from the centre.
    path = np.array([[-1.0, 0.1], [1.0, 0.1]])
    np.testing.assert_allclose(clearance(path, scene), [0.06])
    assert collisions(path, scene) == 0


def test_clearance_catches_a_segment_through_the_obstacle():
    scene = Scene((Obstacle("cup", [0.0, 0.0], 0.04),))
    path = np.array([[-1.0, 0.0], [1.0, 0.0]])  # both vertices far outside
    np.testing.assert_allclose(clearance(path, scene), [-0.04])
    assert collisions(path, scene) == 1


def test_clearance_uses_the_nearest_end_beyond_the_segment():
    scene = Scene((Obstacle("cup", [0.0, 0.0], 0.1),))
    path = np.array([[-1.0, 0.0], [-0.5, 0.0]])
    np.testing.assert_allclose(clearance(path, scene), [0.4])


def test_clearance_3d_and_single_point():
    scene = Scene((Obstacle("cup", [0.0, 0.0, 0.0], 0.04), Obstacle("cup", [3.0, 0.0, 1.0], 0.5)))
    path = np.array([[-1.0, 0.0, 0.1], [1.0, 0.0, 0.1]])
    np.testing.assert_allclose(clearance(path, scene), [0.06, np.hypot(2.0, 0.9) - 0.5])
    np.testing.assert_allclose(clearance([[0.0, 0.3, 0.4]], scene)[0], 0.46)


def test_clearance_repeated_vertices_and_empty_scene():
    scene = Scene((Obstacle("cup", [0.0, 0.0], 0.0),))
    path = np.array([[1.0, 1.0], [1.0, 1.0], [1.0, -1.0]])  # a zero-length segment first
    np.testing.assert_allclose(clearance(path, scene), [1.0])
    assert clearance(path, Scene()).shape == (0,)
    assert collisions(path, Scene()) == 0


def test_collisions_count():
    scene = Scene(
        (
            Obstacle("cup", [0.2, 0.0], 0.05),  # crossed
            Obstacle("cup", [0.5, 0.03], 0.05),  # crossed off-centre
            Obstacle("marker", [0.8, 0.05], 0.05),  # touched exactly: not a collision
            Obstacle("marker", [0.8, 0.5], 0.05),  # far
        )
    )
    path = hline(0.0, 1.0, 0.0, 3)  # vertices at 0, 0.5, 1
    c = clearance(path, scene)
    np.testing.assert_allclose(c, [-0.05, -0.02, 0.0, 0.45], atol=1e-15)
    assert collisions(path, scene) == 2


def test_clearance_of_a_planned_path_is_positive():
    nominal = hline(0, 1, 0, 50)
    scene = Scene((Obstacle("cup", [0.5, 0.02], 0.03),))
    assert collisions(nominal, scene) == 1
    plan = plan_path(Reward(10.0, {"cup": [300.0, 300.0]}), nominal, scene)
    assert clearance(plan.points, scene)[0] > 0
    assert collisions(plan.points, scene) == 0


def test_clearance_bad_inputs():
    scene = Scene((Obstacle("cup", [0.0, 0.0], 0.04),))
    with pytest.raises(ValueError, match="scene"):
        clearance(np.zeros((3, 3)), scene)
    with pytest.raises(ValueError, match="path"):
        clearance([[0.0, np.inf], [1.0, 1.0]], scene)
    with pytest.raises(ValueError, match="path"):
        clearance(np.zeros(4), scene)
    with pytest.raises(TypeError, match="scene"):
        clearance(np.zeros((3, 2)), [[0.0, 0.0]])
    with pytest.raises(TypeError, match="scene"):
        collisions(np.zeros((3, 2)), None)


# ----------------------------------------------------------------- parameter errors
def test_parameter_errors_exact():
    true = Reward(10.0, {"cup": [100.0, 200.0], "marker": [50.0, 400.0]})
    fitted = Reward(12.0, {"marker": [45.0, 400.0], "cup": [110.0, 150.0], "bowl": [1.0, 1.0]})
    errors = parameter_errors(fitted, true)
    assert list(errors) == ["Q", "cup[0]", "cup[1]", "marker[0]", "marker[1]"]
    expected = [0.2, 0.1, 0.25, 0.1, 0.0]
    np.testing.assert_allclose(list(errors.values()), expected, rtol=1e-12, atol=1e-15)
    assert all(isinstance(v, float) for v in errors.values())
    assert parameter_errors(true, true) == dict.fromkeys(errors, 0.0)


def test_parameter_errors_full_matrix_uses_the_diagonal():
    true = Reward(1.0, {"cup": [[4.0, 1.0], [1.0, 3.0]]})
    fitted = Reward(1.5, {"cup": [2.0, 6.0]})
    assert parameter_errors(fitted, true) == pytest.approx({"Q": 0.5, "cup[0]": 0.5, "cup[1]": 1.0})


def test_parameter_errors_3d():
    true = Reward(20.0, {"cup": [15.4, 1000.0, 50.0]})
    fitted = Reward.from_theta(true.theta + np.log(1.1), ["cup"], 3)
    errors = parameter_errors(fitted, true)
    assert list(errors) == ["Q", "cup[0]", "cup[1]", "cup[2]"]
    np.testing.assert_allclose(list(errors.values()), 0.1, rtol=1e-10)


def test_parameter_errors_bad_inputs():
    true = Reward(10.0, {"cup": [100.0, 200.0], "marker": [50.0, 400.0]})
    with pytest.raises(ValueError, match="fitted: has no class 'marker'"):
        parameter_errors(Reward(10.0, {"cup": [100.0, 200.0]}), true)
    with pytest.raises(ValueError, match="fitted: class 'cup'"):
        parameter_errors(Reward(10.0, {"cup": [1, 2, 3], "marker": [1, 2, 3]}), true)
    with pytest.raises(TypeError, match="fitted"):
        parameter_errors({"Q": 10.0}, true)
    with pytest.raises(TypeError, match="true"):
        parameter_errors(true, 10.0)
