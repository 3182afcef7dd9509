"""The class round in the projector view, in headless Chromium at 1280 x 800: the teacher starts a round from
the band's Class tab, its table shows there and "Watch this game" plays an entry's game on the pitch; every
Class tab's line then says the round finished (it kept "A round is being played ..." 15 s after the table)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from soccer_lab.app.web.ui.projector import PROJECTOR_KEY_SCRIPT
from tests.app.test_ui_browser import (CHROMIUM, browser, dismiss_notifications, free_port,  # noqa: F401 (fixtures)
                                       session_of, shot, wait_until)
from tests.app.test_ui_projector_browser import band_tab

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(shutil.which(CHROMIUM) is None and not Path(CHROMIUM).exists(),
                       reason=f"Chromium not installed at {CHROMIUM} (scripts/test installs it with apt)"),
]
ENTRIES = {"Grace": "if Ball is not At then GoToBall VeryHigh\nif Ball is At then KickTowardGoal VeryHigh",
           "Ben": "if Ball is not At then GoToBall VeryHigh"}


@pytest.fixture(scope="module")
def class_ui(tmp_path_factory):
    """The UI with a class tournament (its Class tab), every tab the teacher's (no admission: one machine)."""
    from soccer_lab.app.web.access import LOCAL
    from soccer_lab.app.web.classroom.settings import ClassSettings
    from soccer_lab.app.web.classroom.tournament import Tournament
    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.store import Store
    from soccer_lab.app.web.ui import start_ui
    from soccer_lab.fuzzy.vocabulary import Vocabulary
    from soccer_lab.soccer.config import GameConfig

    data = tmp_path_factory.mktemp("class-ui")
    store = Store(data / "db.sqlite3")
    runs = RunManager(store, data)
    tournament = Tournament(store, Vocabulary.default(), GameConfig(max_ticks=200), lambda: ClassSettings(starts=2))
    for name, text in ENTRIES.items():
        tournament.submit(LOCAL, text, name=name, source="typed")
    handle = start_ui(store, runs, port=free_port(), tournament=tournament)
    yield handle
    handle.stop()
    runs.shutdown(wait=10)
    store.close()


def class_page(ui, browser):
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    page.set_default_timeout(120_000)
    page.add_init_script(PROJECTOR_KEY_SCRIPT)
    page.goto(ui.url)
    page.locator(".game-status").wait_for()
    wait_until(lambda: session_of(ui).ready.is_set(), timeout=120)
    dismiss_notifications(page)
    return page, session_of(ui)


def test_a_round_is_started_shown_and_watched_in_the_projector_view(class_ui, browser):
    other, _ = class_page(class_ui, browser)  # another Class tab, in the panels
    other.get_by_role("tab", name="Class").click()
    page, session = class_page(class_ui, browser)
    try:
        page.keyboard.press("p")
        page.locator(".projector-status").wait_for()
        band_tab(page, "Class").click()
        page.get_by_role("button", name="Start a round").click()
        page.locator(".class-table tbody tr").nth(1).wait_for()
        for tab in (page, other):  # the line says the round finished, on every Class tab
            wait_until(lambda: "Round 1 finished" in tab.locator(".class-message").first.inner_text(), timeout=60)
            assert "being played" not in tab.locator(".class-message").first.inner_text()
        shot(page, "projector-class-round-1280x800")
        page.get_by_role("button", name="Watch this game").click()
        wait_until(lambda: "(round 1, start 1)" in session.game.name)
        band_tab(page, "Game").click()
        page.locator(".projector-status").wait_for()
        assert session.projector.on
    finally:
        page.close()
        other.close()
