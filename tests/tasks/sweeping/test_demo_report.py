"""The report of ``lfdkit demo``: its content, and the page as a browser shows it.

One demo run (``lfdkit demo -v``, the session's ``demo_runs`` fixture, which
the command's test also reads) is checked twice: its results and report as
files (the unseen-scene plans end at the goal, the executed plan is the one in
the table, every section and glossary term is there), and the page rendered
by headless Chromium at a 1280 px wide window (every section present, every
figure loaded and shown at least 600 px wide, at no less than 80 % of its
own size so that its lettering stays legible). The browser test saves a
full-page screenshot as ``report.png`` in its temporary folder and is skipped
when Chromium, its driver or selenium is missing.
"""

from __future__ import annotations

import base64
import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from lfdkit.app.report import PNG_SIGNATURE
from lfdkit.tasks.sweeping import NEW_GOAL
from lfdkit.tasks.sweeping.demo import GLOSSARY

pytestmark = pytest.mark.slow

#: The report's sections, in order.
SECTIONS = [
    "Mimic: the generalized path",
    "Imitate: a DMP to new goals",
    "Emulate: the obstacle reward",
    "Unseen scenes with a new goal",
    "Execution: a simulated UR5 sweeps the cube",
    "Glossary",
    "Files",
]
#: Terms the report uses that its glossary must explain.
TERMS = ["MSE_R", "MSE_Mp", "Pr", "Q", "P", "Distance-Space", "nominal", "e1, e3"]
WINDOW_WIDTH = 1280
#: A figure is shown at least this wide (CSS px) in a 1280 px window...
MIN_SHOWN_WIDTH = 600
#: ... and at no less than this fraction of its own width: its 10 pt lettering stays legible.
MIN_SCALE = 0.8

INSTALL = (
    "needs Chromium and its driver (Debian/Ubuntu: apt-get install chromium chromium-driver) "
    "and selenium (pip install -e '.[test]')"
)


@pytest.fixture(scope="module")
def demo(demo_runs) -> Path:
    """The folder ``lfdkit demo`` wrote (the session's run, shared with the command's test)."""
    assert demo_runs.verbose.returncode == 0, demo_runs.verbose.stderr[-2000:]
    return demo_runs.out


@pytest.fixture(scope="module")
def results(demo: Path) -> dict:
    return json.loads((demo / "results.json").read_text())


# ------------------------------------------------------------------ content
def test_unseen_plans_end_at_the_goal(results):
    rows = results["unseen"]
    assert {row["planner"] for row in rows} == {"learned reward", "true reward", "DMP only"}
    for row in rows:
        assert row["end_to_goal_mm"] <= 1.0, row
    learned = [row for row in rows if row["planner"] == "learned reward"]
    assert all(row["collisions"] == 0 for row in learned)
    # Every row is held to the brush's half-width, the DMP's too (issue 31: a DMP passing
    # 0.1 mm from a cup counted as no collision while the plans kept 25 mm).
    margin = 1e3 * results["execution"]["clearance_m"]
    for row in rows:
        assert row["margin_mm"] == pytest.approx(margin) == pytest.approx(25.0), row
        assert (row["collisions"] > 0) == (row["min_clearance_mm"] < margin - 1e-3), row


def test_results_carry_what_plans_keep_besides_the_reward(results):
    behaviour = results["emulate"]["behaviour"]
    assert 0.0 < behaviour["return_fraction"] <= 1.0 and behaviour["max_slope"] > 0.0
    for preference in behaviour["sides"].values():
        assert preference["side"] in ("left", "right") and preference["clearance"] >= 0.0


def test_the_executed_plan_is_the_tables(demo, results):
    run = results["execution"]
    assert run["plan"] == "plans/unseen_1.csv"
    assert run["goal_approach_m"] > 0 and run["clearance_m"] > 0
    plan = np.loadtxt(demo / run["plan"], delimiter=",", skiprows=1)
    np.testing.assert_allclose(plan[-1], NEW_GOAL, atol=1e-3)
    assert run["success"], run["failures"]


def test_report_explains_its_terms(demo):
    html = (demo / "report.html").read_text(encoding="utf-8")
    for section in SECTIONS:
        assert f">{section}</h2>" in html.replace("&#x27;", "'"), section
    for term in TERMS:
        assert term in GLOSSARY, term
        assert f"<dt>{term}</dt>" in html, term
    # Self-contained: every image is embedded.
    assert html.count('<img src="data:image/png;base64,') == html.count("<img ")


