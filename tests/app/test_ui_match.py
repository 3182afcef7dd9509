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
