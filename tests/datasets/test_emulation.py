"""Tests for lfdkit.datasets.emulation: demonstrations around obstacles from a known reward."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from lfdkit.core.geometry import point_tangents, resample
from lfdkit.datasets.emulation import (
    EMULATION_DATASETS,
    EmulationSet,
    artificial_obstacles,
    da_vinci_marker,
    load_emulation_dataset,
    sweeping,
)
from lfdkit.datasets.synthetic import da_vinci_walls
from lfdkit.emulate import Reward
from lfdkit.model.scene import Obstacle, Scene

NAMES = ("artificial", "da_vinci_marker", "sweeping")
#: Small configurations: the 3-D planner is the slow part, so da Vinci gets few demos.
CONFIG = {
    "artificial": {},
    "da_vinci_marker": {"n_demos": 4, "plan_points": 60},
    "sweeping": {},
}
#: Cheaper still, for the tests that generate a set several times.
TINY = {
    "artificial": {"n_demos": 3},
    "da_vinci_marker": {"n_demos": 2, "plan_points": 40},
    "sweeping": {"n_cup": 2, "n_marker": 2},
}
#: Largest distance from a demonstration's end to the nominal's goal, metres. The
#: thesis's sweeping responses reach 25 cm along the path, so those demos end beside
#: the dustpan; elsewhere only the noise (at most sqrt(6 (q - 1)) sd) moves the end.
END_TOL = {"artificial": 0.005, "da_vinci_marker": 0.0015, "sweeping": 0.05}
DIMS = {"artificial": 2, "da_vinci_marker": 3, "sweeping": 2}


@pytest.fixture(scope="module")
def sets() -> dict[str, EmulationSet]:
    return {name: load_emulation_dataset(name, seed=0, **CONFIG[name]) for name in NAMES}


@pytest.fixture(scope="module")
def clean() -> dict[str, EmulationSet]:
    """The noise-free demonstrator, same seed (so the same scenes)."""
    return {name: load_emulation_dataset(name, seed=0, noise=0.0, **CONFIG[name]) for name in NAMES}


# ----------------------------------------------------------------- helpers
def distance_to_polyline(point: np.ndarray, path: np.ndarray) -> float:
    """Euclidean distance from a point to a polyline (segments, not just vertices)."""
    a, b = path[:-1], path[1:]
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", point - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    return float(np.min(np.linalg.norm(a + t[:, None] * ab - point, axis=1)))


def side_of(obstacle: np.ndarray, nominal: np.ndarray, path: np.ndarray) -> float:
    """Where ``path`` crosses the nominal's normal plane nearest the obstacle, projected on
    the direction from the nominal to the obstacle (negative: the far side)."""
    i = int(np.argmin(np.linalg.norm(nominal - obstacle, axis=1)))
    tangent = point_tangents(nominal)[i]
    toward = obstacle - nominal[i]
    toward -= (toward @ tangent) * tangent
    toward /= np.linalg.norm(toward)
    along = (path - nominal[i]) @ tangent
    k = int(np.argmin(np.abs(along)))
    return float((path[k] - nominal[i]) @ toward)


def same_arrays(a: list[np.ndarray], b: list[np.ndarray]) -> bool:
    return len(a) == len(b) and all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))


def scene_positions(scenes: list[Scene]) -> list[np.ndarray]:
    return [s.positions for s in scenes]


# ----------------------------------------------------------------- registry
def test_registry_names() -> None:
    assert set(EMULATION_DATASETS) == set(NAMES)
    assert EMULATION_DATASETS["artificial"] is artificial_obstacles
    assert EMULATION_DATASETS["da_vinci_marker"] is da_vinci_marker
    assert EMULATION_DATASETS["sweeping"] is sweeping


@pytest.mark.parametrize("name", ["nope", "", None, ["artificial"]])
def test_unknown_name_lists_valid_names(name) -> None:
    with pytest.raises(ValueError, match="valid names: artificial, da_vinci_marker, sweeping"):
        load_emulation_dataset(name, seed=0)


def test_loader_matches_generator() -> None:
    a = load_emulation_dataset("artificial", seed=5, n_demos=2)
    b = artificial_obstacles(seed=5, n_demos=2)
    assert same_arrays(a.demos, b.demos)


# ----------------------------------------------------------------- determinism
@pytest.mark.parametrize("name", NAMES)
def test_same_seed_bit_identical_and_different_seeds_differ(name: str) -> None:
    a = load_emulation_dataset(name, seed=11, **TINY[name])
    b = load_emulation_dataset(name, seed=11, **TINY[name])
    c = load_emulation_dataset(name, seed=12, **TINY[name])
    assert same_arrays(a.demos, b.demos)
    assert same_arrays(scene_positions(a.scenes), scene_positions(b.scenes))
    assert same_arrays(scene_positions(a.held_out_scenes), scene_positions(b.held_out_scenes))
    assert np.array_equal(a.nominal, b.nominal)
    assert not any(np.allclose(x, y) for x, y in zip(a.demos, c.demos, strict=True))
    assert not any(
        np.allclose(x, y)
        for x, y in zip(scene_positions(a.scenes), scene_positions(c.scenes), strict=True)
    )


def test_generator_seed_equals_int_seed() -> None:
    a = artificial_obstacles(seed=3, n_demos=2)
    b = artificial_obstacles(seed=np.random.default_rng(3), n_demos=2)
    assert same_arrays(a.demos, b.demos)


def test_first_demos_do_not_depend_on_how_many_follow() -> None:
    short = artificial_obstacles(seed=4, n_demos=3)
    long = artificial_obstacles(seed=4, n_demos=8)
    assert same_arrays(short.demos, long.demos[:3])


def test_noise_does_not_change_the_scenes(sets, clean) -> None:
    for name in NAMES:
        assert same_arrays(scene_positions(sets[name].scenes), scene_positions(clean[name].scenes))
        assert not any(
            np.array_equal(x, y) for x, y in zip(sets[name].demos, clean[name].demos, strict=True)
        )


# ----------------------------------------------------------------- contents
@pytest.mark.parametrize("name", NAMES)
def test_shapes_dims_and_units(sets, name: str) -> None:
    es = sets[name]
    q = DIMS[name]
    assert es.name == name
    assert es.units == "m"
    assert es.n_dims == q
    assert es.nominal.shape == (500, q)
    expected_points = 90 if name == "sweeping" else 100
    assert all(d.shape == (expected_points, q) and d.dtype == np.float64 for d in es.demos)
    assert len(es.scenes) == es.n_demos
    assert all(len(s) == 1 and s.positions.shape == (1, q) for s in es.scenes)
    assert es.true_reward.n_dims == q


def test_default_sizes() -> None:
    es = artificial_obstacles(seed=0)
    assert es.n_demos == 8
    assert es.train.tolist() == [0, 1, 2, 3, 4, 5]
    assert es.test.tolist() == [6, 7]


def test_true_rewards_are_the_thesis_parameters(sets) -> None:
    art = sets["artificial"].true_reward
    assert art.nominal_weight == 10.0
    np.testing.assert_array_equal(art.precisions["obstacle"], np.diag([2500.0, 215.0]))
    dv = sets["da_vinci_marker"].true_reward
    assert dv.nominal_weight == 200.0
    np.testing.assert_array_equal(dv.precisions["marker"], np.diag([475.8, 8576.3, 8576.3]))
    sw = sets["sweeping"].true_reward
    assert sw.nominal_weight == 20.0
    np.testing.assert_array_equal(sw.precisions["cup"], np.diag([15.4, 1000.0]))
    np.testing.assert_array_equal(sw.precisions["marker"], np.diag([20.08, 880.0]))


def test_classes_and_radii(sets) -> None:
    assert sets["artificial"].classes == ("obstacle",)
    assert all(s.radii.tolist() == [0.02] for s in sets["artificial"].scenes)
    assert sets["da_vinci_marker"].classes == ("marker",)
    assert all(s.radii.tolist() == [0.01] for s in sets["da_vinci_marker"].scenes)
    sw = sets["sweeping"]
    assert sw.classes == ("cup", "marker")
    assert [s.labels[0] for s in sw.scenes] == ["cup"] * 6 + ["marker"] * 6
    for s in sw.scenes:
        assert s.radii[0] == {"cup": 0.03, "marker": 0.01}[s.labels[0]]


@pytest.mark.parametrize("name", NAMES)
def test_train_test_disjoint_and_complete(sets, name: str) -> None:
    es = sets[name]
    assert es.train.size > 0 and es.test.size > 0
    assert np.intersect1d(es.train, es.test).size == 0
    assert sorted(np.concatenate((es.train, es.test)).tolist()) == list(range(es.n_demos))
    assert len(es.train_demos) == es.train.size and len(es.test_scenes) == es.test.size


def test_sweeping_split_is_per_class(sets) -> None:
    sw = sets["sweeping"]
    labels = np.array([s.labels[0] for s in sw.scenes])
    assert sorted(labels[sw.test].tolist()) == ["cup", "cup", "marker", "marker"]
    assert sorted(labels[sw.train].tolist()) == ["cup"] * 4 + ["marker"] * 4


@pytest.mark.parametrize("name", NAMES)
def test_demos_start_at_start_and_end_at_goal(sets, name: str) -> None:
    es = sets[name]
    for demo in es.demos:
        assert np.linalg.norm(demo[0] - es.nominal[0]) < 0.005
        assert np.linalg.norm(demo[-1] - es.nominal[-1]) < END_TOL[name]


@pytest.mark.parametrize("name", NAMES)
def test_noise_free_demonstrator_swerves_away(clean, name: str) -> None:
    es = clean[name]
    for demo, scene in zip(es.demos, es.scenes, strict=True):
        obstacle = scene.positions[0]
        nominal_gap = distance_to_polyline(obstacle, es.nominal)
        demo_gap = distance_to_polyline(obstacle, demo)
        assert demo_gap > nominal_gap + 0.01
        # The obstacle is beside the nominal: the demonstrator passes on the far side.
        assert side_of(obstacle, es.nominal, demo) < 0.0


@pytest.mark.parametrize("name", NAMES)
def test_no_demo_passes_through_an_obstacle(sets, name: str) -> None:
    es = sets[name]
    for demo, scene in zip(es.demos, es.scenes, strict=True):
        for obstacle in scene:
            assert distance_to_polyline(obstacle.position, demo) > obstacle.radius


@pytest.mark.parametrize("name", NAMES)
def test_noise_size_is_as_documented(sets, clean, name: str) -> None:
    noise = {"artificial": 0.0015, "da_vinci_marker": 0.00025, "sweeping": 0.001}[name]
    q = DIMS[name]
    gaps = np.array(
        [
            distance_to_polyline(p, c)
            for d, c in zip(sets[name].demos, clean[name].demos, strict=True)
            for p in d
        ]
    )
    assert gaps.max() <= np.sqrt(6.0 * (q - 1)) * noise * 1.05
    assert 0.3 * noise < np.sqrt(np.mean(gaps**2)) < 2.0 * noise


def test_true_plan_is_the_noise_free_demonstrator(clean) -> None:
    es = clean["artificial"]
    plan = es.true_plan(es.scenes[0], n_points=100)
    np.testing.assert_allclose(resample(plan, 100), es.demos[0], rtol=0, atol=1e-12)


# ----------------------------------------------------------------- da Vinci geometry
def test_da_vinci_nominal_and_walls_match_the_mimicking_set(sets) -> None:
    dv = sets["da_vinci_marker"]
    ref = da_vinci_walls(n_demos=1, seed=0, noise=0.0)
    np.testing.assert_allclose(dv.nominal, ref.nominal, rtol=0, atol=1e-12)
    assert len(dv.walls) == 2
    for a, b in zip(dv.walls, ref.walls, strict=True):
        np.testing.assert_array_equal(a, b)


def test_da_vinci_markers_clear_of_walls_and_start(sets) -> None:
    dv = sets["da_vinci_marker"]
    precision = dv.true_reward.precisions["marker"]
    for scene in [*dv.scenes, *dv.held_out_scenes]:
        for marker in scene:
            assert abs(marker.position[1]) + marker.radius < 0.025
            assert marker.position[2] == 0.035
            rel = dv.nominal[0] - marker.position
            assert rel @ precision @ rel > 1.0  # the planner's "start inside" test
    for demo in dv.demos:
        assert np.all(np.abs(demo[:, 1]) < 0.025)
        travel = demo[(demo[:, 0] > 0.03) & (demo[:, 0] < 0.07)]
        assert np.all(np.abs(travel[:, 2] - 0.035) < 0.002)  # sideways dodge, not over/under


# ----------------------------------------------------------------- held-out scenes
@pytest.mark.parametrize("name", NAMES)
def test_held_out_scenes_use_training_classes(sets, name: str) -> None:
    es = sets[name]
    seen = {c for s in es.train_scenes for c in s.classes}
    assert es.held_out_scenes
    for scene in es.held_out_scenes:
        assert len(scene) >= 1
        assert set(scene.classes) <= seen
        assert scene.positions.shape[1] == es.n_dims


def test_artificial_held_out_clutter_and_concave_pocket(sets) -> None:
    es = sets["artificial"]
    cluttered, concave = es.held_out_scenes
    assert len(cluttered) == 4 and len(concave) == 5
    # The pocket sits on the nominal (going straight on runs into its bottom), its
    # arms lie on both sides of the nominal and reach back towards the start.
    assert min(distance_to_polyline(p, es.nominal) for p in concave.positions) < 0.02
    centre = concave.positions.mean(axis=0)
    i = int(np.argmin(np.linalg.norm(es.nominal - centre, axis=1)))
    tangent = point_tangents(es.nominal)[i]
    left = np.array([-tangent[1], tangent[0]])
    lateral = (concave.positions - es.nominal[i]) @ left
    along = (concave.positions - es.nominal[i]) @ tangent
    assert lateral.min() < -0.05 and lateral.max() > 0.05
    bottom = int(np.argmin(np.abs(lateral)))
    arms = np.argsort(np.abs(lateral))[-2:]
    assert np.all(along[arms] < along[bottom] - 0.05)  # the opening faces the oncoming path
    for scene in es.held_out_scenes:
        plan = es.true_plan(scene)
        for obstacle in scene:
            assert distance_to_polyline(obstacle.position, plan) > obstacle.radius


def test_sweeping_held_out_mixes_both_classes(sets) -> None:
    sw = sets["sweeping"]
    assert len(sw.held_out_scenes) == 4
    for scene in sw.held_out_scenes:
        assert set(scene.classes) == {"cup", "marker"}
    assert len(sw.held_out_scenes[-1]) == 4
    for scene in sw.held_out_scenes:
        plan = sw.true_plan(scene)  # the cube is outside every response: no ValueError
        for obstacle in scene:
            assert distance_to_polyline(obstacle.position, plan) > obstacle.radius


# ----------------------------------------------------------------- argument errors
@pytest.mark.parametrize(
    ("generator", "kwargs", "field"),
    [
        (artificial_obstacles, {"n_demos": 0}, "n_demos"),
        (artificial_obstacles, {"noise": -0.001}, "noise"),
        (artificial_obstacles, {"noise": np.inf}, "noise"),
        (artificial_obstacles, {"n_points": 1}, "n_points"),
        (artificial_obstacles, {"plan_points": 2}, "plan_points"),
        (da_vinci_marker, {"n_demos": -1}, "n_demos"),
        (sweeping, {"n_cup": 0}, "n_cup"),
        (sweeping, {"n_marker": 0}, "n_marker"),
    ],
)
def test_bad_arguments_raise_value_error(generator, kwargs, field) -> None:
    with pytest.raises(ValueError, match=field):
        generator(seed=0, **kwargs)


@pytest.mark.parametrize("kwargs", [{"n_demos": 2.5}, {"seed": "zero"}])
def test_wrong_argument_types_raise_type_error(kwargs) -> None:
    with pytest.raises(TypeError):
        artificial_obstacles(**kwargs)


# ----------------------------------------------------------------- EmulationSet validation
@pytest.fixture(scope="module")
def small() -> EmulationSet:
    return artificial_obstacles(seed=1, n_demos=3)


def _other_obstacle(label: str = "obstacle", q: int = 2) -> Scene:
    return Scene((Obstacle(label, np.full(q, 0.5), 0.02),))


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"name": ""}, "name"),
        ({"nominal": np.zeros((10, 4))}, "nominal"),
        ({"demos": []}, "demos"),
        ({"units": "inch"}, "units: expected one of"),
        ({"train": np.array([0, 1]), "test": np.array([2, 1])}, "test: indices"),
        ({"train": np.array([0]), "test": np.array([2])}, "neither"),
        ({"train": np.array([0, 1, 3]), "test": np.array([2])}, "train: indices must lie"),
        ({"train": np.array([0, 0, 1]), "test": np.array([2])}, "train: repeated"),
        ({"train": np.array([], dtype=int), "test": np.array([0, 1, 2])}, "train: needs"),
        ({"train": np.array([0.0, 1.0]), "test": np.array([2])}, "train: expected"),
        ({"walls": (np.zeros((2, 3)),)}, "walls"),
    ],
)
def test_emulation_set_rejects_inconsistent_fields(small, changes, message) -> None:
    with pytest.raises(ValueError, match=message):
        dataclasses.replace(small, **changes)


def test_emulation_set_rejects_mismatched_scenes(small) -> None:
    with pytest.raises(ValueError, match="scenes: expected one scene per demonstration"):
        dataclasses.replace(small, scenes=small.scenes[:2])
    with pytest.raises(ValueError, match=r"scenes\[1\]: 3-D obstacles"):
        dataclasses.replace(small, scenes=[small.scenes[0], _other_obstacle(q=3), small.scenes[2]])
    with pytest.raises(ValueError, match=r"scenes\[0\]: obstacle class 'cat'"):
        dataclasses.replace(small, scenes=[_other_obstacle("cat"), *small.scenes[1:]])
    with pytest.raises(ValueError, match=r"held_out_scenes\[0\]: obstacle class 'cat'"):
        dataclasses.replace(small, held_out_scenes=[_other_obstacle("cat")])
    sweep = sweeping(seed=0, n_cup=2, n_marker=2)
    cups_only = np.array([0, 1])
    with pytest.raises(ValueError, match=r"held_out_scenes\[0\]: obstacle class 'marker'"):
        dataclasses.replace(sweep, train=cups_only, test=np.array([2, 3]))
    with pytest.raises(TypeError, match=r"scenes\[0\]"):
        dataclasses.replace(small, scenes=["not a scene", *small.scenes[1:]])
    with pytest.raises(TypeError, match="true_reward"):
        dataclasses.replace(small, true_reward={"obstacle": [1.0, 1.0]})
    with pytest.raises(ValueError, match="true_reward: 3-D"):
        dataclasses.replace(small, true_reward=Reward(1.0, {"obstacle": [1.0, 1.0, 1.0]}))


def test_emulation_set_accepts_lists_and_empty_walls(small) -> None:
    es = dataclasses.replace(small, train=[0, 2], test=[1], held_out_scenes=())
    assert es.train.dtype == np.intp and es.test.tolist() == [1]
    assert es.held_out_scenes == [] and es.walls == ()
