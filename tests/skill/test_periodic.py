"""PeriodicSkill: learned from cycles, planned as asked, and its file round-trips to the bit."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lfdkit.core.rotations import angle_between, exp, multiply
from lfdkit.datasets.robots import WIPE_PERIOD, wipe_demo
from lfdkit.imitate import RhythmicDMP
from lfdkit.skill.periodic import PERIODIC_FORMAT, PeriodicSkill

PERIOD = 1.25


def figure_eight(t: np.ndarray) -> np.ndarray:
    """A 20 × 6 cm figure-eight in cm about (40, 20), ``PERIOD`` s a cycle: a known cycle."""
    u = 2 * np.pi * t / PERIOD
    return np.c_[40.0 + 10.0 * np.sin(u), 20.0 + 3.0 * np.sin(2 * u)]


@pytest.fixture(scope="module")
def pose_skill() -> PeriodicSkill:
    positions, times, orientations = wipe_demo(seed=3, n_points=300)
    return PeriodicSkill().fit(positions, times, orientations)


@pytest.fixture(scope="module")
def plane_skill() -> PeriodicSkill:
    t = np.sort(np.random.default_rng(1).uniform(0.0, 4.2 * PERIOD, 300))  # uneven samples
    return PeriodicSkill(units="cm", n_harmonics=4).fit(figure_eight(t), t)


def test_the_period_centre_and_cycle_are_learned(plane_skill, pose_skill) -> None:
    assert plane_skill.period_ == pytest.approx(PERIOD, rel=1e-6)
    assert plane_skill.cycles_ == pytest.approx(4.2, rel=2e-2)
    assert plane_skill.centre_ == pytest.approx([40.0, 20.0], abs=1e-6)
    assert plane_skill.extent_ == pytest.approx([20.0, 6.0], rel=1e-3)
    assert pose_skill.period_ == pytest.approx(WIPE_PERIOD, rel=3e-3)
    assert pose_skill.orientation_ is not None
    line = pose_skill.summary()
    assert "period 1.6" in line and "4.3 cycles" in line and "mrad" in line


def test_a_plan_rests_at_the_centre_at_both_ends_and_lasts_its_cycles(plane_skill) -> None:
    plan = plane_skill.plan(3, amplitude=2.0, frequency=2.5, centre=[0.0, 0.0])
    run_period = PERIOD / 2.5
    # 3 cycles, the rise and fall (half a cycle each by default) and half a ramp settling.
    assert plan.times[-1] == pytest.approx(3 * run_period + 2.5 * 0.5 * run_period, rel=1e-9)
    np.testing.assert_allclose(plan.positions[[0, -1]], 0.0, atol=1e-6 * 20)
    np.testing.assert_allclose(plan.velocities[[0, -1]], 0.0, atol=1e-3)
    # At full amplitude the cycle is twice as wide about the new centre.
    middle = plan.positions[(plan.times > 1.0 * run_period) & (plan.times < 3.0 * run_period)]
    assert np.ptp(middle, axis=0) == pytest.approx([40.0, 12.0], rel=2e-2)


def test_without_a_ramp_the_plan_is_the_cycle_in_closed_form(plane_skill) -> None:
    plan = plane_skill.plan(2, amplitude=1.5, frequency=2.0, ramp=0.0, centre=[1.0, 2.0])
    phase = 2 * np.pi * 2.0 * plan.times / plane_skill.period_
    expected = [1.0, 2.0] + 1.5 * (plane_skill.position_.cycle(phase) - plane_skill.centre_)
    np.testing.assert_allclose(plan.positions, expected, atol=1e-9)
    assert plan.times[-1] == pytest.approx(2 * plane_skill.period_ / 2.0, rel=1e-12)


def test_the_orientation_rocks_as_demonstrated_and_stays_unit(pose_skill) -> None:
    plan = pose_skill.plan(cycles=2, ramp=0.0)
    np.testing.assert_allclose(np.linalg.norm(plan.orientations, axis=1), 1.0, atol=1e-14)
    # The learned cycle against the noise-free wipe (the generator's closed form).
    t = np.linspace(0.0, WIPE_PERIOD, 100)
    u = 2 * np.pi * t / WIPE_PERIOD
    rock = np.outer(0.08 * np.sin(u), [1.0, 0.0, 0.0]) + np.outer(
        0.05 * np.sin(2 * u + 0.3), [0.0, 1.0, 0.0]
    )
    truth = multiply(exp(rock), [1.0, 0.0, 0.0, 0.0])
    learned = pose_skill.orientation_.cycle(2 * np.pi * t / pose_skill.period_)
    assert angle_between(learned, truth).max() < 6e-3  # 8.7 mrad of noise, averaged


def test_save_load_save_gives_the_same_bytes_and_plans(tmp_path, pose_skill, plane_skill) -> None:
    for name, skill in (("pose", pose_skill), ("plane", plane_skill)):
        first, second = tmp_path / f"{name}.json", tmp_path / f"{name}-again.json"
        skill.save(first)
        loaded = PeriodicSkill.load(first)
        loaded.save(second)
        assert first.read_bytes() == second.read_bytes()
        asked = {"cycles": 1.5, "amplitude": 0.7, "frequency": 1.3}
        mine, theirs = skill.plan(**asked), loaded.plan(**asked)
        assert np.array_equal(mine.positions, theirs.positions)
        assert np.array_equal(mine.velocities, theirs.velocities)
        if skill.orientation_ is not None:
            assert np.array_equal(mine.orientations, theirs.orientations)
        assert json.loads(first.read_text())["format"] == PERIODIC_FORMAT


def test_loading_reads_and_never_refits(tmp_path, pose_skill, monkeypatch) -> None:
    pose_skill.save(tmp_path / "wipe.json")

    def refit(*args, **kwargs):
        raise AssertionError("refitted")

    monkeypatch.setattr(RhythmicDMP, "fit", refit)
    assert PeriodicSkill.load(tmp_path / "wipe.json").period_ == pose_skill.period_


def test_save_refuses_an_existing_file_unless_asked(tmp_path, plane_skill) -> None:
    target = plane_skill.save(tmp_path / "s.json")
    with pytest.raises(FileExistsError):
        plane_skill.save(target)
    plane_skill.save(target, overwrite=True)
    with pytest.raises(IsADirectoryError):
        plane_skill.save(tmp_path)


def _edited(document: dict, path: tuple, value) -> dict:
    copy = json.loads(json.dumps(document))
    where = copy
    for key in path[:-1]:
        where = where[key]
    if value is KeyError:
        del where[path[-1]]
    else:
        where[path[-1]] = value
    return copy


@pytest.mark.parametrize(
    ("path", "value", "message"),
    [
        (("format",), "lfdkit-skill", "not an lfdkit periodic skill"),
        (("version",), 2, "version 2 was written by a newer lfdkit"),
        (("position",), KeyError, "position: missing field"),
        (("position", "coefficients"), [[1.0, 2.0]], "position.coefficients: shape (1, 2)"),
        (("position", "period"), -1.0, "position.period: expected a positive number"),
        (("position", "params", "n_harmonics"), 4.5, "position.params: n_harmonics"),
        (("position", "params", "alpha"), 30.0, "position.params.alpha: 30.0"),
        (("params", "n_harmonics"), 0, "params: n_harmonics"),
        (("units",), "mm", "units: 'mm' does not match params.units"),
        (("n_dims",), 3, "position.n_dims: 2, but n_dims is 3"),
        (("fit", "cycles"), "many", "fit.cycles: expected a positive number"),
    ],
)
def test_a_broken_file_is_refused_on_one_line(plane_skill, path, value, message) -> None:
    with pytest.raises(ValueError, match=r"^f\.json: ") as caught:
        PeriodicSkill.from_dict(_edited(plane_skill.to_dict(), path, value), source="f.json")
    assert message in str(caught.value) and "\n" not in str(caught.value)


def test_an_orientation_off_the_position_phase_is_refused(pose_skill) -> None:
    document = _edited(pose_skill.to_dict(), ("orientation", "tangent", "period"), 1.0)
    with pytest.raises(ValueError, match="both run on one phase"):
        PeriodicSkill.from_dict(document, source="w.json")


def test_to_units_scales_the_plan(plane_skill) -> None:
    metres = plane_skill.to_units("m")
    assert metres.units == "m"
    np.testing.assert_allclose(
        metres.plan(2).positions, plane_skill.plan(2).positions / 100.0, rtol=1e-12
    )


@pytest.mark.parametrize(
    ("asked", "message"),
    [
        ({"cycles": 0}, "cycles"),
        ({"cycles": 2, "duration": 3.0}, "not both"),
        ({"cycles": 1e6}, "more than 10000"),
        ({"frequency": -1.0}, "frequency"),
        ({"orientation_centre": [0, 0, 0, 1]}, "learned no orientations"),
        ({"frequency": lambda t: 1.0}, "needs the run's duration"),
    ],
)
def test_bad_plan_settings_are_one_line(plane_skill, asked, message) -> None:
    with pytest.raises(ValueError, match=message):
        plane_skill.plan(**asked)


def test_no_rhythm_and_too_few_cycles_are_said() -> None:
    t = np.linspace(0.0, 2.0, 200)
    with pytest.raises(ValueError, match="does not move"):
        PeriodicSkill().fit(np.zeros((200, 2)), t)
    u = 2 * np.pi * t / 2.5  # 0.8 cycles of a circle: the best period leaves 82 % unexplained
    with pytest.raises(ValueError, match="no repeating cycle found"):
        PeriodicSkill().fit(np.c_[np.cos(u), np.sin(u)], t)
    with pytest.raises(ValueError, match=r"covers 0\.8 cycles"):
        PeriodicSkill(period=2.5).fit(np.c_[np.cos(u), np.sin(u)], t)
    with pytest.raises(ValueError, match="2 or 3"):
        PeriodicSkill().fit(np.zeros((200, 4)), t)


def test_a_poor_fit_is_said(plane_skill) -> None:
    t = np.linspace(0.0, 4.2 * PERIOD, 300)
    assert plane_skill.fit_warning(figure_eight(t)) is None
    # 2 cm of noise on a 20 x 6 cm cycle: 38 % of the stroke.
    noisy = figure_eight(t) + np.random.default_rng(0).normal(0.0, 2.0, (300, 2))
    skill = PeriodicSkill(period=PERIOD).fit(noisy, t)
    assert "poorly" in skill.fit_warning(noisy)


@settings(max_examples=30, deadline=None)
@given(
    coefficients=st.lists(
        st.floats(-1e3, 1e3, allow_nan=False, allow_subnormal=True), min_size=15, max_size=15
    ),
    period=st.floats(1e-3, 1e3, allow_nan=False),
)
def test_any_state_round_trips_through_json_to_the_bit(coefficients, period) -> None:
    """A document of any stored numbers reads back and writes the same text (2 harmonics, 3-D)."""
    document = {
        "format": PERIODIC_FORMAT,
        "version": 1,
        "lfdkit": "0",
        "params": {"alpha": 25.0, "n_harmonics": 2, "period": None, "ramp": None, "units": "m"},
        "n_dims": 3,
        "units": "m",
        "fit": {"cycles": 3.5, "n_points": 100},
        "position": {
            "params": {"alpha": 25.0, "n_harmonics": 2, "period": None},
            "period": period,
            "n_dims": 3,
            "residual_rms": 0.0,
            "coefficients": np.reshape(coefficients, (5, 3)).tolist(),
        },
    }
    skill = PeriodicSkill.from_dict(json.loads(json.dumps(document)))
    text = json.dumps(skill.to_dict(), indent=1)
    assert json.dumps(PeriodicSkill.from_dict(json.loads(text)).to_dict(), indent=1) == text
    stored = np.array(json.loads(text)["position"]["coefficients"])
    assert np.array_equal(stored, np.reshape(coefficients, (5, 3)))
    assert skill.period_ == period
