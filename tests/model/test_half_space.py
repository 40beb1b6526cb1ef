"""The built-in half-space (a table top, a floor, a wall): exact distances, the cover of its
clipped part, files, planner, IOC, metrics, plots and MuJoCo through the obstacle contract."""

from __future__ import annotations

import importlib.util
import itertools

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.distance import cdist

from lfdkit.app.plot import draw_scene, emulation_figure
from lfdkit.core.rotations import matrix_from_quaternion
from lfdkit.emulate import IOC, Box, HalfSpace, Obstacle, Reward, Scene, metrics, plan_path
from lfdkit.io import load_scenes, save_scenes
from lfdkit.model.motion import ConstantVelocity


def reference_height(position, normal, radius, point) -> float:
    """Signed distance to the plane ``n·x = n·p + r·|n|``, by the textbook formula."""
    normal = np.asarray(normal, float)
    return float(np.dot(point - position, normal) / np.sqrt(np.sum(normal**2))) - radius


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    q=st.sampled_from([2, 3]),
    n=st.integers(1, 5),
    radius=st.sampled_from([0.0, 0.02]),
    scale=st.sampled_from([1.0, 1000.0]),  # metres or millimetres
)
def test_distance_is_the_least_height_over_the_whole_path(seed, q, n, radius, scale) -> None:
    rng = np.random.default_rng(seed)
    normal = rng.normal(size=q) * rng.uniform(0.1, 5.0)  # any length: normalised
    position = scale * rng.normal(size=q)
    table = HalfSpace("table", position, scale * radius, normal)
    path = position + scale * rng.normal(size=(n, q))
    # Independent reference: densely sampled segments, each point by the textbook formula.
    dense = (
        path
        if n == 1
        else np.concatenate(
            [a + np.linspace(0, 1, 201)[:, None] * (b - a) for a, b in itertools.pairwise(path)]
        )
    )
    want = min(reference_height(position, normal, scale * radius, p) for p in dense)
    assert table.distance(path) == pytest.approx(want, rel=1e-9, abs=1e-9 * scale)
    assert metrics.clearance(path, Scene((table,)))[0] == pytest.approx(want, abs=1e-9 * scale)


@pytest.mark.parametrize("q", [2, 3])
def test_the_clipped_part_is_covered_tightly_by_balls(q: int) -> None:
    rng = np.random.default_rng(q)
    for _ in range(4):
        normal = rng.normal(size=q)
        table = HalfSpace("table", rng.normal(size=q) * 0.3, 0.01, normal)
        lower = rng.uniform(-1.0, -0.3, q)
        upper = lower + rng.uniform(0.5, 1.5, q)
        part = table.clipped(lower, upper)
        centres, radii = part.balls()
        # Every solid point in the box lies in a ball (independent: random points, heights).
        points = rng.uniform(lower, upper, (4000, q))
        solid = points[[table.distance(p[None]) <= 0.0 for p in points]]
        assert len(solid) > 100
        covered = (cdist(solid, centres) <= radii[None] + 1e-12).any(axis=1)
        assert covered.all()
        # The balls overhang the surface by a few millimetres per metre of box.
        highest = (centres - table.surface_point) @ table.normal + radii
        diagonal = float(np.linalg.norm(upper - lower))
        assert highest.max() <= 0.006 * diagonal
        # Its bounds and outline are those of the part: every vertex in the box, on or below.
        vertices, face = part.section()
        assert np.all((vertices >= lower - 1e-12) & (vertices <= upper + 1e-12))
        np.testing.assert_allclose(table.heights(face), 0.0, atol=1e-12)
        lo, hi = part.bounds()
        assert np.all(lo >= lower - 1e-12) and np.all(hi <= upper + 1e-12)


