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


# ----------------------------------------------------------------- the units rule (issue 31)
from lfdkit.core.units import (  # noqa: E402
    MAX_EXTENT_M,
    MAX_MEAN_SPEED_M_S,
    MIN_EXTENT_CM,
    MIN_EXTENT_M,
    implausible_units,
    likely_units,
)


@pytest.mark.parametrize(
    ("extent", "units", "speed", "flagged"),
    [
        (0.8, "m", None, False),  # the shipped sweep
        (11.4, "m", None, False),  # lfdkit's largest synthetic "metre" set
        (MAX_EXTENT_M, "m", None, False),  # the bound itself passes
        (MAX_EXTENT_M * 1.001, "m", None, True),
        (800.0, "m", None, True),  # an 80 cm sweep in mm, read as metres
        (80.0, "m", None, True),  # ... in cm
        (2000.0, "mm", None, False),  # 2 m in mm
        (0.8, "mm", None, True),  # metres read as mm: 0.8 mm
        (MIN_EXTENT_M, "m", None, False),
        (0.8, "m", MAX_MEAN_SPEED_M_S, False),
        (0.8, "m", MAX_MEAN_SPEED_M_S * 1.001, True),  # faster than a hand
        (15.0, "m", 150.0, True),  # 15 cm in cm, timed over 1 s: the speed gives it away
        (15.0, "m", None, False),  # ... untimed, it is not caught (the rule's stated gap)
        (300.0, "mm", 200.0, False),
        (0.8, "cm", None, True),  # a 0.8 m reach in metres read as cm (passed at 2f1f475)
        (MIN_EXTENT_CM * 0.999, "cm", None, True),
        (MIN_EXTENT_CM, "cm", None, False),  # the bound itself passes
        (80.0, "cm", None, False),  # the shipped sweep in cm
        (5.0, "mm", None, False),  # a real 5 mm task in mm
        (1.5, "mm", None, False),
    ],
)
def test_the_units_rule_flags_only_implausible_sizes_and_speeds(
    extent, units, speed, flagged
) -> None:
    reason = implausible_units(extent, units, speed)
    assert (reason is not None) is flagged
    if flagged:
        assert f"{extent:.4g} {units}" in reason or f"{speed:.4g} {units}/s" in reason


@pytest.mark.parametrize(
    ("extent", "units", "likely"),
    [
        (800.0, "m", "mm"),
        (80.0, "m", "cm"),
        (300.0, "m", "mm"),
        (30.0, "m", "cm"),
        (0.8, "mm", "m"),
    ],
)
def test_the_likely_unit_brings_the_span_nearest_half_a_metre(extent, units, likely) -> None:
    assert likely_units(extent, units) == likely


def test_no_built_in_data_set_trips_the_units_rule() -> None:
    """False positives on every set lfdkit ships or loads (LASA when installed): none."""
    np = pytest.importorskip("numpy")
    from lfdkit.core.geometry import path_length
    from lfdkit.datasets import catalog, dataset_demos

    checked = 0
    for info in catalog():
        data = dataset_demos(info.name)
        extent = max(float(np.ptp(d, axis=0).max()) for d in data.demos)
        speeds = [
            path_length(d) / (t[-1] - t[0])
            for d, t in zip(data.demos, data.times or [None] * len(data.demos), strict=True)
            if t is not None
        ]
        assert implausible_units(extent, info.units, max(speeds, default=None)) is None, info.name
        checked += 1
    assert checked >= 17


@pytest.mark.parametrize(
    ("point", "units", "likely"),
    [
        ([0.36, 0.5], "mm", "m"),  # a goal typed in metres for a millimetre skill
        ([360.0, 500.0], "m", "mm"),  # the reverse: --units m on millimetre numbers
        ([360.0, 500.0], "mm", None),  # among the demonstrations
        ([1500.0, 500.0], "mm", None),  # far, but no unit brings it among them
        ([0.0, 0.0], "mm", None),  # the origin is the origin in every unit
    ],
)
def test_a_point_is_misplaced_only_when_another_unit_brings_it_among_the_demonstrations(
    point, units, likely
) -> None:
    from lfdkit.core.units import misplaced_units

    factor = {"mm": 1.0, "m": 1e-3, "cm": 0.1}[units]  # the box in the point's unit
    low, high = [factor * -400.0, factor * 450.0], [factor * 400.0, factor * 500.0]
    assert misplaced_units(point, low, high, units) == likely


@pytest.mark.parametrize(
    ("point", "size", "likely"),
    [
        ([0.3, 0.2], 0.2, "m"),  # a 20 cm carton typed in metres near the skill's origin
        ([300.0, 200.0], 200.0, None),  # the same carton in millimetres
        ([0.3, 0.2], 0.0, None),  # a point obstacle has no size to tell
        ([0.3, 0.2], 0.9, "cm"),  # 900 mm in metres is larger than the workspace; 9 mm in cm
        ([3.0, 2.0], 0.5, "cm"),  # in metres it would stand far outside the workspace
        ([0.3, 0.2], 0.0005, None),  # no unit makes it 1 mm
    ],
)
def test_an_obstacle_too_small_for_its_unit_is_misplaced_where_another_unit_fits_it(
    point, size, likely
) -> None:
    from lfdkit.core.units import misplaced_units

    # A reach from the robot's base, in millimetres: the origin is inside the workspace.
    assert misplaced_units(point, [-400.0, 0.0], [400.0, 500.0], "mm", size=size) == likely