# ------------------------------------------------------------------ in a browser
def _browser():
    """A headless Chromium driven by selenium, or skip the test saying what to install."""
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        pytest.skip(f"the report's browser test {INSTALL}")
    binary = next(
        (p for p in map(shutil.which, ("chromium", "chromium-browser", "google-chrome")) if p),
        None,
    )
    driver = shutil.which("chromedriver")
    if binary is None or driver is None:
        pytest.skip(f"the report's browser test {INSTALL}")
    options = webdriver.ChromeOptions()
    options.binary_location = binary
    for argument in (
        "--headless=new",
        f"--window-size={WINDOW_WIDTH},900",
        "--hide-scrollbars",
        "--disable-gpu",
        "--disable-dev-shm-usage",
        "--force-device-scale-factor=1",
    ):
        options.add_argument(argument)
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        options.add_argument("--no-sandbox")  # Chromium refuses to sandbox as root
    try:
        return webdriver.Chrome(options=options, service=Service(executable_path=driver))
    except Exception as exc:  # a driver that does not match the browser, no display libs, ...
        pytest.skip(f"Chromium did not start ({type(exc).__name__}: {exc}); {INSTALL}")


@pytest.fixture(scope="module")
def browser():
    driver = _browser()
    yield driver
    driver.quit()


@pytest.fixture(scope="module")
def page(browser, demo, tmp_path_factory):
    """The report open in the browser, its images decoded (the browser first: skip early)."""
    browser.get((demo / "report.html").resolve().as_uri())
    browser.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "Promise.all([...document.images].map(img => img.decode().catch(() => null)))"
        ".then(() => done(true));"
    )
    return browser, tmp_path_factory.mktemp("browser")


def test_report_in_a_browser_has_every_section(page):
    browser, _ = page
    headings = browser.execute_script(
        "return [...document.querySelectorAll('main h2')].map(h => h.textContent)"
    )
    assert headings == SECTIONS
    links = browser.execute_script(
        "return [...document.querySelectorAll('nav.toc a')].map(a => a.textContent)"
    )
    assert links == SECTIONS
    terms = browser.execute_script(
        "return [...document.querySelectorAll('dt')].map(dt => dt.textContent)"
    )
    assert set(TERMS) <= set(terms)
    # Nothing wider than the window: no sideways scrolling.
    width = browser.execute_script("return document.documentElement.scrollWidth")
    assert width <= WINDOW_WIDTH


def test_report_in_a_browser_shows_every_figure_legibly(page, demo):
    browser, folder = page
    images = browser.execute_script(
        "return [...document.images].map(img => ({alt: img.alt, complete: img.complete,"
        " natural: img.naturalWidth, naturalHeight: img.naturalHeight,"
        " shown: img.getBoundingClientRect().width,"
        " shownHeight: img.getBoundingClientRect().height}))"
    )
    figures = sorted(p.name for p in (demo / "figures").glob("*.png"))
    assert len(images) == len(figures) >= 5
    for image in images:
        where = image["alt"][:60]
        assert image["complete"] and image["natural"] > 0 and image["naturalHeight"] > 0, where
        assert image["shown"] >= MIN_SHOWN_WIDTH, (where, image["shown"])
        assert image["shown"] >= MIN_SCALE * image["natural"], (where, image)
        # Drawn at its own proportions.
        ratio = image["natural"] / image["naturalHeight"]
        assert image["shown"] / image["shownHeight"] == pytest.approx(ratio, rel=0.02), where

    # A full-page screenshot to look at.
    size = browser.execute_cdp_cmd("Page.getLayoutMetrics", {})["cssContentSize"]
    shot = browser.execute_cdp_cmd(
        "Page.captureScreenshot",
        {
            "format": "png",
            "captureBeyondViewport": True,
            "clip": {"x": 0, "y": 0, "width": size["width"], "height": size["height"], "scale": 1},
        },
    )
    png = base64.b64decode(shot["data"])
    assert png.startswith(PNG_SIGNATURE)
    (folder / "report.png").write_bytes(png)
    assert int.from_bytes(png[20:24], "big") >= sum(i["shownHeight"] for i in images)
