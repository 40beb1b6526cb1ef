"""The obstacle contract: a rod (Capsule) used unchanged by reward, planner, IOC, metrics, plots.

The round obstacle is the contract's base case; the capsule is the proof that
a new shape is one class: every layer below works with it through the
contract's methods only.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from typing import ClassVar

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.distance import cdist

from lfdkit.app.plot import draw_scene
from lfdkit.core.geometry import segment_polyline_distance
from lfdkit.emulate import IOC, Capsule, Obstacle, Reward, Scene, metrics, plan_path
from lfdkit.emulate.planner import UnsafePlanError
from lfdkit.io import load_scenes, save_scenes
from lfdkit.model.scene import OBSTACLE_SHAPES, register_shape


def dense_segment(start: np.ndarray, end: np.ndarray, n: int = 4001) -> np.ndarray:
    return start + np.linspace(0.0, 1.0, n)[:, None] * (end - start)


def dense_polyline(points: np.ndarray, n: int = 2001) -> np.ndarray:
    if len(points) == 1:
        return points
    return np.concatenate([dense_segment(a, b, n) for a, b in itertools.pairwise(points)])


coordinates = st.floats(-2.0, 2.0, allow_nan=False, allow_infinity=False)


@settings(max_examples=60, deadline=None)
@given(
    q=st.sampled_from([2, 3]),
    n=st.integers(1, 4),
    values=st.lists(coordinates, min_size=18, max_size=18),
)
def test_segment_polyline_distance_matches_dense_sampling(q: int, n: int, values) -> None:
    data = np.array(values).reshape(6, 3)[:, :q]
    start, end, polyline = data[0], data[1], data[2 : 2 + n]
    got = segment_polyline_distance(start, end, polyline)
    reference = cdist(dense_segment(start, end), dense_polyline(polyline)).min()
    # Dense sampling only over-estimates, by at most a sample spacing.
    assert got <= reference + 1e-9
    assert reference - got <= 4e-3


def test_a_round_obstacle_is_its_own_anchor_and_ball() -> None:
    cup = Obstacle("cup", [0.3, -0.2], 0.04)
    np.testing.assert_array_equal(cup.anchors(), [[0.3, -0.2]])
    centres, radii = cup.balls()
    np.testing.assert_array_equal(centres, [[0.3, -0.2]])
    np.testing.assert_array_equal(radii, [0.04])
    path = np.array([[0.0, 0.0], [1.0, 0.0]])
    assert cup.distance(path) == pytest.approx(0.2 - 0.04)
    lo, hi = cup.bounds()
    np.testing.assert_allclose(lo, [0.26, -0.24])
    np.testing.assert_allclose(hi, [0.34, -0.16])


@pytest.mark.parametrize("q", [2, 3])
def test_a_capsule_is_covered_by_its_balls_and_measured_exactly(q: int) -> None:
    rng = np.random.default_rng(q)
    start, end = rng.normal(size=(2, q))
    rod = Capsule("marker", start, 0.07, end)
    # Points inside the rod: within its radius of the axis.
    axis = dense_segment(start, end, 300)
    offsets = rng.normal(size=(300, q))
    offsets *= 0.07 * rng.uniform(0, 1, (300, 1)) / np.linalg.norm(offsets, axis=1, keepdims=True)
    inside = axis + offsets
    centres, radii = rod.balls()
    covered = (cdist(inside, centres) <= radii[None] + 1e-12).any(axis=1)
    assert covered.all()
    assert radii.max() < 1.05 * 0.07  # a tight cover: the planner does not detour much more
    # Distance to a path: the axis's distance minus the radius.
    path = rng.normal(size=(5, q))
    reference = cdist(dense_segment(start, end), dense_polyline(path)).min() - 0.07
    assert rod.distance(path) == pytest.approx(reference, abs=2e-3)
    # Anchors run along the whole axis, ends included.
    anchors = rod.anchors()
    np.testing.assert_allclose(anchors[[0, -1]], [start, end])
    assert np.diff(np.linalg.norm(anchors - start, axis=1)).max() <= rod.length / 16 + 1e-12


@pytest.mark.parametrize("q", [2, 3])
def test_a_capsules_extreme_point_is_the_farthest_of_its_dense_surface(q: int) -> None:
    # The solid sampled densely: a sphere (circle) of 4000 directions of the radius
    # about each of 4001 points of the axis. Its farthest sample along a direction is
    # the farthest axis point's plus the farthest direction's (the sum of two sets), at
    # most the sampling short of the exact answer, which lies on the surface.
    rng = np.random.default_rng(3)
    sphere = rng.normal(size=(4000, q))
    sphere /= np.linalg.norm(sphere, axis=1, keepdims=True)
    for scale in (1.0, 1e-3, 1e3):  # units of the data: m, km, mm
        start, end = rng.normal(size=q) * scale, rng.normal(size=q) * scale
        rod = Capsule("rod", start, 0.3 * scale, end)
        axis = dense_segment(start, end)
        for direction in [*rng.normal(size=(6, q)), end - start, start - end]:
            unit = direction / np.linalg.norm(direction)
            point = rod.extreme_point(direction * 7.0)  # any length: a direction
            assert rod.distance(point[None]) == pytest.approx(0.0, abs=1e-12 * scale)
            best = float(np.max(axis @ unit)) + 0.3 * scale * float(np.max(sphere @ unit))
            assert best - 1e-12 * scale <= float(point @ unit) <= best + 2e-3 * scale
    # Perpendicular to the axis both ends are as far: either is exact.
    rod = Capsule("rod", [0.0, 0.0], 0.1, [1.0, 0.0])
    np.testing.assert_allclose(rod.extreme_point([0.0, 2.0]), [0.0, 0.1])


def test_capsule_transformations_and_bad_input() -> None:
    rod = Capsule("marker", [0.1, 0.2], 0.01, [0.3, 0.2])
    twice = rod.scaled(2.0)
    np.testing.assert_allclose(
        [*twice.position, *twice.end, twice.radius], [0.2, 0.4, 0.6, 0.4, 0.02]
    )
    mirrored = Scene((rod,)).mirrored().obstacles[0]
    assert isinstance(mirrored, Capsule)
    np.testing.assert_allclose(mirrored.end, [0.3, -0.2])
    with pytest.raises(ValueError, match=r"^end: a 3-D point for a 2-D position"):
        Capsule("marker", [0.0, 0.0], 0.01, [1.0, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"^end: contains NaN"):
        Capsule("marker", [0.0, 0.0], 0.01, [np.nan, 0.0])
    with pytest.raises(ValueError, match=r"^end: expected a 2-D or 3-D point"):
        Capsule("marker", [0.0, 0.0], 0.01)


def test_reward_of_a_capsule_is_the_class_term_along_it_with_exact_derivatives() -> None:
    reward = Reward(10.0, {"marker": [400.0, 900.0]})
    rod = Capsule("marker", [0.3, -0.1], 0.01, [0.6, 0.15])
    scene = Scene((rod,))
    nominal = np.column_stack([np.linspace(0, 1, 50), np.zeros(50)])
    anchors = rod.anchors()
    points = np.array([[0.45, 0.02], [0.2, 0.3], [0.7, -0.05]])
    # The term is the class's Gaussian at every anchor, summed.
    rel = points[:, None] - anchors[None]
    expected = np.exp(-(rel**2 @ np.array([400.0, 900.0]))).sum(axis=1)
    np.testing.assert_allclose(reward.obstacle_cost(points, scene), expected)
    # Gradient and Hessian against central differences.
    h = 1e-6
    for point in points:
        gradient = reward.gradient(point[None], nominal, scene)[0]
        hessian = reward.hessian(point[None], nominal, scene)[0]
        for i in range(2):
            step = np.zeros(2)
            step[i] = h
            up = reward.value((point + step)[None], nominal, scene)[0]
            down = reward.value((point - step)[None], nominal, scene)[0]
            assert gradient[i] == pytest.approx((up - down) / (2 * h), rel=1e-5, abs=1e-6)
            g_up = reward.gradient((point + step)[None], nominal, scene)[0]
            g_down = reward.gradient((point - step)[None], nominal, scene)[0]
            np.testing.assert_allclose(
                hessian[:, i], (g_up - g_down) / (2 * h), rtol=1e-4, atol=1e-4
            )


def straight(n: int = 120) -> np.ndarray:
    x = np.linspace(0.0, 1.0, n)
    return np.column_stack([x, np.zeros(n)])


@pytest.mark.parametrize("horizon", [None, 10])
def test_the_planner_goes_round_the_end_of_a_rod_across_the_path(horizon) -> None:
    reward = Reward(5.0, {"marker": [2500.0, 2500.0]})
    # A rod across the path, sticking out 6 cm above it: the plan must pass its top end.
    rod = Capsule("marker", [0.5, -0.4], 0.01, [0.5, 0.06])
    scene = Scene((rod,))
    plan = plan_path(reward, straight(), scene, horizon=horizon, clearance=0.01)
    assert metrics.clearance(plan.points, scene)[0] >= 0.01 - 1e-9
    assert plan.points[:, 1].max() > 0.06 + 0.02 - 1e-9
    assert plan.goal_error < 1e-3
    np.testing.assert_allclose(plan.clearance, metrics.clearance(plan.points, scene) - 0.01)
    # A round obstacle at the rod's middle would be avoided by a path that crosses the rod.
    round_only = Scene((Obstacle("marker", 0.5 * (rod.position + rod.end), 0.01),))
    naive = plan_path(reward, straight(), round_only, horizon=horizon, clearance=0.01)
    assert metrics.collisions(naive.points, scene) == 1


@pytest.mark.parametrize("q", [2, 3])
def test_a_clipped_capsule_holds_every_part_of_the_rod_in_the_box(q: int) -> None:
    rng = np.random.default_rng(10 + q)
    lower, upper = np.zeros(q), np.ones(q)
    for _ in range(40):
        start, end = rng.uniform(-2.0, 3.0, (2, q))
        rod = Capsule("marker", start, 0.05, end)
        part = rod.clipped(lower, upper)
        assert isinstance(part, Capsule)
        # Independent reference: dense points of the rod's axis; those within the
        # radius of the box (where the rod can reach into it) lie on the part's axis.
        axis = dense_segment(start, end, 2001)
        near = np.all((axis >= lower - 0.05) & (axis <= upper + 0.05), axis=1)
        for point in axis[near][::50]:
            assert segment_polyline_distance(part.position, part.end, point[None]) <= 1e-9
        # The part is a piece of the rod: its ends lie on the axis.
        for point in (part.position, part.end):
            assert segment_polyline_distance(start, end, point[None]) <= 1e-9


def test_a_kilometre_rod_far_beyond_the_goal_does_not_block_the_plan() -> None:
    """A 1e6 m rod 4.6 m past the goal: covered whole, its balls were ~2 km wide."""
    reward = Reward(5.0, {"marker": [2500.0, 2500.0]})
    rod = Capsule("marker", [5.6, 0.0], 0.03, [5.6 + 1e6, 0.0])
    assert rod.balls()[1].max() > 1000.0  # why clipping is needed
    plan = plan_path(reward, straight(), Scene((rod,)), clearance=0.01)
    assert metrics.clearance(plan.points, Scene((rod,)))[0] == pytest.approx(4.6 - 0.03)
    assert plan.goal_error < 1e-3
    # Long rods along the path, 10 cm beside it, are still avoided exactly and tightly.
    beside = Capsule("marker", [-1e6, 0.1], 0.03, [1e6, 0.1])
    plan = plan_path(reward, straight(), Scene((beside,)), clearance=0.01)
    assert metrics.clearance(plan.points, Scene((beside,)))[0] >= 0.01 - 1e-9
    # One across it still blocks every plan (clipping never makes a plan unsafe).
    across = Capsule("marker", [0.5, -1e6], 0.03, [0.5, 1e6])
    with pytest.raises(UnsafePlanError):
        plan_path(reward, straight(), Scene((across,)), clearance=0.01)


def test_a_start_inside_a_rod_is_refused_with_its_name() -> None:
    reward = Reward(5.0, {"marker": [2500.0, 2500.0]})
    rod = Capsule("marker", [-0.1, -0.005], 0.02, [0.1, 0.005])
    with pytest.raises(ValueError, match=r"^start: lies inside obstacle 0 \('marker'"):
        plan_path(reward, straight(), Scene((rod,)), clearance=0.0)


def test_ioc_learns_from_demonstrations_around_rods() -> None:
    true = Reward(8.0, {"marker": [1600.0, 900.0]})
    nominal = straight(60)
    scenes, demos = [], []
    for j, (x, top) in enumerate([(0.3, 0.02), (0.45, -0.03), (0.6, 0.0), (0.7, 0.04)]):
        sign = 1.0 if j % 2 else -1.0
        rod = Capsule("marker", [x, top], 0.0, [x + 0.05, top + sign * 0.2])
        scenes.append(Scene((rod,)))
        demos.append(plan_path(true, nominal, scenes[-1], goal_approach=None).points)
    fit = IOC(n_points=60).fit(demos, scenes, nominal)
    for demo, scene in zip(demos, scenes, strict=True):
        replay = plan_path(fit.reward_, nominal, scene, goal_approach=None).points
        assert np.abs(replay - demo).max() < 0.1 * np.abs(demo[:, 1]).max()


def test_metrics_and_plots_use_the_shape() -> None:
    rod = Capsule("marker", [0.2, 0.1], 0.02, [0.8, 0.1])
    cup = Obstacle("cup", [0.5, -0.3], 0.05)
    scene = Scene((rod, cup))
    path = straight()
    np.testing.assert_allclose(metrics.clearance(path, scene), [0.08, 0.25])
    fig, ax = plt.subplots()
    draw_scene(ax, scene)
    patches = {p.get_label(): p for p in ax.patches}
    np.testing.assert_allclose(patches["marker"].get_xy(), rod.outline())
    lo, hi = patches["marker"].get_xy().min(axis=0), patches["marker"].get_xy().max(axis=0)
    np.testing.assert_allclose([*lo, *hi], [0.18, 0.08, 0.82, 0.12], atol=1e-3)
    plt.close(fig)


@pytest.mark.parametrize("suffix", [".csv", ".json"])
@pytest.mark.parametrize("q", [2, 3])
def test_scene_files_keep_every_shape_exactly(tmp_path, suffix: str, q: int) -> None:
    rng = np.random.default_rng(q)
    scenes = {
        "rods": Scene(
            (
                Capsule("marker", rng.normal(size=q), 0.011, rng.normal(size=q)),
                Obstacle("cup", rng.normal(size=q), 0.03),
            )
        ),
        7: Scene(),
        "cups": Scene((Obstacle("cup", rng.normal(size=q), 0.0),)),
    }
    path = save_scenes(tmp_path / f"s{suffix}", scenes)
    back = load_scenes(path)
    assert list(back) == list(scenes)
    for key, scene in scenes.items():
        assert [type(o) for o in back[key]] == [type(o) for o in scene]
        for got, want in zip(back[key], scene, strict=True):
            np.testing.assert_array_equal(got.position, want.position)
            assert got.radius == want.radius
            for name, value in want.fields().items():
                np.testing.assert_array_equal(got.fields()[name], value)


def test_round_only_scene_files_are_unchanged(tmp_path) -> None:
    path = save_scenes(tmp_path / "s.csv", {1: Scene((Obstacle("cup", [0.5, 0.25], 0.03),))})
    assert path.read_text() == "demo,class,x,y,radius\n1,cup,0.5,0.25,0.03\n"


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("class,x,y,shape\ncup,0,0,cone\n", r"line 2, column 'shape': unknown shape 'cone'; known"),
        ("class,x,y,shape\ncup,0,0,capsule\n", r"line 2: a capsule obstacle needs columns"),
        ("class,x,y,shape,end_x,end_y\ncup,0,0,capsule,1,\n", r"line 2: a capsule obstacle"),
        ("class,x,y,end_x,end_y\ncup,0,0,1,2\n", r"line 2, column 'end_x': a capsule field"),
    ],
)
def test_bad_shapes_in_csv_files_are_named(tmp_path, text: str, message: str) -> None:
    path = tmp_path / "s.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=message):
        load_scenes(path)


def test_bad_shapes_in_json_files_are_named(tmp_path) -> None:
    path = tmp_path / "s.json"
    head = '{"format": "lfdkit-scenes", "version": 1, "scenes": [{"demo": 1, "obstacles": ['
    for body, message in [
        ('{"class": "m", "position": [0, 0], "shape": "capsule"}', r"needs 'end'"),
        ('{"class": "m", "position": [0, 0], "shape": "capsule", "end": [1]}', r"\.end: expected"),
        ('{"class": "m", "position": [0, 0], "shape": 3}', r"\.shape: expected a shape name"),
        ('{"class": "m", "position": [0, 0], "shape": "cone"}', r"unknown shape 'cone'"),
    ]:
        path.write_text(head + body + "]}]}")
        with pytest.raises(ValueError, match=message):
            load_scenes(path)


# A shape defined outside lfdkit: two posts of one radius (a dumbbell's ends).
@dataclass(frozen=True, eq=False)
class TwoPosts(Obstacle):
    other: np.ndarray = field(default_factory=lambda: np.zeros(2))

    shape: ClassVar[str] = "two_posts"
    field_kinds: ClassVar[dict[str, str]] = {"other": "point"}

    def anchors(self) -> np.ndarray:
        return np.stack([self.position, np.asarray(self.other, float)])

    def balls(self) -> tuple[np.ndarray, np.ndarray]:
        return self.anchors(), np.full(2, self.radius)

    def distance(self, path: np.ndarray) -> float:
        return min(Obstacle(self.label, p, self.radius).distance(path) for p in self.anchors())

    def outline(self, n_points: int = 64) -> np.ndarray:
        half = n_points // 2
        circles = [Obstacle(self.label, p, self.radius).outline(half) for p in self.anchors()]
        return np.vstack(circles)

    def fields(self) -> dict:
        return {"other": np.asarray(self.other, float)}

    def transformed(self, factor: float, flip: np.ndarray) -> TwoPosts:
        return TwoPosts(
            self.label,
            factor * flip * self.position,
            factor * self.radius,
            factor * flip * np.asarray(self.other, float),
        )

    @classmethod
    def from_fields(cls, label, position, radius, fields) -> TwoPosts:
        return cls(label, position, radius, np.asarray(fields["other"], float))


def test_a_new_shape_is_one_class_used_unchanged_by_every_layer(tmp_path) -> None:
    register_shape(TwoPosts)
    try:
        posts = TwoPosts("post", [0.45, 0.01], 0.03, [0.6, -0.02])
        scene = Scene((posts,))
        # Scene files.
        back = load_scenes(save_scenes(tmp_path / "s.json", {1: scene}))[1].obstacles[0]
        assert isinstance(back, TwoPosts)
        np.testing.assert_array_equal(back.other, posts.other)
        back = load_scenes(save_scenes(tmp_path / "s.csv", {1: scene}))[1].obstacles[0]
        np.testing.assert_array_equal(back.other, posts.other)
        # Planner and metrics: the plan keeps clear of both posts.
        reward = Reward(5.0, {"post": [900.0, 900.0]})
        plan = plan_path(reward, straight(), scene, clearance=0.005)
        assert metrics.clearance(plan.points, scene)[0] >= 0.005 - 1e-9
        # The second post alone would be hit by the plan around the first one's response only.
        first_only = Scene((Obstacle("post", posts.position, 0.03),))
        naive = plan_path(reward, straight(), first_only, clearance=0.005)
        assert metrics.collisions(naive.points, scene) == 1
        # IOC scales it (its normalisation) and fits.
        demos = [plan.points]
        IOC(n_points=60, max_iter=5).fit(demos, [scene], straight(60))
        # Plots.
        fig, ax = plt.subplots()
        draw_scene(ax, scene)
        assert len(ax.patches) == 1
        plt.close(fig)
    finally:
        OBSTACLE_SHAPES.pop("two_posts", None)


def _shape_class(name: str, kinds: dict) -> type:
    return type("Bad", (TwoPosts,), {"shape": name, "field_kinds": kinds, "__annotations__": {}})


@pytest.mark.parametrize(
    ("name", "kinds", "message"),
    [
        ("round", {"other": "point"}, r"shape: 'round' is a built-in shape; give Bad another"),
        ("capsule", {"other": "point"}, r"shape: 'capsule' is a built-in shape"),
        ("posts", {"radius": "number"}, r"field_kinds\['radius'\]: 'radius' is a column every"),
        ("posts", {"vx": "number"}, r"field_kinds\['vx'\]: 'vx' is a column every"),
        ("posts", {"position": "point"}, r"field_kinds\['position'\]: 'position' is a column"),
        ("posts", {"demo": "number"}, r"field_kinds\['demo'\]: 'demo' is a column every"),
        ("posts", {"a": "point", "a_x": "number"}, r"its column 'a_x' is also field 'a'"),
        ("posts", {"end_x": "number"}, r"'end_x' is the capsule shape's field 'end'"),
        ("posts", {"other": "vector"}, r"kind must be 'point' or 'number'"),
        ("Posts", {"other": "point"}, r"must be a lowercase identifier"),
    ],
)
def test_register_shape_refuses_names_that_would_not_round_trip(name, kinds, message) -> None:
    with pytest.raises(ValueError, match=message):
        register_shape(_shape_class(name, kinds))
    assert set(OBSTACLE_SHAPES) >= {"round", "capsule"} and "posts" not in OBSTACLE_SHAPES


def test_fields_of_another_shape_or_dimension_are_refused_not_dropped(tmp_path) -> None:
    path = tmp_path / "s.csv"
    path.write_text("class,x,y,shape,end_x,end_y,end_z\nrod,0,0,capsule,1,0,0.5\n")
    with pytest.raises(ValueError, match=r"line 2, column 'end_z': a value in a 2-D scene"):
        load_scenes(path)
    path.write_text("class,x,y,shape,end_x,end_y,end_z\nrod,0,0,capsule,1,0,\n")
    assert load_scenes(path)[0].obstacles[0].shape == "capsule"  # an empty end_z is fine
    path = tmp_path / "s.json"
    path.write_text(
        '{"format": "lfdkit-scenes", "version": 1, "scenes": [{"demo": 1, "obstacles": '
        '[{"class": "cup", "position": [0, 0], "radius": 0.03, "end": [1, 0]}]}]}'
    )
    with pytest.raises(ValueError, match=r"obstacles\[0\]\.end: a capsule field, but the "):
        load_scenes(path)


_coord = st.floats(-10, 10, allow_nan=False, width=64)


@given(data=st.data(), q=st.sampled_from([2, 3]), suffix=st.sampled_from([".csv", ".json"]))
@settings(max_examples=40, deadline=None)
def test_any_registered_shapes_scene_file_reads_back_equal(tmp_path_factory, data, q, suffix):
    register_shape(TwoPosts)
    try:
        obstacles = []
        for _ in range(data.draw(st.integers(1, 4))):
            shape = data.draw(st.sampled_from(sorted(OBSTACLE_SHAPES)))
            cls = OBSTACLE_SHAPES[shape]
            fields = {
                name: data.draw(st.lists(_coord, min_size=q, max_size=q))
                if kind == "point"
                else data.draw(_coord)
                for name, kind in cls.field_kinds.items()
            }
            position = data.draw(st.lists(_coord, min_size=q, max_size=q))
            radius = data.draw(st.floats(0, 1, allow_nan=False))
            try:
                obstacles.append(cls.from_fields("c", np.array(position), radius, fields))
            except ValueError:
                continue
        scene = Scene(tuple(obstacles))
        path = tmp_path_factory.mktemp("rt") / f"s{suffix}"
        back = load_scenes(save_scenes(path, {1: scene}))[1]
        assert [type(o) for o in back] == [type(o) for o in scene]
        for got, want in zip(back, scene, strict=True):
            np.testing.assert_array_equal(got.position, want.position)
            assert got.radius == want.radius
            for name, value in want.fields().items():
                np.testing.assert_array_equal(got.fields()[name], value)
    finally:
        OBSTACLE_SHAPES.pop("two_posts", None)
