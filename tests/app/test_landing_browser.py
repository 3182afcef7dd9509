"""The landing page in headless Chromium: it lists the recorded experiments with links to their report
and figures (served by the API)."""

from __future__ import annotations

import shutil
import threading
import time
from pathlib import Path

import pytest

from tests.app.test_ui_browser import CHROMIUM, CHROMIUM_ARGS, TIMEOUT_MS, free_port, offline

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(shutil.which(CHROMIUM) is None and not Path(CHROMIUM).exists(),
                       reason=f"Chromium not installed at {CHROMIUM} (scripts/test installs it with apt)"),
]


@pytest.fixture
def api_url(tmp_path):
    import uvicorn

    from soccer_lab.app.web.api import create_app
    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.store import Store

    folder = tmp_path / "initial-seed0"
    (folder / "figures").mkdir(parents=True)
    (folder / "report.html").write_text("<html><body>the report</body></html>")
    (folder / "figures" / "initial-best_fitness.png").write_bytes(b"\x89PNG")
    store = Store(tmp_path / "db.sqlite3")
    runs = RunManager(store, tmp_path)
    store.record_experiment("initial", folder, {
        "presets": ["initial"], "trials": 20, "verdicts": {"agrees": 4, "disagrees": 1},
        "figures": ["figures/initial-best_fitness.png"], "figure_captions": ["Initial: best fitness"]})
    port = free_port()
    server = uvicorn.Server(uvicorn.Config(create_app(store, runs), host="127.0.0.1", port=port, log_level="warning"))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    deadline = time.monotonic() + 20
    while not server.started and time.monotonic() < deadline:
        time.sleep(0.05)
    yield f"http://127.0.0.1:{port}"
    server.should_exit = True
    thread.join(10)
    store.close()


def test_landing_page_lists_experiments_with_report_and_figure_links(api_url):
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            page = browser.new_page()
            page.set_default_timeout(TIMEOUT_MS)
            asked = offline(page)  # the home page, like every page the app shows, needs no internet
            page.goto(api_url + "/")
            row = page.locator("#experiments tr.experiment")
            row.wait_for()
            assert row.count() == 1
            cells = row.locator("td").all_inner_texts()
            assert cells[:2] == ["1", "initial"] and cells[3] == "20" and cells[4] == "4 agrees, 1 disagrees"
            report = row.get_by_role("link", name="report")
            assert report.get_attribute("href") == f"{api_url}/api/experiments/1/report.html"
            figure = row.get_by_role("link", name="initial-best_fitness")
            assert figure.get_attribute("title") == "Initial: best fitness"
            report.click()
            page.get_by_text("the report").wait_for()
            page.wait_for_load_state("networkidle")
            assert asked == []
        finally:
            browser.close()


@pytest.mark.parametrize("path, shown", [("/docs", ".swagger-ui .info .title"), ("/redoc", ".api-info h1")])
def test_api_docs_work_without_internet(api_url, path, shown):
    """/docs was a blank page offline: Swagger UI came from a CDN. Its scripts are the app's own now."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            page = browser.new_page()
            page.set_default_timeout(TIMEOUT_MS)
            asked = offline(page)
            page.goto(api_url + path)
            page.locator(shown, has_text="soccer-lab").first.wait_for()
            page.wait_for_load_state("networkidle")
            assert asked == []
        finally:
            browser.close()
