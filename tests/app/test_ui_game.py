"""The UI's game at a fresh start: before the first tick the panels show what the player perceives and
the decision it is about to make, exactly what the engine then decides."""

from __future__ import annotations

import pytest

from soccer_lab.app.web.ui.context import UiContext
from soccer_lab.app.web.ui.game import Game
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.demo import demo_rulebase

VOCABULARY = Vocabulary.default()

CONTEXT = UiContext(store=None, runs=None, vocabulary=Vocabulary.default(), game=GameConfig())


@pytest.mark.parametrize("seed", range(8))
def test_fresh_start_shows_the_decision_the_first_tick_makes(seed):
    game = Game(CONTEXT, demo_rulebase(), "demo", seed=seed)
    assert game.state.tick == 0
    inputs, visible, inference = game.inputs(), game.visible(), game.inference()
    game.step()
    assert inputs == game.state.inputs and visible == game.state.visible
    selected = inference.selected.action if inference.selected else None
    assert selected == game.state.action
    assert tuple(inference.strengths) == game.state.strengths


def test_ball_and_goal_in_view_at_the_start_are_not_shown_as_unseen():
    # The player starts facing the goal (+x): the goal's centre is in view from anywhere in its half.
    seen = [Game(CONTEXT, demo_rulebase(), "demo", seed=seed) for seed in range(8)]
    assert all(game.visible()["GOAL"] and game.inputs()["goal_distance"] > 0 for game in seen)
    with_ball = [game for game in seen if game.visible()["BALL"]]
    assert with_ball, "no start of these seeds has the ball in view"
    game = with_ball[0]
    assert game.inference().selected is not None and any(s > 0 for s in game.inference().strengths)
    assert game.frame().ball_visible


def test_loading_a_rulebase_with_a_restart_explains_its_first_decision():
    game = Game(CONTEXT, demo_rulebase(), "demo", seed=3)
    for _ in range(5):
        game.step()
    game.set_rulebase(parse_rulebase("if Goal is not At then Turn Left", VOCABULARY), "turner")
    game.restart(game.seed)
    inference = game.inference()
    assert inference.selected.action == "TURN" and inference.strengths[0] > 0
    game.step()
    assert game.state.action == "TURN"


@pytest.mark.parametrize("player", [(-54.0, -37.0), (56.0, 37.0), (0.0, 0.0), (50.0, -38.0)])
@pytest.mark.parametrize("label", ["kick 100", "no kick: ball out of reach", "hunt: turn -180°"])
def test_the_command_label_stays_whole_on_the_grass(player, label):
    """The label over the player, as long as it is and wherever the player stands (corners included), never
    reaches past the grass: the frame around the pitch would hide it."""
    from soccer_lab.app.web.ui.command_mark import label_half_width, label_place
    from soccer_lab.app.web.ui.pitch import PitchGeometry
    from soccer_lab.app.web.ui import style
    from soccer_lab.soccer.config import WorldConfig

    x0, x1, y0, y1 = grass = PitchGeometry.from_world(WorldConfig()).grass
    x, y = label_place(*player, label, grass)  # the label's bottom centre
    assert x0 <= x - label_half_width(label) and x + label_half_width(label) <= x1
    assert y0 <= y - style.COMMAND_LABEL_HEIGHT and y <= y1
