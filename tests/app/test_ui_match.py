"""A match on the UI's pitch (app/web/ui/match_game.py, pitch.py): the panels explain the watched player's tick as
its engine decided it, the thinking switch changes whose, the half-time score stays a moment, the names on the
pitch never overlap."""

from __future__ import annotations

import pytest

from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.command_mark import label_half_width
from soccer_lab.app.web.ui.context import UiContext
from soccer_lab.app.web.ui.match_game import HALF_TIME_TICKS, MatchGame
from soccer_lab.app.web.ui.pitch import PitchGeometry, name_places
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.examples import example

VOCABULARY = Vocabulary.default()
CONFIG = GameConfig(max_ticks=200)
CONTEXT = UiContext(store=None, runs=None, vocabulary=VOCABULARY, game=CONFIG)
STRIKER, DRIBBLER = (example(name).rulebase(VOCABULARY) for name in ("striker", "dribbler"))


def a_match(seed: int = 2) -> MatchGame:
    return MatchGame(CONTEXT, (STRIKER, DRIBBLER), ("Striker", "Dribbler <b>"), seed, CONFIG, VOCABULARY)


@pytest.mark.parametrize("watched", [0, 1])
def test_the_panels_explain_the_watched_players_decision_as_its_engine_made_it(watched):
    match = a_match()
    match.watch(watched)
    about_to = match.inference()  # at the kick-off: the decision the first tick makes
    match.step()
    assert tuple(about_to.strengths) == match.state.minds[watched].strengths
    for _ in range(40):
        match.step()
        inference, mind = match.inference(), match.state.minds[watched]
        assert tuple(inference.strengths) == mind.strengths
        assert (inference.selected.action if inference.selected else None) == mind.action
    assert match.rule_texts == match._rule_texts[watched] and match.rulebase is (STRIKER, DRIBBLER)[watched]


def test_the_thinking_switch_changes_the_rules_and_inputs_shown():
    match = a_match()
    for _ in range(10):
        match.step()
    a_inputs, a_rules = match.inputs(), match.rule_texts
    match.watch(1)
    assert match.inputs() == match.state.minds[1].inputs != a_inputs
    assert match.rule_texts != a_rules and len(match.inference().strengths) == len(DRIBBLER)
    assert 'data-watched="B"' in match.status_html()
    assert match.frame().match.watched == 1


def test_the_status_names_both_players_as_text_with_score_half_and_sides():
    html = a_match().status_html()
    assert "Dribbler &lt;b&gt;" in html and "<b>" not in html.replace("Dribbler &lt;b&gt;", "")
    assert "half 1 of 2 · tick 0 / 200" in html and "A attacks → (the right goal)" in html


def test_the_half_time_score_stays_before_the_second_half_kicks_off():
    match = a_match()
    while not match.state.half_over:
        match.step()
    for _ in range(HALF_TIME_TICKS):
        match.step()
        assert match.state.half == 1 and "Half time" in match.status_html()
    match.step()
    assert match.state.half == 2 and match.state.tick == 0
    assert match.pitch_label(0) == "← A" and match.pitch_label(1) == "B →"


def test_the_two_names_on_the_pitch_never_overlap_however_close_the_players():
    geometry = PitchGeometry.from_world(CONFIG.world)
    labels = ("A →", "← B")
    x0, x1, _, _ = geometry.grass
    for a, b in [((0.0, 0.0), (0.5, 0.2)), ((0.0, 0.0), (-0.3, 0.0)), ((x1 - 1, 0.0), (x1 - 2, 0.5)),
                 ((x0 + 1, 5.0), (x0 + 1, 5.0)), ((10.0, 33.0), (11.0, 33.5))]:
        (ax, ay), (bx, by) = name_places(geometry.grass, (a, b), labels)
        widths = sum(label_half_width(label) for label in labels)
        assert abs(ax - bx) > widths or abs(ay - by) >= style.COMMAND_LABEL_HEIGHT, (a, b)
        for x, label in ((ax, labels[0]), (bx, labels[1])):  # whole on the grass
            assert x0 <= x - label_half_width(label) and x + label_half_width(label) <= x1


@pytest.fixture(scope="module")
def gui():
    import viser

    from tests.app.test_ui_browser import free_port

    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    yield server.gui
    server.stop()


@pytest.fixture
def store(tmp_path):
    from soccer_lab.app.store import Store

    store = Store(tmp_path / "db.sqlite3")
    yield store
    store.close()


def test_the_match_folder_plays_a_saved_rulebase_against_an_example(gui, store):
    from soccer_lab.app.web.ui.panels.match import MatchPanel
    from soccer_lab.fuzzy.parser import parse_rulebase

    store.create_rulebase("<i>turner</i>", "if Ball is Near then Turn Left")
    watched = []
    panel = MatchPanel(gui, store, VOCABULARY, current=lambda: (DRIBBLER, "on the pitch"),
                       on_watch=lambda a, b, names: watched.append((a, b, names)))
    saved = next(label for label in panel.players[0].options if label.startswith("Library #"))
    panel.players[0].value = saved
    panel.watch(lambda a, b, names: watched.append((a, b, names)))
    (a, b, names), = watched
    assert a == parse_rulebase("if Ball is Near then Turn Left", VOCABULARY)
    assert b == example("demo").rulebase(VOCABULARY)  # B's first choice: the demo
    assert names == ("<i>turner</i>", "The demo") and "&lt;i&gt;" in panel.message.content


def test_a_player_that_cannot_play_is_one_line_and_no_match(gui, store):
    from soccer_lab.app.web.ui.panels.match import RUN, MatchPanel

    watched = []
    panel = MatchPanel(gui, store, VOCABULARY, current=lambda: (DRIBBLER, "on the pitch"),
                       on_watch=lambda a, b, names: watched.append(names))
    for label in (f"{RUN}7 gone", "Library #x", "nothing at all"):
        panel.players[1].options = (*panel.players[1].options, label)
        panel.players[1].value = label
        panel.watch(lambda a, b, names: watched.append(names))
        assert watched == [] and 'data-error="true"' in panel.message.content and "Player B" in panel.message.content
