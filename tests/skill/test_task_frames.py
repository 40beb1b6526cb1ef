"""Tests of lfdkit.skill.task_frames: a movement learned in its task frames, planned in new ones."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lfdkit.imitate import TaskFrame
from lfdkit.io import load_demos, save_demos
from lfdkit.model.demos import Demo
from lfdkit.skill import TaskFrameSkill


def _hook(t: np.ndarray) -> np.ndarray:
    """The last 30 cm into a dustpan, in the dustpan's frame (m): along its x axis, then in."""
    return np.c_[-0.3 * (1 - t) ** 2, 0.05 * np.sin(np.pi * t) * (1 - t)]


def _demos(n: int, seed: int, q: int = 2, scale: float = 1.0) -> list[Demo]:
    """Sweeps into a dustpan moved and turned at random, each with its start and pan frames."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, 80)
    demos = []
    for _ in range(n):
        angle = rng.uniform(-1.2, 1.2)
        if q == 2:
            pan = np.r_[rng.uniform(0.4, 0.7, 2), angle]
            start = np.r_[rng.uniform(-0.05, 0.05, 2), 0.0]
            shape = _hook(t)
        else:
            pan = np.r_[
                rng.uniform(0.4, 0.7, 2), 0.1, 0.0, 0.0, np.sin(angle / 2), np.cos(angle / 2)
            ]
            start = np.r_[rng.uniform(-0.05, 0.05, 2), 0.1, 0.0, 0.0, 0.0, 1.0]
            shape = np.c_[_hook(t), 0.02 * np.sin(np.pi * t)]
        path = TaskFrame.from_vector(pan).to_world(shape) + 0.001 * rng.normal(size=shape.shape)
        frames = {"start": start, "pan": pan}
        if scale != 1.0:  # the same demonstration in another unit
            frames = {k: np.r_[v[:q] * scale, v[q:]] for k, v in frames.items()}
        demos.append(Demo(path * scale, 1.5 * t, frames=frames))
    return demos


@pytest.mark.parametrize("q", [2, 3])
def test_a_plan_arrives_along_a_new_pose_of_the_pan(q: int) -> None:
    skill = TaskFrameSkill(n_components=8).fit(_demos(8, seed=0, q=q))
    angle = 2.0  # beyond every training turn (±1.2 rad)
    if q == 2:
        pan = [0.5, 0.3, angle]
        new = {"start": [0.0, 0.0, 0.0], "pan": pan}
        local = _hook(np.linspace(0.0, 1.0, 100))
    else:
        pan = [0.5, 0.3, 0.1, 0.0, 0.0, np.sin(angle / 2), np.cos(angle / 2)]
        new = {"start": [0.0, 0.0, 0.1, 0.0, 0.0, 0.0, 1.0], "pan": pan}
        t = np.linspace(0.0, 1.0, 100)
        local = np.c_[_hook(t), 0.02 * np.sin(np.pi * t)]
    plan = skill.plan(new)
    known = TaskFrame.from_vector(pan).to_world(local)
    assert plan.positions.shape == (100, q) and plan.times[-1] == 1.5  # timed as shown
    assert np.linalg.norm(plan.positions[-1] - known[-1]) < 0.01  # m, at the pan
    assert np.sqrt(np.mean(np.sum((plan.positions - known) ** 2, axis=1))) < 0.005  # 1 mm noise
    # it arrives as the hook does into the turned pan: the last 15 points' direction
    end, want = plan.positions[-1] - plan.positions[-15], known[-1] - known[-15]
    cosine = end @ want / (np.linalg.norm(end) * np.linalg.norm(want))
    assert np.degrees(np.arccos(min(cosine, 1.0))) < 10.0
    np.testing.assert_allclose(plan.velocities, np.gradient(plan.positions, plan.times, axis=0))


def test_the_file_round_trips_to_the_bit(tmp_path) -> None:
    skill = TaskFrameSkill(n_components=6).fit(_demos(6, seed=1))
    first = skill.save(tmp_path / "sweep.json")
    loaded = TaskFrameSkill.load(first)
    second = loaded.save(tmp_path / "again.json")
    assert first.read_bytes() == second.read_bytes()
    new = {"start": [0.01, 0.0, 0.0], "pan": [0.6, 0.4, -0.5]}
    np.testing.assert_array_equal(loaded.plan(new).positions, skill.plan(new).positions)
    assert loaded.frame_names_ == ["start", "pan"] and loaded.duration_ == 1.5
    with pytest.raises(FileExistsError):
        skill.save(first)


def test_a_demonstrations_file_with_frame_columns_learns_the_same_skill(tmp_path) -> None:
    demos = _demos(6, seed=2)
    path = save_demos(tmp_path / "sweeps.csv", demos)
    from_file = TaskFrameSkill(n_components=6).fit(load_demos(path, as_records=True))
    direct = TaskFrameSkill(n_components=6).fit(demos)
    new = {"start": [0.0, 0.0, 0.0], "pan": [0.5, 0.5, 0.3]}
    np.testing.assert_array_equal(from_file.plan(new).positions, direct.plan(new).positions)
    arrays = TaskFrameSkill(n_components=6).fit(
        [d.points for d in demos], frames=[d.frames for d in demos]
    )
    assert arrays.duration_ is None  # arrays carry no times
    with pytest.raises(ValueError, match=r"^duration: the demonstrations had no times"):
        arrays.plan(new)
    np.testing.assert_allclose(arrays.plan(new, duration=1.5).times[-1], 1.5)


def test_millimetres_plan_the_metres_path_times_1000() -> None:
    new_m = {"start": [0.0, 0.0, 0.0], "pan": [0.55, 0.35, 0.7]}
    new_mm = {"start": [0.0, 0.0, 0.0], "pan": [550.0, 350.0, 0.7]}
    metres = TaskFrameSkill(n_components=6).fit(_demos(6, seed=3)).plan(new_m)
    millimetres = TaskFrameSkill(n_components=6, units="mm").fit(_demos(6, seed=3, scale=1e3))
    np.testing.assert_allclose(
        millimetres.plan(new_mm).positions, 1e3 * metres.positions, rtol=0, atol=1e-6
    )


def test_bad_input_gets_one_line_errors(tmp_path) -> None:
    skill = TaskFrameSkill(n_components=6).fit(_demos(6, seed=4))
    with pytest.raises(ValueError, match=r"^frames: missing pan; this skill was learned in"):
        skill.plan({"start": [0.0, 0.0, 0.0]})
    with pytest.raises(ValueError, match=r"^frames: unknown lid; this skill was learned in"):
        skill.plan({"start": [0.0, 0.0, 0.0], "pan": [0.5, 0.5, 0.0], "lid": [0, 0, 0]})
    with pytest.raises(ValueError, match=r"^frames\['pan'\]: pose: expected \[x, y, angle\]"):
        skill.plan({"start": [0.0, 0.0, 0.0], "pan": [0.5, 0.5]})
    with pytest.raises(ValueError, match=r"^frames\['pan'\]: this skill is 2-D; give"):
        skill.plan({"start": [0.0, 0.0, 0.0], "pan": [0.5, 0.5, 0.0, 0, 0, 0, 1]})
    with pytest.raises(TypeError, match=r"^frames: expected a mapping of the frames' names"):
        skill.plan([[0.0, 0.0, 0.0], [0.5, 0.5, 0.0]])
    with pytest.raises(ValueError, match=r"^frames\['pan'\]: contains NaN or an infinite value"):
        skill.plan({"start": [0.0, 0.0, 0.0], "pan": [np.nan, 0.5, 0.0]})
    with pytest.raises(ValueError, match=r"^frames\['pan'\]: the origin is 1e\+300 from 0, beyond"):
        skill.plan({"start": [0.0, 0.0, 0.0], "pan": [1e300, 0.5, 0.0]})
    flat = np.random.default_rng(0).random((10, 3))
    with pytest.raises(ValueError, match=r"^demos\[0\]: task frame 'a' is a 2-D pose, the demo"):
        TaskFrameSkill(n_components=2).fit([Demo(flat, frames={"a": [0, 0, 0]})])
    with pytest.raises(ValueError, match=r"^demos\[0\]: task frame 'a': orientation: row 0 has"):
        TaskFrameSkill(n_components=2).fit([Demo(flat, frames={"a": [0, 0, 0, 0, 0, 0, 2]})] * 2)
    plain = [Demo(d.points, d.times) for d in _demos(3, seed=5)]
    with pytest.raises(ValueError, match=r"^demos\[0\]: has no task frames; a task-frame"):
        TaskFrameSkill().fit(plain)
    with pytest.raises(ValueError, match=r"^frames: give each demonstration's task frames"):
        TaskFrameSkill().fit([d.points for d in plain])
    with pytest.raises(ValueError, match=r"^random_state: expected an int seed or None"):
        TaskFrameSkill(random_state=np.random.default_rng(0)).fit(_demos(3, seed=5))
    document = skill.to_dict()
    edited = json.loads(json.dumps(document))
    edited["frames"] = ["start", "lid"]
    with pytest.raises(ValueError, match=r"^f\.json: frames: \['start', 'lid'\], but the mixture"):
        TaskFrameSkill.from_dict(edited, source="f.json")
    edited = json.loads(json.dumps(document))
    edited["tpgmm"]["covariances"][0][0][0][1] += 1.0
    with pytest.raises(ValueError, match=r"^f\.json: tpgmm\.covariances: not symmetric"):
        TaskFrameSkill.from_dict(edited, source="f.json")
    edited = json.loads(json.dumps(document))
    edited["version"] = 2
    with pytest.raises(ValueError, match=r"^f\.json: version 2 was written by a newer lfdkit"):
        TaskFrameSkill.from_dict(edited, source="f.json")
    with pytest.raises(ValueError, match=r"not an lfdkit task-frame skill \(format 'lfdkit-skill'"):
        TaskFrameSkill.from_dict({**document, "format": "lfdkit-skill"})


def test_a_skill_converted_to_millimetres_plans_its_path_times_1000() -> None:
    skill = TaskFrameSkill(n_components=6).fit(_demos(6, seed=6))
    mm = skill.to_units("mm")
    assert mm.units == "mm" and mm.tpgmm_.length_scale == 1000.0
    metres = skill.plan({"start": [0.0, 0.0, 0.0], "pan": [0.55, 0.35, 0.7]}).positions
    in_mm = mm.plan({"start": [0.0, 0.0, 0.0], "pan": [550.0, 350.0, 0.7]}).positions
    np.testing.assert_allclose(in_mm, 1e3 * metres, rtol=0, atol=1e-8)
    back = mm.to_units("m").plan({"start": [0.0, 0.0, 0.0], "pan": [0.55, 0.35, 0.7]})
    np.testing.assert_allclose(back.positions, metres, rtol=0, atol=1e-12)
    assert TaskFrameSkill.from_dict(mm.to_dict()).units == "mm"  # a valid file


DOWN = np.array([1.0, 0.0, 0.0, 0.0])  # a tool pointing down


def _turn(angle: float) -> np.ndarray:
    return np.array([0.0, 0.0, np.sin(angle / 2), np.cos(angle / 2)])


def _held_tool(start: np.ndarray, pan: np.ndarray, n: int = 100) -> np.ndarray:
    """The known orientation: down in the start's frame, turned 0.3 rad in the pan's, blended."""
    from lfdkit.core.rotations import multiply, slerp

    t = np.linspace(0.0, 1.0, n)
    leave = multiply(_turn(start[2]), DOWN)
    arrive = multiply(_turn(pan[2]), multiply(_turn(0.3), DOWN))
    return slerp(np.tile(leave, (n, 1)), np.tile(arrive, (n, 1)), t * t * (3 - 2 * t))


def _turned_demos(n: int, seed: int) -> list[Demo]:
    from lfdkit.core.rotations import exp, multiply
    from lfdkit.datasets import dustpan_sweep

    rng = np.random.default_rng(seed)
    demos = []
    for _ in range(n):
        start = np.r_[np.array([0.2, -0.25]) + rng.uniform(-0.05, 0.05, 2), rng.uniform(-0.3, 0.3)]
        ahead = start[:2] + np.array([0.4, 0.15]) + rng.uniform(-0.08, 0.08, 2)
        pan = np.r_[ahead, rng.uniform(-1.0, 1.0)]
        path = dustpan_sweep(start, pan, 100) + 1e-3 * rng.normal(size=(100, 2))
        turns = multiply(_held_tool(start, pan), exp(0.005 * rng.normal(size=(100, 3))))
        demos.append(
            Demo(path, np.linspace(0.0, 1.5, 100), turns, frames={"start": start, "pan": pan})
        )
    return demos


def test_the_tool_orientation_is_learned_in_the_frames() -> None:
    # Pointing down, its heading held in the start's frame when leaving and turned 0.3 rad
    # in the pan's on arriving: a plan for new poses leaves and arrives so (within 0.5
    # degrees; a few degrees between, where the product of the frames is not the blend).
    from lfdkit.core.rotations import angle_between

    skill = TaskFrameSkill(n_components=8).fit(_turned_demos(8, seed=9))
    for start, pan in (
        ([0.2, -0.25, 0.1], [0.6, -0.1, 0.7]),
        ([0.22, -0.2, -0.2], [0.55, -0.05, -0.9]),
    ):
        plan = skill.plan({"start": start, "pan": pan})
        error = np.degrees(
            angle_between(plan.orientations, _held_tool(np.array(start), np.array(pan)))
        )
        assert error[0] < 0.5 and error[-1] < 0.5 and error.max() < 8.0
        np.testing.assert_allclose(np.linalg.norm(plan.orientations, axis=1), 1.0, atol=1e-12)
        assert np.all(np.sum(plan.orientations[1:] * plan.orientations[:-1], axis=1) > 0)


def test_orientations_round_trip_through_the_file_and_must_be_all_or_none(tmp_path) -> None:
    demos = _turned_demos(5, seed=10)
    skill = TaskFrameSkill(n_components=5).fit(demos)
    first = skill.save(tmp_path / "turned.json")
    loaded = TaskFrameSkill.load(first)
    assert loaded.save(tmp_path / "again.json").read_bytes() == first.read_bytes()
    new = {"start": [0.2, -0.25, 0.0], "pan": [0.6, -0.1, 0.4]}
    np.testing.assert_array_equal(loaded.plan(new).orientations, skill.plan(new).orientations)
    np.testing.assert_array_equal(
        skill.to_units("mm")
        .plan({"start": [200.0, -250.0, 0.0], "pan": [600.0, -100.0, 0.4]})
        .orientations,
        skill.plan(new).orientations,
    )
    mixed = [demos[0], Demo(demos[1].points, demos[1].times, frames=demos[1].frames)]
    with pytest.raises(ValueError, match=r"^demos\[1\]: has no tool orientations, but demos\[0\]"):
        TaskFrameSkill(n_components=2).fit(mixed)
    document = json.loads(first.read_text())
    document["orientation"]["references"][0] = [0.0, 0.0, 0.0, 2.0]
    with pytest.raises(ValueError, match=r"^f\.json: orientation\.references: not unit"):
        TaskFrameSkill.from_dict(document, source="f.json")
    plain = TaskFrameSkill(n_components=5).fit(_demos(5, seed=11))
    assert plain.plan({"start": [0, 0, 0], "pan": [0.5, 0.5, 0.0]}).orientations is None


def test_em_that_did_not_converge_is_said_once(monkeypatch) -> None:
    from lfdkit.imitate import tpgmm

    fit = tpgmm.TPGMM.fit

    def two_iterations(self, *args, **kwargs):
        self.max_iter = 2
        return fit(self, *args, **kwargs)

    monkeypatch.setattr(tpgmm.TPGMM, "fit", two_iterations)
    with pytest.warns(UserWarning) as caught:
        TaskFrameSkill(n_components=5).fit(_demos(3, seed=8))
    said = [str(w.message) for w in caught]
    assert said == [said[0]] and said[0].startswith("demos: the mixture's EM did not converge in 2")


def test_plans_beyond_the_demonstrated_poses_are_said() -> None:
    import warnings

    demos = _demos(8, seed=0)
    skill = TaskFrameSkill(n_components=6).fit(demos)
    mean = {name: np.mean([d.frames[name] for d in demos], axis=0) for name in ("start", "pan")}
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # within the demonstrated poses: nothing to say
        skill.plan(mean)
    with pytest.warns(UserWarning, match=r"^plan: pan turned \+1\.\d+ rad about z from the demo"):
        skill.plan({**mean, "pan": np.r_[mean["pan"][:2], 2.0]})
    far = {**mean, "pan": np.r_[mean["pan"][:2] + 0.5, mean["pan"][2]]}
    with pytest.warns(UserWarning, match=r"^plan: pan at \(.*\) m, beyond the demonstrated x"):
        skill.plan(far)
    # A frame that never moved: what the skill does for its other poses is a guess.
    fixed = [Demo(d.points, d.times, frames={**d.frames, "start": [0.0, 0.0, 0.0]}) for d in demos]
    with pytest.warns(UserWarning, match=r"^demos: task frame\(s\) start stand still in every"):
        TaskFrameSkill(n_components=6).fit(fixed)
    # Kept in the file, converted with the unit, and an edited box refused.
    document = json.loads(json.dumps(skill.to_dict()))
    assert TaskFrameSkill.from_dict(document).frame_ranges_ == skill.frame_ranges_
    mm = skill.to_units("mm").frame_ranges_["pan"]
    np.testing.assert_allclose(mm["low"], 1e3 * np.array(skill.frame_ranges_["pan"]["low"]))
    del document["frame_ranges"]  # a file without them plans as before, without the warning
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        TaskFrameSkill.from_dict(document).plan(far)
    document = json.loads(json.dumps(skill.to_dict()))
    document["frame_ranges"]["pan"]["low"] = [9.0, 9.0]
    with pytest.raises(ValueError, match=r"^f\.json: frame_ranges\.pan: not a box, a rotation"):
        TaskFrameSkill.from_dict(document, source="f.json")
