"""Rule usage beside the rules and the Simplify button: the panel's rendering, and the real UI in
headless Chromium (a measured usage greys the rules that never won; Simplify puts a shorter
rulebase on the pitch that plays the same)."""

from __future__ import annotations

import re
import shutil
from html import escape
from pathlib import Path

import pytest

from soccer_lab.app.web.ui.panels.rules import rules_html
from soccer_lab.fuzzy.engine import Engine
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.printer import format_rule
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.engine import play_game
from soccer_lab.soccer.usage import measure_usage
from tests.app.test_ui_browser import (CHROMIUM, browser, page,  # noqa: F401 (fixtures; page opens this ui)
                                       field, free_port, pause, session_of, shot, wait_until)

VOCABULARY = Vocabulary.default()
GAME = GameConfig(max_ticks=150, idle_ticks=60)
PLAYER = parse_rulebase(
    "if Ball is At then KickTowardGoal High\n"
    "if Ball is not At and Ball is not VeryFar then GoToBall VeryHigh\n"
    "if Ball is At then KickTowardGoal High\n"
    "if Ball is Near then Dash High\n"
    "if Ball is Straight and Goal is Far then Dash Low\n", VOCABULARY)
PLAYER_TEXT = "\n".join(format_rule(rule, VOCABULARY) for rule in PLAYER)


def test_rules_panel_shows_a_usage_bar_per_rule_and_greys_rules_that_never_won():
    usage, _ = measure_usage(PLAYER, [1, 2, 3], GAME, VOCABULARY)
    inputs = {"ball_distance": 5.0, "ball_direction": 0.0, "goal_distance": 40.0, "goal_direction": 0.0}
    html = rules_html([format_rule(r, VOCABULARY) for r in PLAYER], Engine(PLAYER, VOCABULARY).infer(inputs),
                      only_fired=False, usage=usage)
    won = [float(w) for w in re.findall(r'class="usage" data-won="([0-9.]+)"', html)]
    assert won == pytest.approx([r.won / usage.ticks for r in usage.rules], abs=5e-5)
    never = re.findall(r'data-index="(\d)"[^>]*data-never-won="true"', html)
    assert never == [str(i) for i, r in enumerate(usage.rules) if r.won == 0] and "3" in never
    assert 'class="usage-caption" data-games="3"' in html
    assert "usage" not in rules_html(["r"], None, only_fired=False)


def test_the_editor_simplifies_through_its_callbacks_and_undo_goes_back(tmp_path):
    import viser

    from soccer_lab.app.store import Store
    from soccer_lab.app.web.ui.panels.editor import SIMPLIFIED_NAME, EditorPanel
    from soccer_lab.soccer.simplify import simplify_rulebase

    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    asked, applied = [], []

    def simplify(rulebase, games):
        asked.append(games)
        return simplify_rulebase(rulebase, VOCABULARY, list(range(games)), GAME)

    try:
        editor = EditorPanel(server.gui, VOCABULARY, Store(tmp_path / "db.sqlite3"), (PLAYER, "player"),
                             on_apply=lambda r, n: applied.append((r, n)), on_example=lambda r, n: None,
                             on_saved=lambda: None, simplify=simplify)
        editor.check_games.value = 3
        editor.simplify()
        (rulebase, name), = applied
        assert asked == [3] and name == SIMPLIFIED_NAME and len(rulebase) < len(PLAYER)
        assert "checked on 3 games" in editor.message.content
        result = simplify(PLAYER, 3)
        for step in result.simplification.steps:  # which rules went or changed, and why, not counts
            for change in step.changes:
                what = "dropped" if change.after is None else "now"
                assert f"Rule {change.rule} {what}" in editor.message.content
                assert escape(change.reason) in editor.message.content
        editor.show_rulebase(rulebase, name)
        editor.simplify()  # already as short as the steps make it: nothing applied
        assert len(applied) == 1 and "Nothing to simplify" in editor.message.content
        editor.undo()
        assert applied[-1] == (PLAYER, "player")
    finally:
        server.stop()


# ---- in the browser -------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def ui(tmp_path_factory):
    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.store import Store
    from soccer_lab.app.web.ui import start_ui

    data = tmp_path_factory.mktemp("ui-usage-data")
    store = Store(data / "db.sqlite3")
    runs = RunManager(store, data)
    handle = start_ui(store, runs, port=free_port(), game=GAME)
    yield handle
    handle.stop()
    runs.shutdown(wait=10)
    store.close()


