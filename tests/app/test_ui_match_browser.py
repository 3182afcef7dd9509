"""Watching a match in the viser UI, in headless Chromium at a classroom projector's 1280 x 800: pick two examples
in the Play tab's Match folder, watch the match advance (score, half, tick), switch the Inference panel to B and
see B's rules and membership degrees, and the same in the projector view. Screenshots go to
artifacts/screenshots/match-*.png."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from soccer_lab.app.web.ui.match_game import MatchGame
from soccer_lab.app.web.ui.projector import PROJECTOR_KEY_SCRIPT
from soccer_lab.soccer.examples import example
from soccer_lab.soccer.match import play_matches
from tests.app.test_ui_browser import (CHROMIUM, browser, choose, dismiss_notifications, field,  # noqa: F401
                                       session_of, shot, ui, wait_until)

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(shutil.which(CHROMIUM) is None and not Path(CHROMIUM).exists(),
                       reason=f"Chromium not installed at {CHROMIUM} (scripts/test installs it with apt)"),
]
VIEWPORT = {"width": 1280, "height": 800}


@pytest.fixture(scope="module")
def tab(ui, browser):
    page = browser.new_page(viewport=VIEWPORT)
    page.set_default_timeout(60_000)
    page.add_init_script(PROJECTOR_KEY_SCRIPT)
    page.goto(ui.url)
    page.locator(".game-status").wait_for()
    wait_until(lambda: session_of(ui).ready.is_set(), timeout=60)
    dismiss_notifications(page)
    yield page, session_of(ui)
    page.close()


def status(page) -> dict:
    return page.evaluate("() => { const s = document.querySelector('.match-status'); return s && "
                         "{tick: +s.dataset.tick, half: +s.dataset.half, goals: s.dataset.goals, "
                         "watched: s.dataset.watched, text: s.textContent}; }")


def degrees(page) -> list[float]:
    """The membership chips' degrees in the Inference panel."""
    return page.evaluate("() => [...document.querySelectorAll('.membership-input .term')].map(e => +e.dataset.degree)")


def strengths(page) -> list[float]:
    return page.evaluate("() => [...document.querySelectorAll('.rules .rule')].map(e => +e.dataset.strength)")


def open_match_folder(page) -> None:
    page.get_by_role("tab", name="Play").click()
    folder = page.get_by_text("Match: two players", exact=True)
    folder.scroll_into_view_if_needed()
    if not field(page, "Player A", "input").is_visible():
        folder.click()


def test_two_examples_play_a_match_with_score_clock_and_either_players_thinking(ui, tab):
    page, session = tab
    open_match_folder(page)
    choose(page, "Player A", "Example: Two-rule striker")
    choose(page, "Player B", "Example: Dribbler")
    page.get_by_role("button", name="Watch the match").click()
    wait_until(lambda: isinstance(session.game, MatchGame))
    match = session.game
    assert match.names == ("Two-rule striker", "Dribbler")
    # the match plays: the clock runs in the Play tab, half 1 first
    page.locator(".match-status").wait_for()
    first = status(page)["tick"]
    wait_until(lambda: (status(page) or {}).get("tick", 0) > first + 5)
    shown = status(page)
    assert shown["half"] == 1 and "half 1 of 2" in shown["text"] and "A attacks →" in shown["text"]
    assert "Two-rule striker" in shown["text"] and "Dribbler" in shown["text"]
    page.get_by_role("tab", name="Inference").click()
    page.locator(".inference-whose[data-watched='A']").wait_for()
    assert len(strengths(page)) == len(example("striker").rulebase(session.context.vocabulary))
    page.mouse.move(640, 400)
    shot(page, "match-pitch")

    # B's thinking: its rules (the dribbler's) and its own inputs' degrees
    page.get_by_role("tab", name="Play").click()
    page.get_by_role("button", name="Pause").click()
    page.get_by_role("button", name="B", exact=True).first.click()
    page.get_by_role("tab", name="Inference").click()
    page.locator(".inference-whose[data-watched='B']").wait_for()
    dribbler = example("dribbler").rulebase(session.context.vocabulary)
    wait_until(lambda: len(strengths(page)) == len(dribbler))
    with session.lock:
        b_inputs = session.game.state.minds[1].inputs
        b_degrees = [degree for name, value in b_inputs.items()
                     for degree in session.context.vocabulary.variables[name.split("_")[1]].fuzzify(value).values()
                     ] if all(v is not None for v in b_inputs.values()) else None
    assert status(page)["watched"] == "B"
    if b_degrees is not None:  # every object in B's view: its chips are its own degrees
        assert degrees(page) == pytest.approx(b_degrees, abs=1e-4)
    shot(page, "match-thinking-b")


def test_the_match_watched_is_the_match_play_matches_counts(ui, tab):
    page, session = tab
    session.set_playing(False)
    with session.lock:
        match = session.game
        a, b = match.players
        expected = play_matches(a, b, [match.seed], match.config, match.vocabulary)[0]
        match.restart(match.seed)
        while not match.state.half_over:
            match.step()
        session._render()
    page.get_by_role("tab", name="Play").click()
    page.locator(".match-break").wait_for()
    assert "Half time" in status(page)["text"]
    page.mouse.move(640, 400)
    shot(page, "match-half-time")
    with session.lock:
        match.skip_half_time()
        match.step()  # the second half's kick-off: the sides swapped
        session._render()
    wait_until(lambda: status(page)["half"] == 2)
    assert "B attacks → (the right goal), A attacks ←" in status(page)["text"]
    shot(page, "match-second-half")
    with session.lock:
        while not match.done:
            match.skip_half_time()
            match.step()
        assert match.state.result == expected
        session._render()
    page.get_by_role("tab", name="Play").click()
    wait_until(lambda: (status(page) or {}).get("goals") == f"{expected.goals[0]}-{expected.goals[1]}")
    assert "Full time" in status(page)["text"]


def test_the_projector_view_shows_the_match_and_switches_the_thinking(ui, tab):
    page, session = tab
    page.get_by_role("tab", name="Play").click()
    page.get_by_role("button", name="Restart this seed").click()
    page.get_by_role("button", name="Play", exact=True).click()
    wait_until(lambda: session.playing and not session.game.done)
    page.keyboard.press("p")
    band = page.locator(".projector-match")
    band.wait_for()
    first = int(band.get_attribute("data-tick"))
    wait_until(lambda: int(page.locator(".projector-match").get_attribute("data-tick")) > first + 5)
    assert "half 1 of 2" in page.locator(".projector-match").text_content()
    page.get_by_role("button", name="A", exact=True).last.click()
    wait_until(lambda: page.locator(".projector-match").get_attribute("data-watched") == "A")
    assert "A thinks" in page.locator(".projector-match").text_content()
    page.mouse.move(640, 500)
    shot(page, "match-projector")
    page.get_by_role("button", name="B", exact=True).last.click()
    wait_until(lambda: page.locator(".projector-match").get_attribute("data-watched") == "B")
    assert session.game.watched == 1
    page.keyboard.press("p")
