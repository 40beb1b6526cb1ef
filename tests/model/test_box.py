"""The built-in oriented box: exact distances, covering balls, files, planner, IOC, plots."""

from __future__ import annotations

import itertools

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import minimize_scalar
from scipy.spatial.distance import cdist
from scipy.spatial.transform import Rotation

from lfdkit.app.plot import draw_scene
from lfdkit.emulate import IOC, Box, Obstacle, Reward, Scene, metrics, plan_path
from lfdkit.io import load_scenes, save_scenes
from lfdkit.model.scene import OBSTACLE_SHAPES


def reference_point_distance(box: Box, point: np.ndarray) -> float:
    """Signed distance by projection onto the box (scipy's rotation, not lfdkit's)."""
    q = box.n_dims
    matrix = Rotation.from_quat(box.orientation).as_matrix()[:q, :q]
    local = matrix.T @ (point - box.position)
    nearest = np.clip(local, -box.half, box.half)
    if np.any(nearest != local):
        return float(np.linalg.norm(local - nearest)) - box.radius
    return -float(np.min(box.half - np.abs(local))) - box.radius


def reference_path_distance(box: Box, path: np.ndarray) -> float:
    """Minimum over each segment by bounded scalar minimisation (convex along it)."""
    best = min(reference_point_distance(box, p) for p in path)
    for a, b in itertools.pairwise(path):
        found = minimize_scalar(
            lambda t, a=a, b=b: reference_point_distance(box, a + t * (b - a)),
            bounds=(0.0, 1.0),
            method="bounded",
            options={"xatol": 1e-10},
        )
        best = min(best, float(found.fun))
    return best


def random_box(rng: np.random.Generator, q: int, radius: float = 0.0) -> Box:
    size = rng.uniform(0.01, 1.0, q)
    if q == 2:
        return Box.from_yaw("carton", rng.normal(size=2), size, rng.uniform(-4, 4), radius)
    quaternion = Rotation.random(random_state=rng).as_quat()
    return Box("carton", rng.normal(size=3), radius, size, quaternion)


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    q=st.sampled_from([2, 3]),
    n=st.integers(1, 4),
    radius=st.sampled_from([0.0, 0.05]),
    spread=st.sampled_from([0.3, 1.0, 3.0]),
)
def test_distance_to_a_path_is_exact(seed: int, q: int, n: int, radius: float, spread: float):
    rng = np.random.default_rng(seed)
    box = random_box(rng, q, radius)
    path = box.position + spread * rng.normal(size=(n, q))
    got = box.distance(path)
    want = reference_path_distance(box, path)
    # The closed form is exact; the reference optimiser only ever over-estimates.
    assert got <= want + 1e-9
    assert want - got <= 1e-6


@pytest.mark.parametrize("q", [2, 3])
@pytest.mark.parametrize("scale", [1e-3, 1.0, 1e3])
def test_path_distance_is_every_segments_least_to_the_bit(q: int, scale: float) -> None:
    # Box.distance looks only at the segments that may hold the nearest point (issue 34):
    # the same number as the least candidate of every segment, past, through and along it.
    from lfdkit.model.box import _local_signed_distance, _segment_candidates

    rng = np.random.default_rng(q)
    for trial in range(60):
        box = random_box(rng, q, [0.0, 0.05][trial % 2])
        box = box.transformed(scale, np.ones(q))
        a, b = box.position + scale * rng.normal(size=(2, q))
        if trial % 3 == 1:  # through the box
            b = 2.0 * box.position - a
        m = int(rng.integers(2, 150))
        path = a + np.linspace(0.0, 1.0, m)[:, None] * (b - a)
        path += scale * rng.normal(0.0, 0.02, path.shape)
        if trial % 3 == 2:  # each point twice: empty segments
            path = np.repeat(path, 2, axis=0)
        local = box.to_local(path)
        step = np.diff(local, axis=0)
        t = _segment_candidates(local[:-1], step, box.half)
        points = (local[:-1, None, :] + t[:, :, None] * step[:, None, :]).reshape(-1, q)
        want = float(_local_signed_distance(points, box.half).min()) - box.radius
        assert box.distance(path) == want


