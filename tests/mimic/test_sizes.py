"""Absurd sizes are errors naming the argument, never a MemoryError (issue 13)."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.mimic import GMR, NLPCA, MeanPath, pointwise_average, select_n_components

_U = np.linspace(0.0, 1.0, 30)
DEMOS = [np.c_[_U, np.sin(np.pi * _U) + 0.01 * k] for k in range(3)]


@pytest.mark.parametrize(
    ("fit", "match"),
    [
        (lambda: MeanPath(n_points=10**12).fit(DEMOS), r"n_points: expected 2 to 1,000,000"),
        (lambda: pointwise_average(DEMOS, 10**12), r"n_points: expected 2 to 1,000,000"),
        (lambda: pointwise_average(DEMOS, 1), r"n_points: expected 2"),
        (lambda: GMR(n_components=10**9).fit(DEMOS), r"n_components: expected 1 to 1,000, got"),
        (lambda: GMR(n_init=10**9).fit(DEMOS), r"n_init: expected 1 to 1,000, got"),
        (lambda: GMR(n_components=3, random_state=0).fit(DEMOS).path(10**12), "n_points"),
        (lambda: select_n_components(DEMOS, range(1, 10**15)), "candidates: at most 1000"),
        (lambda: NLPCA(n_points=10**12).fit(DEMOS), r"n_points: expected 2 to 1,000,000"),
        (lambda: NLPCA(n_hidden=10**9).fit(DEMOS), r"n_hidden: expected 1 to 1,000, got"),
        (lambda: NLPCA(n_restarts=10**9).fit(DEMOS), r"n_restarts: expected 1 to 1,000, got"),
    ],
)
def test_absurd_sizes_are_errors(fit, match):
    with pytest.raises(ValueError, match=match):
        fit()


def test_the_caps_themselves_are_allowed():
    assert pointwise_average(DEMOS, 1_000_000).shape == (1_000_000, 2)
    assert GMR(n_components=3, random_state=0).fit(DEMOS).path(1_000_000).shape == (1_000_000, 2)
