"""Tests for lfdkit.emulate.Reward: values, derivatives, parameters, errors."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.core.geometry import project_onto_polyline
from lfdkit.emulate import Reward
from lfdkit.model.scene import Obstacle, Scene


@pytest.fixture
def setting():
    x = np.linspace(0.0, 1.0, 50)
    nominal = np.column_stack([x, 0.1 * x])
    reward = Reward(
        10.0, {"cup": [2500.0, 215.0], "marker": np.array([[900.0, 100.0], [100.0, 400.0]])}
    )
    scene = Scene((Obstacle("cup", [0.4, 0.05]), Obstacle("marker", [0.7, 0.02])))
    return reward, nominal, scene


def test_value_is_zero_on_the_nominal_far_from_obstacles(setting) -> None:
    reward, nominal, _ = setting
    assert reward.value(nominal[[5, 20]], nominal, Scene()) == pytest.approx([0.0, 0.0], abs=1e-12)
    off = nominal[10] + np.array([-0.1, 1.0]) * 0.02 / np.hypot(0.1, 1.0)
    assert reward.value(off, nominal, Scene())[0] == pytest.approx(-10.0 * 0.02**2)


@pytest.mark.parametrize(
    "nominal",
    [
        np.column_stack([np.linspace(0, 1, 400), 0.05 * np.sin(np.linspace(0, 9, 400))]),
        np.array([[0.0, 0.0], [0.0, 0.0], [1.0, 1.0], [1.0, 1.0], [0.5, 0.0]]),  # repeats, a turn
        np.array([[0.3, 0.2], [0.3, 0.2]]),  # a single point, twice
        np.random.default_rng(1).uniform(-1, 1, (30, 3)),  # 3-D
    ],
)
def test_value_uses_the_distance_to_the_nominal_polyline(nominal) -> None:
    """value() finds the distance a segment at a time: the projection's, to rounding."""
    q = nominal.shape[1]
    reward = Reward(7.0, {"cup": [300.0] * q})
    scene = Scene((Obstacle("cup", [0.5] * q),))
    points = np.random.default_rng(0).uniform(-1.5, 1.5, (5000, q))
    distance = project_onto_polyline(points, nominal)[2]
    expected = -7.0 * distance**2 - reward.obstacle_cost(points, scene)
    np.testing.assert_allclose(reward.value(points, nominal, scene), expected, rtol=0, atol=1e-12)


def test_obstacle_term_is_a_unit_gaussian(setting) -> None:
    reward, _, scene = setting
    assert reward.obstacle_cost([0.4, 0.05], scene)[0] == pytest.approx(1.0, abs=1e-6)
    point = np.array([0.4 + 0.01, 0.05])
    expected = np.exp(-2500.0 * 0.01**2) + np.exp(
        -np.array([-0.29, 0.03])
        @ np.array([[900.0, 100.0], [100.0, 400.0]])
        @ np.array([-0.29, 0.03])
    )
    assert reward.obstacle_cost(point, scene)[0] == pytest.approx(expected)


def test_gradient_and_hessian_match_finite_differences(setting) -> None:
    reward, nominal, scene = setting
    rng = np.random.default_rng(0)
    points = np.column_stack([rng.uniform(0.2, 0.8, 6), rng.uniform(-0.05, 0.15, 6)])
    gradient = reward.gradient(points, nominal, scene)
    hessian = reward.hessian(points, nominal, scene)
    eps = 1e-6
    for i in range(2):
        step = np.zeros(2)
        step[i] = eps
        fd = (
            reward.value(points + step, nominal, scene)
            - reward.value(points - step, nominal, scene)
        ) / (2 * eps)
        np.testing.assert_allclose(gradient[:, i], fd, rtol=1e-5, atol=1e-7)
        fd_h = (
            reward.gradient(points + step, nominal, scene)
            - reward.gradient(points - step, nominal, scene)
        ) / (2 * eps)
        np.testing.assert_allclose(hessian[:, :, i], fd_h, rtol=1e-4, atol=1e-4)


