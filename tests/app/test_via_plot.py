"""The via-point figure: the band is the demonstrations' spread, pinched where it is pinned."""

from __future__ import annotations

import matplotlib
import numpy as np
import pytest

from lfdkit.app.via_plot import via_figure
from lfdkit.skill import Skill
from tests.skill.test_via import VIA, sweeps

matplotlib.use("Agg")


@pytest.fixture(scope="module")
def skill() -> Skill:
    return Skill(mimic="average").fit_path(sweeps())


def band_width_at(patch, point: np.ndarray) -> float:
    """Width of a band polygon (upper edge, then lower reversed) across the path at ``point``."""
    outline = patch.get_xy()
    if len(outline) % 2:
        outline = outline[:-1]  # the first vertex repeated to close it
    half = len(outline) // 2
    upper, lower = outline[:half], outline[half:][::-1]
    k = int(np.argmin(np.linalg.norm(0.5 * (upper + lower) - point, axis=1)))
    return float(np.linalg.norm(upper[k] - lower[k]))


def test_the_band_is_the_spread_and_pinched_at_the_via_point(skill, tmp_path) -> None:
    free, bent = skill.via_path(), skill.via_path(VIA)
    fig = via_figure(free, bent, VIA, plan=skill.plan(via=VIA).points, demos=sweeps())
    fig.savefig(tmp_path / "via.png", dpi=40)
    ax = fig.axes[0]
    spread, left = ax.patches[:2]
    # At the top the demonstrations' heights (5 to 15 cm) spread ±2σ = ±7.9 cm.
    width = band_width_at(spread, free.points[np.argmin(np.abs(free.phases - 0.5))])
    assert width == pytest.approx(4 * np.std([0.05, 0.08, 0.1, 0.12, 0.15], ddof=1), rel=0.05)
    assert band_width_at(left, np.asarray(VIA[0][1])) < 1e-6
    labels = {t.get_text() for t in ax.get_legend().get_texts()}
    assert {"via-points", "plan", "nominal", "demonstrations' spread (±2 std)"} <= labels
    assert ax.get_aspect() == 1.0
    assert ax.get_xlabel() == "x [m]"