def test_an_unclipped_half_space_is_unbounded_and_says_so() -> None:
    table = HalfSpace("table", [0.5, 0.0, 0.1], 0.02, [0.0, 0.0, 3.0])
    np.testing.assert_array_equal(table.normal, [0.0, 0.0, 1.0])
    lo, hi = table.bounds()
    np.testing.assert_array_equal(lo, [-np.inf, -np.inf, -np.inf])
    np.testing.assert_allclose(hi, [np.inf, np.inf, 0.12], rtol=1e-15)
    assert table.has_extent
    np.testing.assert_array_equal(table.anchors(), [[0.5, 0.0, 0.1]])
    for method in ("balls", "outline", "section"):
        with pytest.raises(ValueError, match=rf"^{method}: half-space 'table' is unbounded; use"):
            getattr(table, method)()
    # A part of a part is their intersection.
    part = table.clipped([0, 0, -1], [1, 1, 1]).clipped([0.5, -1, -1], [2, 0.5, 1])
    np.testing.assert_array_equal(part.region[0], [0.5, 0, -1])
    np.testing.assert_array_equal(part.region[1], [1, 0.5, 1])


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"normal": [0.0, 0.0, 0.0]}, r"^normal: must be finite and non-zero, got \[0\.0, 0\.0"),
        ({"normal": [0.0, np.nan, 1.0]}, r"^normal: must be finite and non-zero"),
        ({"normal": [0.0, 1.0]}, r"^normal: expected 3 components for a 3-D half-space"),
        ({"radius": -1.0}, r"^radius: must be finite and >= 0"),
        (
            {"motion": ConstantVelocity([0.1, 0.0, 0.0])},
            r"^motion: a half-space cannot move \('table'\)",
        ),
    ],
)
def test_bad_half_spaces_are_refused_in_one_line(kwargs, message) -> None:
    args = {"label": "table", "position": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0], **kwargs}
    motion = args.pop("motion", None)
    with pytest.raises(ValueError, match=message) as info:
        HalfSpace(**args, motion=motion)
    assert "\n" not in str(info.value)


def test_transformations_keep_distances() -> None:
    wall = HalfSpace("wall", [0.2, 0.3], 0.01, [1.0, 1.0])
    path = np.array([[1.0, 0.5], [0.8, 1.2]])
    assert wall.scaled(1000.0).distance(1000.0 * path) == pytest.approx(
        1000.0 * wall.distance(path)
    )
    mirrored = wall.mirrored(1)
    assert mirrored.distance(path * [1.0, -1.0]) == pytest.approx(wall.distance(path))
    np.testing.assert_allclose(mirrored.normal, np.array([1.0, -1.0]) / np.sqrt(2.0))


@given(
    data=st.data(),
    q=st.sampled_from([2, 3]),
    suffix=st.sampled_from([".csv", ".json"]),
)
@settings(max_examples=20, deadline=None)
def test_scene_files_keep_half_spaces_to_the_bit(tmp_path_factory, data, q, suffix) -> None:
    coordinate = st.floats(-10, 10, allow_nan=False, width=64)
    normal = data.draw(st.lists(coordinate, min_size=q, max_size=q))
    if not np.any(normal):
        normal[0] = 1.0
    table = HalfSpace(
        "table",
        data.draw(st.lists(coordinate, min_size=q, max_size=q)),
        data.draw(st.floats(0, 1, allow_nan=False)),
        normal,
    )
    cup = Obstacle("cup", np.zeros(q), 0.03)
    path = tmp_path_factory.mktemp("rt") / f"s{suffix}"
    back = load_scenes(save_scenes(path, {"a": Scene((table, cup))}))["a"].obstacles
    assert isinstance(back[0], HalfSpace) and not isinstance(back[1], HalfSpace)
    np.testing.assert_array_equal(back[0].position, table.position)
    np.testing.assert_array_equal(back[0].normal, table.normal)
    assert back[0].radius == table.radius


