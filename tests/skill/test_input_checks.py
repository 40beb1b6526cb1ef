"""Inputs a new user gets wrong: points in another unit, obstacles on or through a demonstration.

A goal or obstacle typed in metres for a skill in millimetres is a valid point
near the origin; a scene file in metres for demonstrations in millimetres puts
every obstacle far from them; a demonstration that starts, ends or passes
inside its obstacle names a wrong position, size or unit. Each is said, naming
the argument and the fix, before any fit or plan runs on it.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from lfdkit.core.units import UnitsWarning
from lfdkit.model.half_space import HalfSpace
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import Skill

# Three sweeps in millimetres along x, 800 mm long, a few mm apart.
_X = np.linspace(-400.0, 400.0, 40)
CLEAN = [np.c_[_X, 450.0 + dy + 30.0 * np.sin(np.linspace(0.0, np.pi, 40))] for dy in (0, 3, -4)]
# One demonstration that swerves 60 mm above a cup of radius 30 mm at (0, 440).
_BUMP = 60.0 * np.exp(-(_X**2) / (2 * 80.0**2))
AROUND = CLEAN[0] + np.c_[np.zeros(40), _BUMP]
CUP = Obstacle("cup", [0.0, 440.0], radius=30.0)


@pytest.fixture(scope="module")
def skill() -> Skill:
    return Skill(units="mm").fit_path(CLEAN)


def test_a_goal_in_metres_for_a_millimetre_skill_is_warned_naming_the_unit(skill) -> None:
    with pytest.warns(UnitsWarning, match=r"^goal: \(0\.4, 0\.45\) mm lies far .* in m it"):
        skill.plan(goal=[0.4, 0.45])
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnitsWarning)
        skill.plan(goal=[400.0, 450.0])  # in its unit: nothing said
        skill.plan(goal=[1200.0, 450.0])  # far, but no unit brings it among the demonstrations


def test_an_obstacle_in_metres_for_a_millimetre_skill_is_warned(skill) -> None:
    scene = Scene((Obstacle("cup", [0.0, 0.44], radius=0.03),))
    # The skill has no reward, so the plan is then refused: the warning comes first.
    with pytest.warns(UnitsWarning, match=r"^scene: obstacle 0 \('cup'\): .* in m it would"):
        with pytest.raises(ValueError):
            skill.plan(goal=[400.0, 450.0], scene=scene)


def test_a_box_in_metres_for_a_millimetre_skill_is_warned_by_its_size() -> None:
    # A reach from the base (the origin) out to 600 mm: a box typed in metres stands
    # among the demonstrations' own coordinates, so only its size (0.1 mm) gives it away.
    from lfdkit.model.box import Box

    t = np.linspace(0.0, 1.0, 40)
    reach = [np.c_[600.0 * t, 400.0 * t + dy] for dy in (0.0, 3.0, -4.0)]
    skill = Skill(units="mm").fit_path(reach)
    in_metres = Box("carton", [0.3, 0.2], size=[0.1, 0.05])
    with pytest.warns(
        UnitsWarning,
        match=r"^scene: obstacle 0 \('carton'\): 0\.1 mm across .* in m it would be 100 mm",
    ):
        with pytest.raises(ValueError):  # no reward for it: refused after the warning
            skill.plan(goal=[600.0, 400.0], scene=Scene((in_metres,)))
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnitsWarning)
        with pytest.raises(ValueError):
            skill.plan(
                goal=[600.0, 400.0], scene=Scene((Box("carton", [300, 200], size=[100, 50]),))
            )


def test_a_scene_file_s_box_in_metres_is_warned_by_its_size_before_the_fit(monkeypatch) -> None:
    # The demonstrations (mm) swerve round a carton at (300, 200) mm; the scene gives it
    # in metres, near the reach's origin: only its size tells.
    from lfdkit.model.box import Box

    t = np.linspace(0.0, 1.0, 40)
    bump = 60.0 * np.exp(-((t - 0.5) ** 2) / (2 * 0.1**2))
    demos = [np.c_[600.0 * t, 400.0 * t - bump + dy] for dy in (0.0, 3.0, -4.0)]
    scenes = [Scene((Box("carton", [0.3, 0.2], size=[0.1, 0.05]),))] * 3

    class Checked(Exception):
        """Raised right after the scenes' checks: the fit itself is not wanted here."""

    def stop(*args, **kwargs):
        raise Checked

    monkeypatch.setattr(Skill, "_goals", stop)
    with pytest.warns(UserWarning, match=r"0\.1 mm across is smaller than any obstacle.*in m it"):
        with pytest.raises(Checked):
            Skill(units="mm").fit(demos, demos, scenes)


@pytest.mark.parametrize(("end", "index"), [("starts", 0), ("ends", -1)])
def test_a_demonstration_starting_or_ending_inside_its_obstacle_is_refused(skill, end, index):
    scene = Scene((Obstacle("cup", AROUND[index], radius=30.0),))
    with pytest.raises(
        ValueError, match=rf"^scenes\[0\]: obstacle 0 \('cup'\): its demonstration {end} 30 mm"
    ):
        Skill(units="mm").fit(CLEAN, [AROUND], [scene])


