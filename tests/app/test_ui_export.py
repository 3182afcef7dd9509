"""The Library's download of a saved rulebase, driven in headless Chromium (fixtures from test_ui_browser)."""

from __future__ import annotations

from pathlib import Path

from soccer_lab.fuzzy.export import export_rulebase
from soccer_lab.fuzzy.parser import parse_rulebase
from tests.app.test_ui_browser import browser, choose, page, pytestmark, session_of, shot, ui, wait_until  # noqa: F401

TEXT = "if Ball is At then Kick SlightlyRight High\nif Ball is not At then GoToBall High\n"


def test_library_downloads_a_saved_rulebase_in_the_chosen_format(ui, page):
    record = ui.context.store.create_rulebase("export me", TEXT)
    session = session_of(ui)
    page.get_by_role("tab", name="Library").click()
    page.get_by_role("button", name="Refresh", exact=True).click()
    wait_until(lambda: any(o.endswith("export me") for o in session.library.rulebases.options))
    choose(page, "Rulebase", f"#{record.id} export me")
    wait_until(lambda: session.library.rulebases.value.endswith("export me"))
    vocabulary = ui.context.vocabulary
    for fmt in ("fis", "fcl"):
        choose(page, "Export as", fmt, exact=True)
        wait_until(lambda: session.library.export_format.value == fmt)
        with page.expect_download() as download:
            page.get_by_role("button", name="Download", exact=True).click()
        assert download.value.suggested_filename == f"export_me.{fmt}"
        text = Path(download.value.path()).read_text()
        assert text == export_rulebase(parse_rulebase(TEXT, vocabulary), fmt, vocabulary)
    page.locator(".library-message", has_text="export_me.fcl").wait_for()
    shot(page, "9-library-download")