def test_half_space_files_read_by_hand_and_refused_with_names(tmp_path) -> None:
    path = tmp_path / "s.csv"
    path.write_text(
        "demo,class,x,y,z,radius,shape,normal_x,normal_y,normal_z\n1,table,0.5,0,0,0,half_space,0,0,2\n"
    )
    table = load_scenes(path)[1].obstacles[0]
    assert isinstance(table, HalfSpace)
    np.testing.assert_array_equal(table.normal, [0.0, 0.0, 1.0])
    path.write_text("class,x,y,shape\ntable,0,0,half_space\n")
    with pytest.raises(ValueError, match=r"line 2: a half_space obstacle needs columns"):
        load_scenes(path)
    path.write_text("class,x,y,shape,normal_x,normal_y\ntable,0,0,half_space,0,0\n")
    with pytest.raises(ValueError, match=r"normal: must be finite and non-zero"):
        load_scenes(path)
    path = tmp_path / "s.json"
    path.write_text(
        '{"format": "lfdkit-scenes", "version": 1, "scenes": [{"demo": 1, "obstacles": '
        '[{"class": "t", "position": [0, 0], "shape": "half_space"}]}]}'
    )
    with pytest.raises(ValueError, match=r"needs 'normal'|normal: a half-space needs"):
        load_scenes(path)


def over_the_table(n: int = 50) -> np.ndarray:
    """A reach 3 cm above a table, along x."""
    x = np.linspace(0.0, 1.0, n)
    return np.column_stack([x, np.zeros(n), np.full(n, 0.03)])


def test_a_plan_over_a_table_goes_round_the_box_on_it_and_never_below_the_top() -> None:
    table = HalfSpace("table", [0.5, 0.0, 0.0], 0.0, [0.0, 0.0, 1.0])
    carton = Box("carton", [0.5, 0.0, 0.06], 0.0, [0.1, 0.1, 0.12])
    scene = Scene((table, carton))
    reward = Reward(10.0, {"table": [1e-2, 1e-2, 400.0], "carton": [200.0, 200.0, 200.0]})
    plan = plan_path(reward, over_the_table(), scene, clearance=0.01)
    table_gap, carton_gap = metrics.clearance(plan.points, scene)
    assert table_gap >= 0.01 - 1e-9 and carton_gap >= 0.01 - 1e-9
    assert plan.goal_error < 1e-3
    # Without the table in the scene the same reward's plan dives under the box's response.
    alone = plan_path(reward, over_the_table(), Scene((carton,)), clearance=0.01)
    assert alone.points[:, 2].min() < 0.0


def test_a_nominal_dipping_through_a_tilted_table_is_lifted_over_it() -> None:
    # The nominal dips 7 cm below z = 0 in its middle; the table top is tilted (rising along x).
    nominal = over_the_table()
    nominal[:, 2] += 0.03 - 0.13 * np.sin(np.pi * nominal[:, 0])
    table = HalfSpace("table", [0.5, 0.0, 0.0], 0.0, [-0.05, 0.0, 1.0])
    scene = Scene((table,))
    assert table.distance(nominal) < -0.05  # the nominal itself runs into it
    reward = Reward(10.0, {"table": [1e-2, 1e-2, 1e-2]})
    plan = plan_path(reward, nominal, scene, clearance=0.02)
    assert metrics.clearance(plan.points, scene)[0] >= 0.02 - 1e-9
    assert plan.goal_error < 1e-3


def test_ioc_fits_paths_along_a_wall() -> None:
    true = Reward(10.0, {"wall": [1.0, 900.0]})  # a response 1 m wide along the wall
    x = np.linspace(0.0, 1.0, 60)
    nominal = np.column_stack([x, np.zeros(60)])
    scenes, demos = [], []
    for y in (-0.04, -0.06, -0.09):
        scenes.append(Scene((HalfSpace("wall", [0.5, y], 0.0, [0.0, 1.0]),)))
        demos.append(plan_path(true, nominal, scenes[-1], goal_approach=None).points)
    fit = IOC(n_points=60).fit(demos, scenes, nominal)
    for demo, scene in zip(demos, scenes, strict=True):
        replay = plan_path(fit.reward_, nominal, scene, goal_approach=None).points
        assert np.abs(replay - demo).max() < 0.1 * np.abs(demo[:, 1]).max()