def test_a_demonstration_through_its_obstacle_and_a_scene_in_metres_are_warned(skill) -> None:
    through = Scene((Obstacle("cup", AROUND[20], radius=30.0),))
    metres = Scene((Obstacle("cup", [0.0, 0.44], radius=0.03),))
    fitted = Skill(units="mm").fit_path(CLEAN)
    # A goal of the wrong size stops the fit right after the checks.
    with pytest.warns(UserWarning) as caught, pytest.raises(ValueError, match=r"^goals"):
        fitted.fit_reward([AROUND, AROUND], [through, metres], goals=[1.0, 2.0, 3.0])
    said = [str(w.message) for w in caught]
    assert any(
        m.startswith("scenes[0]: obstacle 0 ('cup'): its demonstration passes 30 mm inside")
        for m in said
    ), said
    assert any(
        m.startswith("scenes[1]: obstacle 0 ('cup'): at (0, 0.44) mm lies far from every")
        and "in m it would lie among them" in m
        for m in said
    ), said


def test_a_scene_of_the_demonstrations_unit_is_not_warned(skill) -> None:
    fitted = Skill(units="mm").fit_path(CLEAN)
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)
        with pytest.raises(ValueError, match=r"^goals"):
            fitted.fit_reward([AROUND], [Scene((CUP,))], goals=[1.0, 2.0, 3.0])


def test_times_in_milliseconds_are_warned_and_seconds_are_not() -> None:
    seconds = [np.linspace(0.0, 4.0 + 0.5 * j, 40) for j in range(3)]
    with pytest.warns(UserWarning, match=r"^times: the demonstrations last 4500 s \(median\)"):
        Skill(units="mm").fit_path(CLEAN, times=[1000.0 * t for t in seconds])
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)
        Skill(units="mm").fit_path(CLEAN, times=seconds)


def test_demonstrations_that_do_not_move_are_refused_without_a_units_guess() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)  # no "in cm they would span 0 m"
        with pytest.raises(ValueError, match=r"all points coincide"):
            Skill().fit_path([np.ones((20, 2)), np.ones((20, 2))])


def test_a_scene_of_the_wrong_dimension_and_a_bad_horizon_are_named(skill) -> None:
    # A NumPy broadcasting error before; the horizon was ignored where the route has none.
    scene = Scene((Obstacle("cup", [0.0, 440.0, 100.0], radius=30.0),))
    with pytest.raises(ValueError, match=r"^scene: obstacle 0 \('cup'\) has 3 coordinates for a"):
        skill.plan(goal=[400.0, 450.0], scene=scene)
    with pytest.raises(ValueError, match=r"^horizon: expected 4 <= H <= 12"):
        skill.plan(goal=[400.0, 450.0], horizon=50, planner="full")


def test_a_class_in_one_scene_only_is_warned_as_not_cross_validated() -> None:
    fitted = Skill(units="mm").fit_path(CLEAN)
    marker = Scene((Obstacle("marker", [0.0, 440.0], radius=10.0),))
    with pytest.warns(UserWarning) as caught, pytest.raises(ValueError, match=r"^goals"):
        fitted.fit_reward([AROUND] * 3, [Scene((CUP,)), Scene((CUP,)), marker], goals=[1, 2, 3])
    said = [str(w.message) for w in caught]
    assert said == [
        "scenes[2]: obstacle class 'marker' is in this scene only: its learned response rests "
        "on one demonstration and cannot be cross-validated; show another demonstration "
        "around a marker"
    ]


def test_a_table_half_space_in_a_scene_is_checked_not_refused_as_unbounded() -> None:
    # An unbounded shape has no covering balls of its own: the check of how deep a
    # demonstration passes inside its obstacle raised "balls: half-space 'floor' is
    # unbounded" (lfdkit learn with a table in the scene file). It is sized by its part
    # among the demonstrations now, and a demonstration through it is still warned.
    fitted = Skill(units="mm").fit_path(CLEAN)
    floor = HalfSpace("floor", [0.0, 440.0], normal=[0.0, 1.0])  # 10 mm under the starts
    dip = AROUND - np.c_[np.zeros(40), 3.0 * _BUMP]  # about 80 mm below the floor
    depth = 440.0 - dip[:, 1].min()
    with pytest.warns(UserWarning) as caught, pytest.raises(ValueError, match=r"^goals"):
        fitted.fit_reward(
            [AROUND, AROUND, dip],
            [Scene((floor, CUP)), Scene((floor,)), Scene((floor,))],
            goals=[1, 2, 3],
        )
    said = [str(w.message) for w in caught]
    inside = [m for m in said if "inside it" in m]
    assert len(inside) == 1 and inside[0].startswith(
        f"scenes[2]: obstacle 0 ('floor'): its demonstration passes {depth:.3g} mm inside"
    ), said