def test_theta_round_trip_and_combination() -> None:
    reward = Reward(20.0, {"cup": [15.4, 1000.0], "marker": [20.08, 880.0]})
    again = Reward.from_theta(reward.theta, reward.classes, 2)
    assert again.nominal_weight == pytest.approx(20.0)
    np.testing.assert_allclose(again.precisions["marker"], np.diag([20.08, 880.0]))
    both = Reward(20.0, {"cup": [15.4, 1000.0]}).combined(Reward(5.0, {"marker": [20.08, 880.0]}))
    assert both.classes == ("cup", "marker") and both.nominal_weight == 20.0
    with pytest.raises(ValueError, match="theta: expected 5 values"):
        Reward.from_theta(np.zeros(3), ("cup", "marker"), 2)
    with pytest.raises(ValueError, match="theta: contains NaN"):
        Reward.from_theta([np.nan, 0, 0], ("cup",), 2)


@pytest.mark.parametrize(
    "precisions, match",
    [
        ({"cup": [1.0, -1.0]}, "positive"),
        ({"cup": [[1.0, 2.0], [2.0, 1.0]]}, "positive definite"),
        ({"cup": [[1.0, 0.5], [0.0, 1.0]]}, "symmetric"),
        ({"cup": [1.0, np.inf]}, "NaN or infinite"),
        ({"cup": [1.0, 1.0], "marker": [1.0, 1.0, 1.0]}, "different dimensions"),
        ({"cup": [1.0, 0.0]}, "positive"),
        ({"cup": [1.0]}, "expected shape"),
        ({"cup": [1.0, 1.0, 1.0, 1.0]}, "expected shape"),
        ({"cup": [2.0, 3.0], "marker": [1.0, 1.0, 1.0]}, "different dimensions"),
    ],
)
def test_bad_precisions_are_refused(precisions, match) -> None:
    with pytest.raises(ValueError, match=match):
        Reward(1.0, precisions)


def test_a_diagonal_given_as_its_entries_is_the_matrix() -> None:
    # Entries skip the symmetry and Cholesky checks (positive and finite): the same
    # matrices as given whole, and the same reward from θ.
    entries = Reward(2.0, {"cup": [4.0, 9.0], "box": [1.0, 2.0]})
    whole = Reward(2.0, {"cup": np.diag([4.0, 9.0]), "box": np.diag([1.0, 2.0])})
    for label in ("cup", "box"):
        np.testing.assert_array_equal(entries.precisions[label], whole.precisions[label])
    again = Reward.from_theta(entries.theta, entries.classes, 2)
    np.testing.assert_array_equal(again.theta, whole.theta)


def test_unknown_class_and_bad_weight_are_refused(setting) -> None:
    reward, nominal, _ = setting
    with pytest.raises(ValueError, match=r"class 'vase' was never learned.*adopt"):
        reward.value(nominal[:2], nominal, Scene((Obstacle("vase", [0.5, 0.0]),)))
    with pytest.raises(ValueError, match="nominal_weight"):
        Reward(0.0, {})
    with pytest.raises(ValueError, match="position"):
        Obstacle("cup", [np.nan, 0.0])
    with pytest.raises(ValueError, match="mixed 2-D and 3-D"):
        Scene((Obstacle("cup", [0.0, 0.0]), Obstacle("cup", [0.0, 0.0, 0.0])))


