"""The position and orientation DMPs share one base: the same parameters, defaults and refusals."""

from __future__ import annotations

import inspect

import numpy as np
import pytest

from lfdkit.imitate import DMP, QuaternionDMP
from lfdkit.imitate.primitive import Primitive


def _defaults(cls: type) -> dict:
    return {
        name: p.default
        for name, p in inspect.signature(cls.__init__).parameters.items()
        if name != "self"
    }


def test_both_dmps_have_the_primitive_parameters_with_its_defaults():
    shared = _defaults(Primitive)
    for cls in (DMP, QuaternionDMP):
        assert issubclass(cls, Primitive)
        own = _defaults(cls)
        assert {name: own[name] for name in shared} == shared
    assert set(_defaults(DMP)) - set(shared) == {"scaling", "end"}


def test_orientation_dmp_hands_its_parameters_to_the_position_dmp():
    q = np.tile([0.0, 0.0, 0.0, 1.0], (20, 1))
    angle = np.linspace(0.0, 1.0, 20)
    q[:, 2], q[:, 3] = np.sin(angle / 2), np.cos(angle / 2)
    params = {"n_basis": 12, "k": 100.0, "c": 20.0, "alpha": 3.0, "tau": 2.0}
    dmp = QuaternionDMP(**params, regularization=1e-6, basis_tol=0.5).fit(q)
    inner = dmp.dmp_.get_params()
    assert {name: inner[name] for name in dmp.primitive_params()} == dmp.primitive_params()
    assert (inner["scaling"], inner["end"]) == ("translate", "rest")
    assert dmp.dmp_.alpha_ == 3.0


@pytest.mark.parametrize(
    ("name", "value", "message"),
    [
        ("n_basis", "many", r"^n_basis: expected an integer or 'auto', got 'many'$"),
        ("n_basis", 3, r"^n_basis: end='rest' puts 3 constraints"),
        ("basis_tol", 2.0, r"^basis_tol: expected a fraction of the path's extent"),
        ("k", -1.0, r"^k: must be > 0, got -1.0$"),
        ("alpha", 0.0, r"^alpha: must be > 0, got 0.0$"),
        ("tau", 1e9, r"^tau: expected 1e-06 to 1e\+06, got 1e\+09$"),
        ("regularization", -1.0, r"^regularization: must be >= 0, got -1.0$"),
    ],
)
def test_both_dmps_refuse_a_bad_shared_parameter_alike(name, value, message):
    path = np.c_[np.linspace(0.0, 1.0, 10), np.linspace(0.0, 0.5, 10) ** 2]
    quaternions = np.tile([0.0, 0.0, 0.0, 1.0], (10, 1))
    with pytest.raises(ValueError, match=message):
        DMP(**{name: value}).fit(path)
    with pytest.raises(ValueError, match=message):
        QuaternionDMP(**{name: value}).fit(quaternions)
