"""The Evolve tab's Opponent choice in headless Chromium at 1280 x 800: alone by default, a fixed player, or
co-evolution against a hall of fame (its size and the opponents per generation shown only then), reaching
the run's settings. Screenshots go to artifacts/screenshots/."""

from __future__ import annotations

import pytest

from tests.app.test_ui_browser import (TIMEOUT_MS, browser, choose, dismiss_notifications, field, pytestmark,  # noqa: F401
                                       session_of, shot, ui, wait_until)

SMALL_SCREEN = {"width": 1280, "height": 800}


@pytest.fixture(scope="module")
def page(ui, browser):  # noqa: F811
    page = browser.new_page(viewport=SMALL_SCREEN)
    page.set_default_timeout(TIMEOUT_MS)
    page.goto(ui.url)
    page.locator(".game-status").wait_for()
    dismiss_notifications(page)
    yield page
    page.close()


def test_the_opponent_choice_shows_its_fields_and_starts_a_coevolution_run(ui, page):
    page.get_by_role("tab", name="Evolve").click()
    session = session_of(ui)
    hall_size = field(page, "Hall of fame size", "input")
    assert not hall_size.is_visible() and session.evolve.opponent_settings() == {}  # alone, the chapter's
    choose(page, "Opponent", "A fixed player")
    choose(page, "Opponent player", "striker")
    wait_until(lambda: "opponent" in session.evolve.opponent_settings())
    assert not hall_size.is_visible()
    choose(page, "Opponent", "Co-evolve (hall of fame)")
    hall_size.wait_for(state="visible")
    field(page, "Opponents per generation", "input").fill("2")
    field(page, "Opponents per generation", "input").press("Tab")
    wait_until(lambda: session.evolve.opponent_settings().get("coevolve", {}).get("hall_sample") == 2)
    shot(page, "evolve-coevolve-1280")
    page.get_by_text("GA parameters (chapter's Table 2)").click()
    field(page, "Population size", "input").fill("6")
    field(page, "Generations (max)", "input").fill("2")
    field(page, "Generations (max)", "input").press("Tab")
    wait_until(lambda: session.evolve.config()["population_size"] == 6 and session.evolve.config()["max_generations"] == 2)
    page.get_by_role("button", name="Start").click()
    status = page.locator(".evolve-status")
    wait_until(lambda: "finished" in status.inner_text(), timeout=240)
    config = session.evolve.store.get_run(session.evolve.run_id).config
    assert config["coevolve"] == {"hall_size": 10, "hall_sample": 2}
    assert "KickTowardGoal" in config["opponent"]  # the striker founds the hall
    shot(page, "evolve-coevolve-finished-1280")
