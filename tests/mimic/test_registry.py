"""A new mimicking method is its class and one ``register`` call: everything finds it."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.base import BaseEstimator

from lfdkit.mimic import MIMIC_METHODS, Mimic, MimicMethod, MimicSettings, register
from lfdkit.mimic.orientation import check_one_motion


class FirstDemo(BaseEstimator):
    """A deliberately simple method: the first demonstration, resampled."""

    def __init__(self, n_points: int = 100) -> None:
        self.n_points = n_points

    def fit(self, demos, y=None) -> FirstDemo:
        from lfdkit.core.geometry import resample

        self.path_ = resample(np.asarray(demos[0], dtype=float), self.n_points)
        self.reversed_ = np.zeros(len(demos), dtype=bool)
        self.length_ratio_ = check_one_motion(self.path_, demos, "first demo")
        self.converged_ = True
        return self


@pytest.fixture
def first_demo():
    method = MimicMethod(
        key="first_demo",
        label="first demonstration",
        color="#123456",
        build=lambda settings: FirstDemo(n_points=settings.n_points),
        diagnostics=lambda fitted: {"converged": fitted.converged_},
    )
    register(method)
    yield method
    del MIMIC_METHODS[method.key]


def _demos() -> list[np.ndarray]:
    x = np.linspace(0.0, 1.0, 30)
    return [np.column_stack((x, 0.3 * np.sin(3 * x) + dy)) for dy in (-0.02, 0.0, 0.02)]


def test_every_builtin_follows_the_contract() -> None:
    demos = _demos()
    for method in MIMIC_METHODS.values():
        fitted = method.build(MimicSettings(n_points=40, random_state=0)).fit(demos)
        assert isinstance(fitted, Mimic), method.key
        assert fitted.path_.shape == (40, 2), method.key
        assert fitted.reversed_.shape == (3,)
        assert fitted.length_ratio_ == pytest.approx(1.0, abs=0.05), method.key
        # Close to the middle demonstration, start to end.
        assert np.abs(fitted.path_[[0, -1]] - demos[1][[0, -1]]).max() < 0.05, method.key


def test_a_registered_method_is_found_by_skill_cli_evaluation_and_plots(first_demo) -> None:
    from lfdkit.app.cli.common import LazyChoices as _LazyChoices
    from lfdkit.app.cli.common import _mimic_keys
    from lfdkit.app.evaluation import lfdkit_methods
    from lfdkit.app.plot import method_color
    from lfdkit.skill import Skill

    skill = Skill(mimic="first_demo").fit_path(_demos())
    np.testing.assert_allclose(skill.path_[0], _demos()[0][0])
    assert skill.mimic_info_["method"] == "first_demo"
    choices = _LazyChoices(_mimic_keys)  # what `lfdkit learn --mimic` accepts
    assert "first_demo" in choices and "first_demo" in list(choices)
    assert "first demonstration" in lfdkit_methods()
    assert method_color("first demonstration") == "#123456"


def test_register_refuses_a_taken_key_or_label(first_demo) -> None:
    with pytest.raises(ValueError, match="key 'first_demo' is already registered"):
        register(first_demo)
    with pytest.raises(ValueError, match="label 'Mean-Path' is already registered"):
        register(MimicMethod("other", "Mean-Path", "k", first_demo.build))
    with pytest.raises(ValueError, match="unknown settings"):
        register(MimicMethod("other", "other", "k", first_demo.build, uses=("n_pts",)))
