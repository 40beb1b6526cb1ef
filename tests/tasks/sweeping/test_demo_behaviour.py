"""The demo's report says the slow return and the sides' clearances (issue 26).

Known values in, the sentences out (lengths in mm, as the report's tables);
results from before them (no ``"behaviour"``) and a skill with neither say
nothing. No demo run: the report's own test checks the run's results carry it.
"""

from __future__ import annotations

from lfdkit.app.report import Report
from lfdkit.tasks.sweeping.demo import _behaviour_sentences

DEMONSTRATED = {"out": 1.0, "back": 0.27, "ratio": 0.12, "count": 8}


def test_report_says_the_slow_return_and_each_sides_clearance() -> None:
    emulate = {
        "ioc": {"demonstrated_return": DEMONSTRATED},
        "behaviour": {
            "return_fraction": 0.18,
            "max_slope": 1.5,
            "sides": {"cup": {"side": "left", "within": 0.09, "clearance": 0.024}},
        },
    }
    assert _behaviour_sentences(emulate) == [
        "Slow return: back at most 0.18 of the step bound (a slope of 0.27 m across per m "
        "along; the demonstrations return 0.12 times as steeply as they swerve).",
        "Plans keep the sides the sweeps kept, the long way round where needed: every 'cup' "
        "on the left (within 90 mm of the path, at least 24 mm from it).",
    ]
    html = Report("t").paragraph(_behaviour_sentences(emulate)[1]).html()
    assert "at least 24 mm from it" in html


def test_report_of_older_results_or_neither_says_nothing() -> None:
    assert _behaviour_sentences({"ioc": {"demonstrated_return": DEMONSTRATED}}) == []
    symmetric = {"return_fraction": 1.0, "max_slope": 1.0, "sides": {}}
    assert _behaviour_sentences({"ioc": None, "behaviour": symmetric}) == []
    # A side from a file before its clearance: where only.
    older = {**symmetric, "sides": {"marker": {"side": "right", "within": 0.05}}}
    assert _behaviour_sentences({"ioc": None, "behaviour": older}) == [
        "Plans keep the sides the sweeps kept, the long way round where needed: every "
        "'marker' on the right (within 50 mm of the path)."
    ]
