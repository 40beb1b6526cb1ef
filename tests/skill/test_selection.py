"""The behaviour model's ranking over cross-validation folds (lfdkit.skill.selection)."""

import numpy as np
import pytest

from lfdkit.emulate import Reward, plan_path
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import Skill
from lfdkit.skill.selection import (
    FOLD_TRIM,
    SELECTION_MARGIN,
    SWERVE_MARGIN,
    _fidelity_scores,
    _fold_error,
    _ranked,
)


def _rows(errors: list[float], relaxed: tuple[int, ...] = (), refused: tuple[int, ...] = ()):
    """Held-out rows of demonstrations 0..n-1 with these squared errors (replay 1.0 each)."""
    return [
        {"demo": j, "refused": "no route"}
        if j in refused
        else {
            "demo": j,
            "mse": e,
            "improvement": 100.0 * (1.0 - e),
            "sides_agree": e < 1.0,
            "clearance_relaxed": j in relaxed,
            "replay_mse": 1.0,
        }
        for j, e in enumerate(errors)
    ]


def test_the_fold_error_is_a_trimmed_mean_of_the_folds() -> None:
    # 10 demonstrations in 5 folds (demo % 5): fold means 0.1, 0.2, 0.3, 0.4 and 5.0.
    errors = [0.1, 0.2, 0.3, 0.4, 9.9, 0.1, 0.2, 0.3, 0.4, 0.1]
    assert FOLD_TRIM == 0.2
    # The best (0.1) and the worst (5.0) fold left out: the mean of 0.2, 0.3, 0.4.
    assert _fold_error(_rows(errors), 5) == pytest.approx(0.3)
    scores = _fidelity_scores(_rows(errors), 5)
    assert scores["error"] == pytest.approx(0.3)
    assert scores["mse"] == pytest.approx(np.mean(errors))  # still reported whole
    # Fewer than 5 folds: nothing trimmed (the plain mean of the fold means).
    assert _fold_error(_rows([0.1, 0.2, 3.0, 0.4]), 4) == pytest.approx(0.925)
    # Not cross-validated: the mean.
    assert _fidelity_scores(_rows([0.1, 0.3]))["error"] == pytest.approx(0.2)


def test_one_fold_does_not_decide_the_model() -> None:
    # "swerve" replans nine of ten held-out demonstrations at Pr 95 % and flips a side in
    # one fold (Pr -2000 %), where the plan could not keep its floor either; "closest"
    # replans all ten at Pr 45 %. Its mean error is the larger (2.1 against 0.55), yet
    # one fold's flip must not choose the model a person is emulated at 45 % with.
    swerve = _rows([0.05] * 4 + [21.0] + [0.05] * 5, relaxed=(4,))
    closest = _rows([0.55] * 10)
    scores = {"closest": _fidelity_scores(closest, 5), "swerve": _fidelity_scores(swerve, 5)}
    assert scores["swerve"]["mse"] > scores["closest"]["mse"]
    assert _ranked(["closest", "swerve"], scores, "closest") == ["swerve", "closest"]
    # Flips in two folds of five are no outlier: then it loses.
    twice = _rows([0.05] * 3 + [21.0, 21.0] + [0.05] * 5)
    scores["swerve"] = _fidelity_scores(twice, 5)
    assert _ranked(["closest", "swerve"], scores, "closest") == ["closest", "swerve"]


def test_the_ranking_keeps_refusals_first_and_the_default_margin() -> None:
    good, fair = _rows([0.10] * 5), _rows([0.10 * (1.0 - SELECTION_MARGIN / 2)] * 5)
    scores = {"a": _fidelity_scores(good, 5), "b": _fidelity_scores(fair, 5)}
    # b is closer, but by less than the margin: the default a stays.
    assert _ranked(["a", "b"], scores, "a") == ["a", "b"]
    assert _ranked(["a", "b"], scores, "b") == ["b", "a"]
    # A model that finds no plan for a held-out demonstration comes after one that does.
    scores["b"] = _fidelity_scores(_rows([0.01] * 5, refused=(2,)), 5)
    assert _ranked(["a", "b"], scores, "b") == ["a", "b"]


def test_the_swerve_must_cut_the_held_out_error_of_the_models_without_it() -> None:
    # Its folds are single obstacles of the training task: fitting a little closer there
    # (a late swerver: 0.64-1.07 of the others' error) does not choose it; explaining what
    # the symmetric bump cannot (a potential field: 0.07-0.20) does.
    assert SWERVE_MARGIN == 0.35
    names = ["window+demonstrated", "taut+typical", "window/swerve"]
    for ratio, chosen in ((0.6, "window+demonstrated"), (0.3, "window/swerve")):
        scores = {
            "window+demonstrated": _fidelity_scores(_rows([0.10] * 5), 5),
            "taut+typical": _fidelity_scores(_rows([0.30] * 5), 5),
            "window/swerve": _fidelity_scores(_rows([0.10 * ratio] * 5), 5),
        }
        assert _ranked(names, scores, "window+demonstrated")[0] == chosen
    # Against the best model without it, the default's margin included: the taut route
    # at 0.05 leaves the swerve at 0.03 behind it, first among the others.
    scores["taut+typical"] = _fidelity_scores(_rows([0.05] * 5), 5)
    assert _ranked(names, scores, "window+demonstrated") == [
        "taut+typical",
        "window/swerve",
        "window+demonstrated",
    ]


