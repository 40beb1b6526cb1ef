"""The behaviour model's ranking over cross-validation folds (lfdkit.skill.selection)."""

import numpy as np
import pytest

from lfdkit.skill.selection import (
    FOLD_TRIM,
    SELECTION_MARGIN,
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