@pytest.mark.parametrize("q", [2, 3])
def test_point_distances_inside_on_and_outside(q: int) -> None:
    rng = np.random.default_rng(5)
    box = random_box(rng, q)
    centre = box.position[None]
    assert box.distance(centre) == pytest.approx(-box.half.min())
    corners = box.corners()
    np.testing.assert_allclose(box.signed_distances(corners), 0.0, atol=1e-12)
    # Out along a face normal by 0.3: exactly 0.3; beyond a corner along the diagonal: |Δ|.
    normal = box.axes[:, 0]
    face = box.position + (box.half[0] + 0.3) * normal
    assert box.distance(face[None]) == pytest.approx(0.3)
    corner = corners[-1]
    away = corner + 0.2 * (corner - box.position) / np.linalg.norm(corner - box.position)
    assert box.distance(away[None]) == pytest.approx(0.2)
    # A path through the box: negative, down to the deepest point it reaches.
    through = np.stack([box.position - 5 * normal, box.position + 5 * normal])
    assert box.distance(through) == pytest.approx(-box.half.min())


@pytest.mark.parametrize("q", [2, 3])
def test_balls_cover_the_box_tightly_and_anchors_span_it(q: int) -> None:
    rng = np.random.default_rng(q)
    for radius in (0.0, 0.02):
        box = random_box(rng, q, radius)
        local = rng.uniform(-1, 1, (3000, q)) * (box.half + radius)
        inside = box.position + local @ box.axes.T
        inside = inside[box.signed_distances(inside) <= 0]
        centres, radii = box.balls()
        assert (cdist(inside, centres) <= radii[None] + 1e-12).any(axis=1).all()
        # The cover overhangs by at most a cell's half diagonal beyond the surface.
        assert box.signed_distances(centres).max() <= 1e-12 + radius
        assert len(radii) <= 16**q
        anchors = box.anchors()
        assert np.all(box.signed_distances(anchors) <= radius + 1e-12)
        lo, hi = box.bounds()
        assert np.all(inside >= lo - 1e-12) and np.all(inside <= hi + 1e-12)
    cube = Box("cube", [0.0, 0.0, 0.0], 0.0, [0.1, 0.1, 0.1])
    np.testing.assert_allclose(cube.anchors(), [[0.0, 0.0, 0.0]])
    table = Box("table", [0.0, 0.0, 0.0], 0.0, [1.0, 0.6, 0.02])
    assert table.anchors().shape == (8 * 5, 3)  # the response follows the top, not a ball


@pytest.mark.parametrize("q", [2, 3])
def test_the_extreme_point_is_the_farthest_of_the_dense_solid(q: int) -> None:
    # The solid sampled densely: a grid of 41 points per edge through the box (ends
    # included), a sphere (circle) of 4000 directions of the rounding radius about
    # each; its farthest sample along a direction is the grid's plus the sphere's.
    rng = np.random.default_rng(5)
    sphere = rng.normal(size=(4000, q))
    sphere /= np.linalg.norm(sphere, axis=1, keepdims=True)
    for scale, radius in ((1.0, 0.0), (1.0, 0.05), (1e3, 20.0)):  # m and mm
        size = rng.uniform(0.1, 0.5, q) * scale
        turn = Rotation.from_rotvec(rng.normal(size=3) if q == 3 else [0, 0, rng.normal()])
        box = Box("box", rng.normal(size=q) * scale, radius, size, turn.as_quat())
        ticks = [np.linspace(-h, h, 41) for h in box.half]
        grid = box.position + np.array(list(itertools.product(*ticks))) @ box.axes.T
        for direction in rng.normal(size=(8, q)):
            unit = direction / np.linalg.norm(direction)
            point = box.extreme_point(3.0 * direction)  # any length: a direction
            assert box.signed_distances(point[None])[0] == pytest.approx(0.0, abs=1e-12 * scale)
            best = float(np.max(grid @ unit)) + radius * float(np.max(sphere @ unit))
            sampling = 3e-3 * radius + 1e-12 * scale  # the sphere's directions are sampled
            assert best - 1e-12 * scale <= float(point @ unit) <= best + sampling