def test_a_swerve_that_beats_the_symmetric_models_meets_the_slow_return_on_its_error() -> None:
    # Both explain an asymmetric person; the margin is the swerve's case against the
    # thesis's symmetric bump only. Past it, the closer of the two wins.
    names = ["window", "window+demonstrated", "window/swerve", "window+demonstrated/return"]

    def ranked(swerve: float, slow: float) -> list[str]:
        scores = {
            "window": _fidelity_scores(_rows([0.10] * 5), 5),
            "window+demonstrated": _fidelity_scores(_rows([0.12] * 5), 5),
            "window/swerve": _fidelity_scores(_rows([swerve] * 5), 5),
            "window+demonstrated/return": _fidelity_scores(_rows([slow] * 5), 5),
        }
        return _ranked(names, scores, "window")

    # 0.3 of the best symmetric model's error: against the slow return at 0.25 (which
    # would have kept it behind, 0.3 / SWERVE_MARGIN = 0.86) by the errors alone.
    assert ranked(0.030, 0.025)[:2] == ["window+demonstrated/return", "window/swerve"]
    assert ranked(0.030, 0.040)[:2] == ["window/swerve", "window+demonstrated/return"]
    # Not past the margin (0.5 of the symmetric model's): scaled against every model.
    assert ranked(0.050, 0.080)[:2] == ["window+demonstrated/return", "window"]
    assert ranked(0.050, 0.200)[:3] == ["window", "window+demonstrated", "window/swerve"]
    # The default's margin counts in the symmetric models' least error: 0.35 x 0.10 x 0.98
    # = 0.0343. Just within it the swerve wins on its error; just beyond, scaled (0.0986),
    # it loses to the slow return at 0.09.
    assert ranked(0.0342, 0.090)[0] == "window/swerve"
    assert ranked(0.0345, 0.090)[0] == "window+demonstrated/return"


def _skill_of(person: Reward):
    """A skill fitted on 6 demonstrations planned by ``person`` (thesis MPC, H = 8)."""
    x = np.linspace(0.0, 1.0, 100)
    free = [np.column_stack([x, 0.002 * s * np.sin(np.pi * x)]) for s in (-1.0, 0.0, 1.0)]
    rng = np.random.default_rng(1)
    demos, scenes = [], []
    for j in range(6):
        scene = Scene((Obstacle("cup", [0.3 + 0.08 * j, rng.uniform(-0.02, 0.02)], radius=0.01),))
        plan = plan_path(person, free[1], scene, horizon=8, goal_approach=None, lookahead=False)
        demos.append(plan.points)
        scenes.append(scene)
    return Skill().fit(free, demos, scenes)


@pytest.mark.slow  # a skill's whole fit and model choice (about 3 s quiet)
def test_a_skill_of_a_swerving_person_chooses_and_plans_with_the_swerve() -> None:
    skill = _skill_of(Reward(10.0, {"cup": [400.0, 2500.0]}, swerve={"cup": [0.5, 3.0]}))
    selection = skill.model_selection_
    assert selection["chosen"] == "path:window/swerve"
    # the skill plans with the learned swerve, longer after the cup than before (its
    # sizes trade off with the response's width along the path: only the asymmetry is
    # asserted; the IOC's recovery of the values is the test above)
    before, after = skill.reward_.swerve["cup"]
    assert after > 1.5 * before
    # the swerve (its stretches, then its widths refitted; Q the thesis fit's) replans the held-out
    # demonstrations well, and at less than SWERVE_MARGIN of the error of the symmetric response
    candidates = selection["candidates"]
    assert candidates["path:window/swerve"]["improvement_median"] > 85.0
    assert candidates["path:window/swerve"]["error"] < SWERVE_MARGIN * candidates["window"]["error"]