@pytest.mark.browser
@pytest.mark.skipif(not Path(CHROMIUM).exists() and shutil.which(CHROMIUM) is None,
                    reason=f"Chromium not installed at {CHROMIUM} (scripts/test installs it with apt)")
def test_usage_beside_the_rules_then_simplify_in_the_browser(ui, page):
    session = session_of(ui)
    pause(page)  # the pitch's seed (the games' first seed) stays put: short games restart with the next one
    page.get_by_role("tab", name="Rules").click()
    field(page, "Rules", "textarea").fill(PLAYER_TEXT)
    page.get_by_role("button", name="Apply").click()
    wait_until(lambda: session.game.name == "edited" and len(session.game.rulebase) == len(PLAYER))

    page.get_by_role("tab", name="Inference").click()
    field(page, "Usage games", "input").fill("4")
    field(page, "Usage games", "input").press("Tab")
    page.get_by_role("button", name="Measure rule usage").click()
    page.locator('.usage-caption[data-games="4"]').wait_for()
    expected, _ = measure_usage(PLAYER, [session.game.seed + i for i in range(4)], GAME, VOCABULARY)
    greyed = page.locator('.rule[data-never-won="true"]')
    wait_until(lambda: greyed.count() == sum(r.won == 0 for r in expected.rules))
    assert page.locator(".rule .usage").count() == len(PLAYER)
    shot(page, "usage-beside-the-rules")

    page.get_by_role("tab", name="Rules").click()
    field(page, "Check on games", "input").fill("4")
    field(page, "Check on games", "input").press("Tab")
    page.get_by_role("button", name="Simplify").click()
    message = page.locator('.editor-message[data-error="false"]', has_text="Simplified")
    message.wait_for()
    assert "checked on 4 games" in message.inner_text()
    wait_until(lambda: session.game.name == "simplified")
    simplified = session.game.rulebase
    assert len(simplified) < len(PLAYER)
    assert page.locator(".usage-caption").count() == 0  # the usage counted the previous rules
    for seed in range(session.game.seed, session.game.seed + 4):
        assert play_game(simplified, seed, GAME, trace=False)[0] == play_game(PLAYER, seed, GAME, trace=False)[0]
    shot(page, "simplified")
    page.get_by_role("button", name="Undo").click()
    wait_until(lambda: session.game.rulebase == PLAYER)


def test_a_tab_runs_one_usage_or_simplification_at_a_time(ui, page):
    """Each costs seconds of a thread every tab's callbacks share: clicking again while one plays is refused in a
    line, not queued (a pupil's repeated clicks must not hold the class's UI)."""
    session = session_of(ui)
    with session._inspecting:  # a measurement under way in this tab
        with pytest.raises(ValueError, match="still measuring rule usage or simplifying"):
            session.simplify(session.game.rulebase, 2)
        session.measure_usage(2)
        assert "still measuring" in session.inference.usage_note.content and session.inference.usage is None
    session.measure_usage(2)  # once it is done, the next one plays
    assert session.inference.usage is not None and session.inference.usage_note.content == ""


def test_a_usage_of_rules_replaced_while_it_was_measured_says_so_beside_the_button(ui, page, monkeypatch):
    """A pupil loading a player while its usage played got nothing at all: no bars, no line (the lesson walk
    waited 120 s for a caption). The usage is still not shown (it counted other rules), and the line under the
    button says why and what to do; errors are said there too, not in the Rules tab's editor."""
    import soccer_lab.app.web.ui.session as session_module

    session = session_of(ui)
    measured = session_module.rule_usage

    def load_a_player_meanwhile(*args, **kwargs):
        usage = measured(*args, **kwargs)
        session.load_rulebase(PLAYER, "loaded while measuring")
        return usage

    monkeypatch.setattr(session_module, "rule_usage", load_a_player_meanwhile)
    session.measure_usage(2)
    assert session.inference.usage is None
    note = session.inference.usage_note.content
    assert 'class="usage-note" data-error="true"' in note and "rules on the pitch changed" in note
    assert "Usage" not in session.editor.message.content
    page.get_by_role("tab", name="Inference").click()
    page.locator(".usage-note", has_text="Press Measure rule usage again").wait_for()
    monkeypatch.setattr(session_module, "rule_usage", measured)
    session.measure_usage(2)
    assert session.inference.usage is not None and session.inference.usage_note.content == ""