def test_transformations_keep_distances() -> None:
    rng = np.random.default_rng(2)
    for q in (2, 3):
        box = random_box(rng, q, 0.01)
        path = rng.normal(size=(6, q))
        for axis in range(q):
            flip = np.ones(q)
            flip[axis] = -1.0
            mirrored = box.mirrored(axis)
            assert isinstance(mirrored, Box)
            assert mirrored.distance(path * flip) == pytest.approx(box.distance(path), abs=1e-12)
        twice = box.scaled(2.0)
        assert twice.distance(2.0 * path) == pytest.approx(2.0 * box.distance(path), abs=1e-12)
        shifted = box.translated(np.ones(q))
        assert shifted.distance(path + 1.0) == pytest.approx(box.distance(path), abs=1e-12)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"size": [0.1, 0.1, 0.1]}, r"^size: expected 2 edge lengths for a 2-D box"),
        ({"size": [0.1, -0.1]}, r"^size: edge lengths must be finite and >= 0"),
        ({"size": [0.1, 0.1], "orientation": [0, 0, 0, 2]}, r"^orientation: row 0 has norm 2"),
        (
            {"size": [0.1, 0.1], "orientation": [0.6, 0, 0, 0.8]},
            r"^orientation: a 2-D box turns about z only",
        ),
    ],
)
def test_bad_boxes_are_refused_in_one_line(kwargs, message) -> None:
    with pytest.raises(ValueError, match=message):
        Box("carton", [0.0, 0.0], **kwargs)


box_sizes = st.floats(0.0, 5.0, allow_nan=False, width=64)
coords = st.floats(-10, 10, allow_nan=False, width=64)


@settings(max_examples=40, deadline=None)
@given(
    data=st.data(),
    q=st.sampled_from([2, 3]),
    suffix=st.sampled_from([".csv", ".json"]),
)
def test_scene_files_keep_boxes_to_the_bit(tmp_path_factory, data, q, suffix) -> None:
    obstacles = []
    for _ in range(data.draw(st.integers(1, 3))):
        position = data.draw(st.lists(coords, min_size=q, max_size=q))
        size = data.draw(st.lists(box_sizes, min_size=q, max_size=q))
        radius = data.draw(st.floats(0, 1, allow_nan=False))
        if q == 2:
            box = Box.from_yaw("carton", position, size, data.draw(coords), radius)
        else:
            seed = data.draw(st.integers(0, 2**32 - 1))
            quaternion = Rotation.random(random_state=seed).as_quat()
            box = Box("carton", position, radius, size, quaternion)
        obstacles.append(box)
    obstacles.append(Obstacle("cup", np.zeros(q), 0.03))
    scene = Scene(tuple(obstacles))
    path = tmp_path_factory.mktemp("boxes") / f"s{suffix}"
    back = load_scenes(save_scenes(path, {"a": scene}))["a"]
    assert [type(o) for o in back] == [type(o) for o in scene]
    for got, want in zip(back, scene, strict=True):
        np.testing.assert_array_equal(got.position, want.position)
        assert got.radius == want.radius
        for name, value in want.fields().items():
            np.testing.assert_array_equal(got.fields()[name], value)


def test_box_files_read_by_hand_and_refused_with_names(tmp_path) -> None:
    path = tmp_path / "s.csv"
    path.write_text("class,x,y,shape,size_x,size_y,qx,qy,qz,qw\ncarton,0.5,0,box,0.2,0.1,0,0,0,1\n")
    (box,) = load_scenes(path)[0]
    assert isinstance(box, Box) and box.distance(np.array([[0.5, 0.2]])) == pytest.approx(0.15)
    path.write_text("class,x,y,shape,size_x,size_y\ncarton,0.5,0,box,0.2,0.1\n")
    with pytest.raises(ValueError, match=r"line 2: a box obstacle needs columns 'qx'"):
        load_scenes(path)
    assert "box" in OBSTACLE_SHAPES


def straight(n: int = 120, q: int = 2) -> np.ndarray:
    x = np.linspace(0.0, 1.0, n)
    return np.column_stack([x, np.zeros((n, q - 1))])


@pytest.mark.parametrize("q", [2, 3])
def test_the_planner_keeps_clear_of_a_long_box_the_dmp_would_cross(q: int) -> None:
    reward = Reward(5.0, {"carton": [900.0] * q})
    # A long box across the path, turned by 20°, reaching 5 cm past it on one side.
    size = [0.06, 0.5] + [0.1] * (q - 2)
    position = [0.5, -0.2] + [0.0] * (q - 2)
    if q == 2:
        box = Box.from_yaw("carton", position, size, np.radians(20.0))
    else:
        box = Box("carton", position, 0.0, size, Rotation.from_euler("z", 20, True).as_quat())
    scene = Scene((box,))
    assert metrics.collisions(straight(q=q), scene) == 1
    plan = plan_path(reward, straight(q=q), scene, clearance=0.01)
    assert metrics.collisions(plan.points, scene) == 0
    assert metrics.clearance(plan.points, scene)[0] >= 0.01 - 1e-9
    assert plan.points[:, 1].max() > 0.05


