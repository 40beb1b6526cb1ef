"""Length units (lfdkit.core.units): the known units and exact conversion factors."""

from __future__ import annotations

import pytest

from lfdkit.core.units import UNITS, check_units, conversion_factor


def test_the_known_units() -> None:
    assert UNITS == ("m", "cm", "mm")
    for units in UNITS:
        assert check_units(units) == units


@pytest.mark.parametrize(
    ("source", "target", "factor"),
    [
        ("m", "mm", 1000.0),
        ("m", "cm", 100.0),
        ("cm", "mm", 10.0),
        ("mm", "m", 0.001),
        ("cm", "m", 0.01),
        ("mm", "cm", 0.1),
        ("m", "m", 1.0),
        ("mm", "mm", 1.0),
    ],
)
def test_conversion_factors_are_the_decimal_ones_exactly(source, target, factor) -> None:
    # Exactly the float of the decimal: a conversion adds no more than one rounding.
    assert conversion_factor(source, target) == factor
    assert conversion_factor(source, target) * conversion_factor(target, source) == pytest.approx(
        1.0, rel=1e-16
    )


@pytest.mark.parametrize("bad", ["inch", "M", "", " mm", None, 1.0, b"m"])
def test_an_unknown_unit_is_refused_naming_the_argument_and_the_choices(bad) -> None:
    with pytest.raises(ValueError, match=r"^units: expected one of 'm', 'cm', 'mm', got "):
        check_units(bad)
    with pytest.raises(ValueError, match=r"^to_units: expected one of"):
        conversion_factor("m", bad)
    with pytest.raises(ValueError, match=r"^from_units: expected one of"):
        conversion_factor(bad, "m")
    with pytest.raises(ValueError, match=r"^scale: expected one of"):
        check_units(bad, "scale")
