"""The docs site's tables fit a 1280 px wide window: at that width three columns of a calibration table and
the replicates table's "robust" column were once off-screen. Real headless Chromium reads the built site."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPOSITORY = Path(__file__).resolve().parents[2]
CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]
WINDOW = {"width": 1280, "height": 900}
PAGES = ["research/calibration", "research/replicates", "research", "research/open-questions", "inspecting",
         "performance", "robocup", "teaching/match-day"]
pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(not Path(CHROMIUM).exists(), reason=f"Chromium not installed at {CHROMIUM}"),
]
pytest.importorskip("mkdocs", reason="mkdocs is not installed: pip install -e '.[test]'")

# Each table's right edge against its page's content column, and whether any cell overflows its table.
MEASURE = """() => {
  const content = document.querySelector('.md-content__inner').getBoundingClientRect();
  return [...document.querySelectorAll('.md-content table')].map((table, i) => ({
    table: i, header: table.querySelector('th') ? table.querySelector('th').innerText : '',
    right: table.getBoundingClientRect().right, limit: content.right,
    hidden: table.parentElement.scrollWidth - table.parentElement.clientWidth}));
}"""


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("site")
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--site-dir", str(folder)], cwd=REPOSITORY,
                          capture_output=True, text=True, timeout=900, env=dict(os.environ, NO_MKDOCS_2_WARNING="1"))
    assert done.returncode == 0, done.stdout + done.stderr
    return folder


def test_every_table_fits_a_1280_px_window(site):
    from playwright.sync_api import sync_playwright

    measured = []
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        page = browser.new_page(viewport=WINDOW)
        for name in PAGES:
            page.goto((site / name / "index.html").as_uri())
            measured += [(name, table) for table in page.evaluate(MEASURE)]
        browser.close()
    assert measured, "no table measured"
    cut = [(name, t["header"], round(t["right"] - t["limit"]), t["hidden"]) for name, t in measured
           if t["right"] > t["limit"] + 1 or t["hidden"] > 1]
    assert not cut, f"tables wider than the page at 1280 px (page, first header, px beyond, px hidden): {cut}"