def test_plots_draw_the_part_of_the_half_space_they_show() -> None:
    wall = HalfSpace("wall", [0.0, 0.1], 0.0, [0.0, -1.0])
    cup = Obstacle("cup", [0.5, 0.0], 0.05)
    fig, ax = plt.subplots()
    ax.plot([0.0, 1.0], [0.0, 0.0])
    draw_scene(ax, Scene((wall, cup)))
    patches = {p.get_label(): p.get_xy() for p in ax.patches}
    # The wall's part: from y = 0.1 up, as wide as what the axes hold (grown by 10 %).
    assert patches["wall"][:, 1].min() == pytest.approx(0.1)
    assert patches["wall"][:, 0].min() < 0.0 and patches["wall"][:, 0].max() > 1.0
    plt.close(fig)
    # 3-D: the table's surface under the paths, in an emulation figure.
    table = HalfSpace("table", [0.5, 0.0, 0.0], 0.0, [0.0, 0.0, 1.0])
    reward = Reward(10.0, {"table": [1e-2, 1e-2, 400.0]})
    figure = emulation_figure(
        reward, over_the_table(), Scene((table,)), plans={"plan": over_the_table()}
    )
    surfaces = [
        c for a in figure.axes for c in a.collections if type(c).__name__ == "Poly3DCollection"
    ]
    assert len(surfaces) == 1


def test_the_solid_is_a_plane_mujoco_loads() -> None:
    table = HalfSpace("table", [0.5, 0.0, 0.1], 0.01, [0.0, 0.0, 1.0])
    centre, geom = table.solid(0.1)
    np.testing.assert_allclose(centre, [0.5, 0.0, 0.11])
    assert geom["type"] == "plane"
    w, x, y, z = (float(v) for v in geom["quat"].split())  # MuJoCo: scalar first
    # Its local z (MuJoCo's plane normal) is the half-space's normal.
    np.testing.assert_allclose(matrix_from_quaternion([x, y, z, w])[:, 2], [0, 0, 1], atol=1e-15)
    if importlib.util.find_spec("mujoco") is None:
        pytest.skip("mujoco is not installed: the XML is not loaded")
    import mujoco

    attributes = " ".join(f'{k}="{v}"' for k, v in geom.items())
    x, y, z = centre
    wall = HalfSpace("wall", [0.3, 0.0], 0.0, [1.0, 1.0]).solid(0.2)
    wall_attributes = " ".join(f'{k}="{v}"' for k, v in wall[1].items())
    xml = (
        f'<mujoco><worldbody><geom name="t" pos="{x} {y} {z}" {attributes}/>'
        f'<geom name="w" pos="{" ".join(map(str, wall[0]))}" {wall_attributes}/>'
        "</worldbody></mujoco>"
    )
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    # MuJoCo's plane normal (its local z) is the half-space's normal, in 3-D and in 2-D.
    np.testing.assert_allclose(data.geom_xmat[0].reshape(3, 3)[:, 2], [0.0, 0.0, 1.0], atol=1e-12)
    np.testing.assert_allclose(
        data.geom_xmat[1].reshape(3, 3)[:, 2], [np.sqrt(0.5), np.sqrt(0.5), 0.0], atol=1e-12
    )


def test_a_tiny_normal_is_a_direction_not_zero() -> None:
    # Its plain norm underflows to 0 (hypothesis found [0, 1.29e-211]).
    for normal, unit in (([0.0, 1.29e-211], [0.0, 1.0]), ([5e-324, 0.0], [1.0, 0.0])):
        np.testing.assert_array_equal(HalfSpace("table", [0.0, 0.0], 0.0, normal).normal, unit)