def test_ioc_fits_demonstrations_round_boxes() -> None:
    true = Reward(8.0, {"carton": [1600.0, 900.0]})
    nominal = straight(60)
    scenes, demos = [], []
    for x, y, yaw in [(0.3, 0.04, 0.2), (0.5, -0.05, -0.3), (0.7, 0.02, 0.5)]:
        scenes.append(Scene((Box.from_yaw("carton", [x, y], [0.08, 0.04], yaw),)))
        demos.append(plan_path(true, nominal, scenes[-1], goal_approach=None).points)
    fit = IOC(n_points=60).fit(demos, scenes, nominal)
    for demo, scene in zip(demos, scenes, strict=True):
        replay = plan_path(fit.reward_, nominal, scene, goal_approach=None).points
        assert np.abs(replay - demo).max() < 0.1 * np.abs(demo[:, 1]).max()


def test_plots_draw_the_box() -> None:
    box = Box.from_yaw("carton", [0.5, 0.0], [0.2, 0.1], np.radians(30.0))
    fig, ax = plt.subplots()
    draw_scene(ax, Scene((box,)))
    (patch,) = ax.patches
    np.testing.assert_allclose(patch.get_xy()[:-1], box.outline()[:-1])
    np.testing.assert_allclose(np.sort(patch.get_xy()[:-1], axis=0), np.sort(box.corners(), axis=0))
    plt.close(fig)
    fig = plt.figure()
    ax = fig.add_subplot(projection="3d")
    draw_scene(ax, Scene((Box("carton", [0.5, 0.0, 0.1], 0.0, [0.2, 0.1, 0.2]),)))
    plt.close(fig)


def test_a_box_with_volume_is_a_hard_barrier_and_a_point_is_not() -> None:
    assert Box.from_yaw("carton", [0.5, 0.0], [0.2, 0.1]).has_extent
    assert Box("carton", [0.5, 0.0, 0.0], 0.0, [0.2, 0.1, 0.3]).has_extent
    assert not Box.from_yaw("plate", [0.5, 0.0], [0.2, 0.0]).has_extent  # a segment
    assert Box.from_yaw("plate", [0.5, 0.0], [0.2, 0.0], radius=0.01).has_extent
    assert not Obstacle("cup", [0.5, 0.0]).has_extent
    assert Obstacle("cup", [0.5, 0.0], 0.01).has_extent
    scene = Scene((Obstacle("cup", [0.5, 0.0]), Box.from_yaw("carton", [0.5, 0.0], [0.2, 0.1])))
    np.testing.assert_array_equal(scene.has_extent, [False, True])


def densely(points: np.ndarray, per_segment: int = 50) -> np.ndarray:
    """The polyline resampled with ``per_segment`` points on every segment (ends included)."""
    t = np.linspace(0.0, 1.0, per_segment, endpoint=False)[None, :, None]
    inner = points[:-1, None] + t * np.diff(points, axis=0)[:, None]
    return np.vstack([inner.reshape(-1, points.shape[1]), points[-1:]])


@pytest.mark.parametrize("q", [2, 3])
def test_a_sharp_box_planned_without_clearance_is_never_entered(q: int) -> None:
    # A narrow response (precision 1e5: 3 mm wide) on a box 0.1 wide across
    # the nominal: only a hard barrier keeps the plan out of it.
    reward = Reward(5.0, {"carton": [1e5] * q})
    size = [0.1, 0.08] + [0.1] * (q - 2)
    position = [0.5, 0.01] + [0.0] * (q - 2)
    if q == 2:
        box = Box.from_yaw("carton", position, size, np.radians(10.0))
    else:
        box = Box("carton", position, 0.0, size, Rotation.from_euler("z", 10, True).as_quat())
    scene = Scene((box,))
    nominal = straight(q=q)
    assert box.radius == 0.0 and metrics.collisions(nominal, scene) == 1
    plan = plan_path(reward, nominal, scene, clearance=0.0)
    assert plan.clearance.min() >= 0.0
    assert box.distance(plan.points) > 0.0
    assert box.signed_distances(densely(plan.points)).min() > 0.0
    np.testing.assert_allclose(plan.points[-1], nominal[-1], atol=0.01)


def test_a_start_inside_a_sharp_box_is_refused_without_clearance() -> None:
    reward = Reward(5.0, {"carton": [1e5, 1e5]})
    scene = Scene((Box.from_yaw("carton", [0.05, 0.0], [0.2, 0.1]),))
    with pytest.raises(ValueError, match=r"start: lies inside obstacle 0 \('carton'.*box shape"):
        plan_path(reward, straight(), scene, clearance=0.0)
