"""core.validation's state readers: one-line errors naming the field, for any from_state."""

from __future__ import annotations

import math

import pytest

from lfdkit.core.validation import check_state_number, made_from_state
from lfdkit.imitate import ProMP


def test_made_from_state_builds_the_estimator_of_its_parameters():
    made = made_from_state(ProMP, {"params": {"n_basis": 7}, "width": 0.1}, "promp", ("width",))
    assert isinstance(made, ProMP) and made.n_basis == 7
    assert not hasattr(made, "weights_mean_")  # unfitted: the caller sets the state


@pytest.mark.parametrize(
    ("state", "message"),
    [
        ([], r"^promp: expected an object, got list$"),
        ({"width": 0.1}, r"^promp\.params: missing field$"),
        ({"params": {}}, r"^promp\.width: missing field$"),
        ({"params": [], "width": 0.1}, r"^promp\.params: expected an object, got \[\]$"),
        ({"params": {"n_basis": 1}, "width": 0.1}, r"^promp\.params: n_basis"),
        ({"params": {"colour": 1}, "width": 0.1}, r"^promp\.params: .*colour"),
    ],
)
def test_made_from_state_refuses_in_one_line(state, message):
    with pytest.raises(ValueError, match=message) as info:
        made_from_state(ProMP, state, "promp", ("width",))
    assert "\n" not in str(info.value)


def test_check_state_number_reads_numbers_and_names_the_bad_ones():
    assert check_state_number({"p": 2}, "p", "rhythm", positive=True) == 2.0
    assert check_state_number({"r": 0.0}, "r", "rhythm", positive=False) == 0.0
    for value, positive, wanted in (
        (True, False, "a number"),
        ("1", False, "a number"),
        ([1.0], False, "a number"),
        (0.0, True, "a positive number"),
        (-1e-9, False, "a number >= 0"),
        (math.nan, False, "a number >= 0"),
        (math.inf, True, "a positive number"),
    ):
        with pytest.raises(ValueError, match=rf"^rhythm\.x: expected {wanted}, got "):
            check_state_number({"x": value}, "x", "rhythm", positive=positive)


def test_a_transposed_demonstration_is_named_with_the_fix() -> None:
    import numpy as np

    from lfdkit.core.validation import check_demos

    demo = np.c_[np.linspace(0.0, 1.0, 50), np.zeros(50)]
    with pytest.raises(
        ValueError, match=r"^demos\[1\]: got shape \(2, 50\), which looks transposed"
    ):
        check_demos([demo, demo.T], "demos")
    with pytest.raises(ValueError, match=r"at row 3; remove or interpolate"):
        check_demos([np.where(np.arange(50)[:, None] == 3, np.nan, demo)], "demos")
