"""The fidelity benchmark's people (benchmarks/emulate/people.py) have their stated behaviour."""

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

from lfdkit.emulate.metrics import clearance
from lfdkit.model.scene import Scene

_FILE = Path(__file__).resolve().parents[2] / "benchmarks" / "emulate" / "people.py"


def _load():
    # Loaded by path: the benchmarks folder is not a package of the library.
    spec = importlib.util.spec_from_file_location("_fidelity_people", _FILE)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


P = _load()


def _cases(family, seed, n, scale=1.0):
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        case = P.draw_case(family, rng, scale)
        if case is not None:
            out.append(case)
    return out


def test_thesis_person_peak_offset_is_the_closed_form_optimum():
    # Obstacle on a straight nominal: at its station the reward −Q e² − exp(−P e²) peaks at
    # e* = sqrt(ln(P/Q) / P); the MPC's path reaches it to the 1 mm grid.
    person = P.ThesisPerson()
    nominal = P.task_nominal("train")
    for label in P.CLASSES:
        path = person.clean(nominal, P.make_scene([(label, (0.4, 0.0))]))
        lateral = person.precisions[label][1, 1]
        expected = np.sqrt(np.log(lateral / person.q) / lateral)
        assert abs(np.abs(path[:, 1]).max() - expected) <= 1.01e-3


def test_thesis_person_is_deterministic_for_a_seed():
    a = [P.ThesisPerson().clean(c.nominal, c.scene) for c in _cases("pair", 3, 2)]
    b = [P.ThesisPerson().clean(c.nominal, c.scene) for c in _cases("pair", 3, 2)]
    for x, y in zip(a, b, strict=True):
        np.testing.assert_array_equal(x, y)


@pytest.mark.parametrize("scale", [1.0, 1000.0])
def test_margin_person_keeps_its_margin_per_class(scale):
    person = P.MarginPerson(scale)
    for case in _cases("pair", 1, 2, scale) + _cases("clutter", 2, 1, scale):
        path = person.clean(case.nominal, case.scene)
        gaps = clearance(path, case.scene)
        margins = np.array([person.margins[o.label] for o in case.scene])
        # Chords between the 100 samples cut a disc by at most 0.3 mm (per metre).
        assert np.all(gaps >= margins - 3e-4 * scale)
        # ... and is tight on at least one obstacle it had to avoid (the shortest path).
        if np.any(clearance(case.nominal, case.scene) < margins):
            assert np.min(gaps - margins) <= 2e-3 * scale


def test_people_in_millimetres_move_as_in_metres():
    case_m = _cases("pair", 4, 1)[0]
    case_mm = _cases("pair", 4, 1, 1000.0)[0]
    # The late person's arithmetic has no ties: its path is the metre one times 1000.
    late_m = P.LatePerson().clean(case_m.nominal, case_m.scene)
    late_mm = P.LatePerson(1000.0).clean(case_mm.nominal, case_mm.scene)
    np.testing.assert_allclose(late_mm, 1000.0 * late_m, atol=1e-6)
    # The margin person's shortest path has near ties on the grid: rounding (different in
    # mm) must not break them, or the same person demonstrates another path in mm.
    for case_m, case_mm in zip(
        _cases("pair", 4, 1) + _cases("train", 1, 2),
        _cases("pair", 4, 1, 1000.0) + _cases("train", 1, 2, 1000.0),
        strict=True,
    ):
        margin_m = P.MarginPerson().clean(case_m.nominal, case_m.scene)
        margin_mm = P.MarginPerson(1000.0).clean(case_mm.nominal, case_mm.scene)
        np.testing.assert_allclose(margin_mm, 1000.0 * margin_m, rtol=0.0, atol=1e-6)


def test_people_follow_the_nominal_without_obstacles():
    nominal = P.task_nominal("arc")
    for kind in P.KINDS:
        path = P.make_person(kind).clean(nominal, Scene())
        # Resampled at equal arc length: on the nominal to well below the 1 mm grid.
        assert np.abs(np.linalg.norm(path - [0.0, 0.5], axis=1) - 0.5).max() < 2e-4, kind


def test_field_person_is_collision_free_and_reaches_the_goal():
    person = P.FieldPerson()
    for case in _cases("single", 5, 2) + _cases("pair", 6, 1):
        path = person.clean(case.nominal, case.scene)
        assert clearance(path, case.scene).min() >= P.MIN_CLEARANCE
        assert np.linalg.norm(path[-1] - case.goal) < 5e-3


def test_late_person_does_not_react_before_its_lookahead():
    person = P.LatePerson()
    nominal = P.task_nominal("train")
    for label in P.CLASSES:
        path = person.clean(nominal, P.make_scene([(label, (0.5, 0.01))]))
        width = P.RADIUS[label] + person.clearances[label]
        before = path[:, 0] < 0.5 - width - person.lookahead - 0.01
        assert np.all(path[before, 1] == 0.0)
        # It passes on the side away from the obstacle, at its clearance.
        assert clearance(path, P.make_scene([(label, (0.5, 0.01))]))[0] == pytest.approx(
            person.clearances[label], abs=1.5e-3
        )


def test_noise_has_its_level_and_keeps_the_ends():
    path = P.task_nominal("train", n=100)
    one = P.add_noise(path, P.NOISE, np.random.default_rng(7))
    two = P.add_noise(path, 2 * P.NOISE, np.random.default_rng(7))
    np.testing.assert_allclose(one[[0, -1]], path[[0, -1]], atol=1e-12)
    # Lateral (y) offset: tapered, so its sd is a little below the level; 2× is twice 1×
    # (to the resampling at equal arc length, which moves points along the path).
    assert 0.6 * P.NOISE < one[:, 1].std() < 1.01 * P.NOISE
    np.testing.assert_allclose(two[:, 1], 2 * one[:, 1], atol=0.05 * P.NOISE)
    assert not np.allclose(two[:, 1], 3 * one[:, 1], atol=0.05 * P.NOISE)
