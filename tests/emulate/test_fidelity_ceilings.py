"""The fidelity benchmark's ceilings (benchmarks/emulate/fidelity.py) mean what they say."""

import importlib
import sys
from pathlib import Path

import numpy as np
import pytest

_ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def fidelity():
    # The benchmark is a package of the repository, not of the library.
    sys.path.insert(0, str(_ROOT))
    try:
        return importlib.import_module("benchmarks.emulate.fidelity")
    finally:
        sys.path.remove(str(_ROOT))


def _arc(n=400, radius=0.5):
    a = np.linspace(0.0, 0.5 * np.pi, n)
    return np.column_stack((radius * np.sin(a), radius * (1.0 - np.cos(a))))


def _offset(nominal, bump):
    """``nominal`` with a lateral bump (its left normal times ``bump(u)``), 100 points."""
    from lfdkit.core.geometry import left_normals, resample

    points = resample(nominal, 100)
    u = np.linspace(0.0, 1.0, 100)
    return points + bump(u)[:, None] * left_normals(points)


def test_carried_onto_a_shifted_nominal_is_the_path_shifted(fidelity):
    nominal = _arc()
    path = _offset(nominal, lambda u: 0.03 * np.sin(np.pi * u) ** 2)
    shift = np.array([0.2, -0.1])
    moved = fidelity.carried(path, nominal, nominal + shift, 1.0)
    # Projection is on 2000 stations (0.4 mm apart on this 0.79 m arc).
    np.testing.assert_allclose(moved, path + shift, atol=5e-4)


def test_carried_keeps_the_lateral_offset_onto_another_nominal(fidelity):
    from lfdkit.core.geometry import left_normals

    straight = np.column_stack((np.linspace(0.0, 0.8, 400), np.zeros(400)))
    bump = lambda u: 0.04 * np.exp(-(((u - 0.5) / 0.1) ** 2))  # noqa: E731
    path = _offset(straight, bump)  # 4 cm left of a straight line at its middle
    onto = _arc(radius=0.8 / (0.5 * np.pi))  # same length, turning left
    moved = fidelity.carried(path, straight, onto, 1.0)
    # At the middle: 4 cm along the arc's left normal, i.e. towards the arc's centre.
    middle = _offset(onto, lambda u: 0.0 * u)[50]
    normal = left_normals(_offset(onto, lambda u: 0.0 * u))[50]
    assert float((moved[50] - middle) @ normal) == pytest.approx(
        0.04 * np.exp(-((0.5 / 99 / 0.1) ** 2)), abs=1e-3
    )
    assert float(np.linalg.norm(moved[0] - onto[0])) < 1e-3
    assert float(np.linalg.norm(moved[-1] - onto[-1])) < 1e-3


def test_every_ceiling_is_reported_pooled_and_per_scene(fidelity):
    scores = [
        {
            "mse_mp": 4.0,
            "mse_r": 1.0,
            "pr": 75.0,
            "quiet": False,
            "agree": 1,
            "encounters": 1,
            "collisions": 0,
            "mse_clean": 0.0,
            "mse_clean_goal": 1.0,
            "mse_clean_nominal": 2.0,
        },
        {
            "mse_mp": 1.0,
            "mse_r": 1.0,
            "pr": 0.0,
            "quiet": False,
            "agree": 1,
            "encounters": 1,
            "collisions": 0,
            "mse_clean": 0.5,
            "mse_clean_goal": 0.5,
            "mse_clean_nominal": 0.5,
        },
    ]
    out = fidelity.summary(scores)
    assert out["ceiling_noise"] == pytest.approx(100.0 * (1.0 - 0.5 / 5.0))
    assert out["ceiling_nominal"] == pytest.approx(100.0 * (1.0 - 2.5 / 5.0))
    # Per scene: goal 75 % and 50 %, nominal 50 % and 50 %.
    assert out["ceiling_goal_median"] == pytest.approx(62.5)
    assert out["ceiling_nominal_median"] == pytest.approx(50.0)


def test_person_data_keeps_the_person_it_was_given(fidelity):
    # The probe's variants are people other than their kind's own: the "own" ceiling must
    # run that person, not look its variant name up (it raised for "thesis-noise3").
    person = fidelity.P.make_person("margin")
    data = fidelity.person_data("margin", 0, 1.0, 0, person=person)
    assert data["person"] is person
    assert data["held"] == []


def _thesis_row(fidelity, family_prs):
    """A fitted thesis row: pooled Pr against the recorded and the noise-free path per family."""
    by_family = {f: {} for f in fidelity.P.FAMILIES}
    for f, (pr, clean) in family_prs.items():
        by_family[f] = {"n": 1, "pr_pooled": pr, "pr_pooled_clean": clean, "ceiling_goal": 70.0}
    return {
        "kind": "thesis",
        "n_train": 10,
        "noise": 2.0,
        "held": {},
        "refused": [],
        "fit_s": 1.0,
        "by_family": by_family,
    }


def test_thesis_target_is_checked_against_the_recorded_and_the_noise_free_path(fidelity):
    row = _thesis_row(
        fidelity, {"single": (99.0, 99.5), "pair": (65.0, 94.0), "clutter": (92.0, 88.0)}
    )
    checks = {c["target"]: c for c in fidelity.check_targets([row])}
    recorded = checks["thesis person: pooled Pr >= 90 % in every family"]
    clean = checks["thesis person: pooled Pr >= 90 % in every family, against its noise-free path"]
    assert recorded["value"] == 65.0 and not recorded["pass"] and "pair" in recorded["note"]
    assert clean["value"] == 88.0 and not clean["pass"] and "clutter" in clean["note"]