def _turn(points, angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.asarray(points, dtype=float) @ np.array([[c, s], [-s, c]])


def test_a_response_shown_one_way_is_judged_by_its_width_across_a_path_running_another() -> None:
    from lfdkit.emulate.reward import shown_directions, unshown_widths
    from lfdkit.model.half_space import HalfSpace

    x = np.linspace(0.0, 1.0, 101)
    along_x = np.column_stack([x, 0.0 * x])
    cup = Obstacle("cup", [0.5, 0.01], radius=0.02)
    # Shown running +x and running back (-x): one direction, a Gaussian being symmetric.
    shown = shown_directions([Scene((cup,)), Scene((cup,))], [along_x, along_x[::-1]], np.ones(2))
    assert shown == {"cup": [0.0]}
    long = Reward(20.0, {"cup": [100.0, 4000.0]})  # long along x: 6.3 times as wide as across

    def judged(angle: float, reward: Reward = long, obstacle=cup) -> list:
        turned = Obstacle(obstacle.label, _turn(obstacle.position, angle), radius=0.02)
        return unshown_widths(reward, Scene((turned,)), _turn(along_x, angle), shown)

    assert judged(0.0) == [] and judged(np.pi) == []
    # Turned by 90 degrees: across the path is the response's long axis now.
    ((i, degrees, across, along),) = judged(np.pi / 2)
    assert (i, degrees) == (0, pytest.approx(90.0))
    assert across == pytest.approx(np.sqrt(40.0)) and along == pytest.approx(np.sqrt(1 / 40))
    # Across (n' P n)^-1/2 against the shown (0, 1)' P (0, 1): a quarter wider at 40 degrees.
    for turn, widened in ((30.0, None), (37.0, None), (45.0, np.sqrt(4000.0 / 2050.0))):
        got = judged(np.radians(turn))
        assert (got[0][2] if got else None) == (pytest.approx(widened) if widened else None)
    # A round response is the same in any frame; a far obstacle is not reacted to.
    assert judged(np.pi / 2, Reward(20.0, {"cup": [1000.0, 1000.0]})) == []
    far = Obstacle("cup", [0.5, 0.5], radius=0.02)  # 3 widest widths: 3 / sqrt(100) = 0.3
    assert judged(np.pi / 2, obstacle=far) == []
    # A class never shown, and a half-space (no centre to pass), are not judged.
    assert unshown_widths(long, Scene((Obstacle("pan", [0.0, 0.5]),)), along_x, shown) == []
    table = HalfSpace("cup", [0.0, -0.05], 0.0, [0.0, 1.0])
    assert unshown_widths(long, Scene((table,)), _turn(along_x, np.pi / 2), shown) == []


def test_the_path_frame_keeps_a_response_as_shown_in_the_nearest_direction() -> None:
    from lfdkit.emulate.reward import in_path_frame

    x = np.linspace(0.0, 1.0, 101)
    long = Reward(20.0, {"cup": [100.0, 4000.0]}, swerve={"cup": [0.5, 2.0]})
    learned = long.precision_of(Scene((Obstacle("cup", [0.0, 0.0]),)))[0]

    def framed(angle: float, shown) -> np.ndarray:
        path = _turn(np.column_stack([x, 0.0 * x]), angle)
        scene = Scene((Obstacle("cup", _turn([0.5, 0.01], angle), radius=0.02),))
        reward, relabelled = in_path_frame(long, scene, path, [1.0, 0.0], shown)
        assert reward.along_path and relabelled.labels == ("cup#0",)
        assert list(reward.swerve) == ["cup#0"]
        np.testing.assert_array_equal(reward.swerve["cup#0"], [0.5, 2.0])  # along the path
        return reward.precision_of(relabelled)[0]

    def in_axes_of(angle: float) -> np.ndarray:
        """The learned (world) precision in the axes of a path running at ``angle``."""
        c, s = np.cos(angle), np.sin(angle)
        axes = np.array([[c, -s], [s, c]])
        return axes.T @ learned @ axes

    # Learned along +x and passed so: the path's axes are the room's.
    np.testing.assert_allclose(framed(0.0, None), learned, atol=1e-9)
    np.testing.assert_allclose(framed(np.pi / 3, {"cup": [np.pi / 3]}), in_axes_of(np.pi / 3))
    # Shown along x and along y: running at 80 or 100 degrees, the response as shown along
    # y (not along x); at 170 degrees, as shown along x (mod pi). Whatever the exact turn.
    shown = {"cup": [0.0, np.pi / 2]}
    for angle, nearest in ((80.0, 90.0), (100.0, 90.0), (170.0, 0.0)):
        got = framed(np.radians(angle), shown)
        np.testing.assert_allclose(got, in_axes_of(np.radians(nearest)), rtol=1e-9, atol=1e-6)
    # A class the mapping lacks: as learned, along the axis (+x).
    np.testing.assert_allclose(framed(np.radians(80.0), {"pan": [np.pi / 2]}), learned, atol=1e-9)