@pytest.mark.slow  # a skill's whole fit and model choice per person (about 3 s quiet each)
@pytest.mark.parametrize(
    ("swerve", "chosen"),
    [
        # Starts late and returns slowly, its stretches on the walls (1/5, 5): the stretches
        # alone lower the training loss to 0.47 of the thesis fit's (a screen at 0.45 of the
        # training loss dropped it), held out its error is 0.28 of the others'.
        ([0.2, 5.0], True),
        # The thesis's model: the swerve is a candidate (its stretches lower the training
        # loss a little, to 0.97) and replans held out no closer than the thesis's bump.
        (None, False),
        # Stretched alike before and after: a wider symmetric bump, which the thesis's
        # precisions express (training loss 0.99, held-out error the same).
        ([2.0, 2.0], False),
    ],
)
def test_the_swerve_is_chosen_for_a_swerve_person_and_not_for_a_thesis_one(swerve, chosen) -> None:
    person = Reward(10.0, {"cup": [400.0, 2500.0]}, swerve={"cup": swerve} if swerve else None)
    selection = _skill_of(person).model_selection_
    # a candidate each time, decided by the held-out demonstrations
    assert "path:window/swerve" in selection["candidates"]
    assert selection["swerve_gain"] < 1.0
    assert (selection["chosen"] == "path:window/swerve") is chosen, selection["chosen"]


def test_the_clearance_consistency_is_measured_above_the_noise() -> None:
    from lfdkit.skill.selection import CONSISTENT_CLEARANCE, NOISE_SHARE

    # The thesis's person at 3x noise (probe, seed 0): with no floor the held-out
    # demonstrations are replanned at 5.06e-5 m², with the closest any came at 7.20e-5;
    # the demonstrations' own spread without obstacles is 2.53e-5. Taken whole the ratio
    # is 1.42 (a margin: gaps closed); above the noise it is 4.67 / 2.53 = 1.85 (a reward).
    names = ["window", "window+demonstrated", "window+closest"]
    candidates = [
        {"route": "window", "frame": "world", "floor": f}
        for f in ("none", "demonstrated", "closest")
    ]
    scores = {"window": {"mse": 5.295e-5}, "window+demonstrated": {"mse": 5.295e-5}}
    scores["window+closest"] = {"mse": 7.20e-5}
    default, ratio = Skill._default_model(candidates, names, scores, 5.06e-5)
    assert (default, ratio) == ("window+demonstrated", pytest.approx(7.20 / 5.06))
    assert ratio < CONSISTENT_CLEARANCE
    default, ratio = Skill._default_model(candidates, names, scores, 5.06e-5, 2.53e-5)
    assert (default, ratio) == ("window", pytest.approx(4.67 / 2.53))
    # A spread larger than the error itself (starts and goals that differ, not noise): at
    # most NOISE_SHARE of the error with no floor is taken away.
    _, ratio = Skill._default_model(candidates, names, scores, 5.06e-5, 1.0)
    floor = NOISE_SHARE * 5.06e-5
    assert ratio == pytest.approx((7.20e-5 - floor) / (5.06e-5 - floor))
    # No spread known (a path given, an older skill): as before.
    _, ratio = Skill._default_model(candidates, names, scores, 5.06e-5, None)
    assert ratio == pytest.approx(7.20 / 5.06)


def test_a_skill_records_the_spread_of_its_demonstrations_without_obstacles() -> None:
    # Demonstrations 0 and +-2 mm sin(pi x) about the path: mean square 2/3 of 2e-6 m²,
    # times 3/2 for a path fitted to them: 2e-6 m².
    x = np.linspace(0.0, 1.0, 100)
    skill = Skill().fit([np.column_stack([x, 0.002 * s * np.sin(np.pi * x)]) for s in (-1, 0, 1)])
    assert skill.mimic_info_["spread_mse"] == pytest.approx(2e-6, rel=0.05)
    mm = Skill(units="mm").fit(
        [np.column_stack([1000 * x, 2.0 * s * np.sin(np.pi * x)]) for s in (-1, 0, 1)]
    )
    assert mm.mimic_info_["spread_mse"] == pytest.approx(2.0, rel=0.05)  # mm²
    # From one start and to one goal, the noise is the spread.
    assert skill.mimic_info_["noise_mse"] == pytest.approx(2e-6, rel=0.05)


def test_the_noise_of_demonstrations_from_spread_starts_is_not_their_starts_spread() -> None:
    # Lines from starts 10 cm apart to one goal with +-2 mm sin(pi x) on three of four:
    # mean square 3/4 of 2e-6 m², times 4/3 (fitted): 2e-6 m². Against the one learned
    # path their spread is the starts' (5.6e-3 m²), which made the gap allowance
    # (GAP_STANDARD_ERRORS of it) close gaps 20 cm wide (boxes_sides, 3-D).
    x = np.linspace(0.0, 1.0, 100)
    demos = [
        np.column_stack([x, y0 * (1.0 - x) + 0.002 * s * np.sin(np.pi * x)])
        for y0, s in zip((-0.15, -0.05, 0.05, 0.15), (-1, 1, 0, -1), strict=True)
    ]
    skill = Skill().fit(demos)
    assert skill.mimic_info_["spread_mse"] > 1e-3
    assert skill.mimic_info_["noise_mse"] == pytest.approx(2e-6, rel=0.05)
