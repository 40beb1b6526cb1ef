"""lfdkit's estimators keep scikit-learn's conventions without deriving from it."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.base import clone
from sklearn.exceptions import NotFittedError

from lfdkit.imitate import DMP
from lfdkit.mimic import GMR, NLPCA, ArcLengthAverage, MeanPath
from lfdkit.skill import Skill


@pytest.mark.parametrize("cls", [MeanPath, GMR, NLPCA, ArcLengthAverage, DMP, Skill])
def test_params_round_trip_and_clone(cls):
    model = cls()
    params = model.get_params()
    assert list(params) == sorted(params)  # every constructor parameter, by name
    twin = clone(model)
    assert twin is not model and twin.get_params() == params
    assert repr(cls()) == f"{cls.__name__}()"


def test_set_params_repr_and_errors():
    model = MeanPath().set_params(n_points=50, center="median")
    assert model.n_points == 50 and model.center == "median"
    assert repr(model) == "MeanPath(center='median', n_points=50)"
    assert "init=array of shape (3, 2)" in repr(MeanPath(init=np.zeros((3, 2))))
    with pytest.raises(ValueError, match="Invalid parameter 'centre'"):
        MeanPath().set_params(centre="mean")
    assert MeanPath().set_params().get_params() == MeanPath().get_params()


def test_not_fitted_is_scikit_learns_error():
    with pytest.raises(NotFittedError, match="not fitted"):
        GMR().path()
    with pytest.raises(NotFittedError, match="skill: not fitted"):
        Skill().plan(goal=[1.0, 0.0])
