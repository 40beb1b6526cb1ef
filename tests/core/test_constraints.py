"""Declarative parameter checks: one-line refusals, and the Estimator's walk of the tables."""

from __future__ import annotations

from typing import Any, ClassVar

import numpy as np
import pytest

from lfdkit.core.constraints import Checked, InstanceOf, Integer, OneOf, Real
from lfdkit.core.estimator import Estimator


@pytest.mark.parametrize(
    ("constraint", "value", "error", "message"),
    [
        (Real(), 0.0, ValueError, r"^x: must be > 0, got 0.0$"),
        (Real(allow_zero=True), -1, ValueError, r"^x: must be >= 0, got -1.0$"),
        (Real(), float("nan"), ValueError, r"^x: must be finite, got nan$"),
        (Real(), None, TypeError, r"^x: expected a number, got None$"),
        (
            Real(maximum=1.0, meaning="a fraction"),
            2.0,
            ValueError,
            r"^x: expected a fraction, 0 < x <= 1, got 2$",
        ),
        (
            Real(options=("auto",)),
            "soon",
            ValueError,
            r"^x: expected a number or 'auto', got 'soon'$",
        ),
        (Integer(), 2.5, TypeError, r"^x: expected an integer, got 2.5$"),
        (Integer(), True, TypeError, r"^x: expected an integer, got True$"),
        (Integer(), 0, ValueError, r"^x: must be > 0, got 0$"),
        (Integer(minimum=0), -1, ValueError, r"^x: must be >= 0, got -1$"),
        (Integer(maximum=10), 11, ValueError, r"^x: expected 1 to 10, got 11$"),
        (Integer(minimum=2), 1, ValueError, r"^x: expected 2 to 1,000,000, got 1$"),
        (
            Integer(options=("auto",)),
            "many",
            ValueError,
            r"^x: expected an integer or 'auto', got 'many'$",
        ),
        (OneOf(("a", "b")), "c", ValueError, r"^x: expected one of 'a', 'b', got 'c'$"),
        (InstanceOf(dict), [], TypeError, r"^x: expected a dict, got list$"),
    ],
)
def test_each_constraint_refuses_on_one_line_naming_the_argument(constraint, value, error, message):
    with pytest.raises(error, match=message):
        constraint(value, "x")


def test_constraints_return_the_checked_value():
    assert Real()(np.float32(2.5), "x") == 2.5 and type(Real()(3, "x")) is float
    assert Integer()(np.int64(4), "x") == 4 and type(Integer()(np.int64(4), "x")) is int
    assert Integer(options=("auto",))("auto", "x") == "auto"
    assert Real(options=("auto",))("auto", "x") == "auto" and Real(options=("auto",))(2, "x") == 2.0
    assert Real(optional=True)(None, "x") is None
    assert InstanceOf(dict, optional=True)(None, "x") is None
    assert Checked(lambda value, name: value * 2)(3, "x") == 6
    assert Checked(lambda value, name: 1 / 0, optional=True)(None, "x") is None


class _Base(Estimator):
    _parameter_constraints: ClassVar[dict[str, Any]] = {"a": Integer(), "b": Real()}

    def __init__(self, a=1, b=1.0):
        self.a = a
        self.b = b


class _Child(_Base):
    _parameter_constraints: ClassVar[dict[str, Any]] = {"c": OneOf(("x", "y"))}

    def __init__(self, a=1, b=1.0, c="x"):
        super().__init__(a=a, b=b)
        self.c = c


def test_validate_params_checks_the_bases_rows_first_and_returns_the_values():
    assert _Child(a=np.int64(3), b=2, c="y")._validate_params() == {"a": 3, "b": 2.0, "c": "y"}
    assert list(_Child()._validate_params()) == ["a", "b", "c"]
    with pytest.raises(ValueError, match=r"^a: must be > 0"):
        _Child(a=0, c="z")._validate_params()  # the base's row is checked first
    with pytest.raises(ValueError, match=r"^c: expected one of 'x', 'y', got 'z'$"):
        _Child(c="z")._validate_params()
    assert Estimator()._validate_params() == {}
