"""The UI's game at a fresh start: before the first tick the panels show what the player perceives and
the decision it is about to make, exactly what the engine then decides."""

from __future__ import annotations

import math

import numpy as np
import pytest

from soccer_lab.app.web.ui.command_mark import LABELS
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
@pytest.mark.parametrize("label", LABELS)
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


def rotate(wxyz, points: np.ndarray) -> np.ndarray:
    """`points` [N, 3] turned by the unit quaternion `wxyz`, as three.js turns a node's children."""
    w, q = wxyz[0], np.asarray(wxyz[1:])
    return points + 2 * w * np.cross(q, points) + 2 * np.cross(q, np.cross(q, points))


def drawn(placed) -> np.ndarray:
    """float[N, 2, 2]: the world segments a placed shape shows, as the scene draws them."""
    from soccer_lab.app.web.ui.command_mark import mark_shapes
    from soccer_lab.app.web.ui.pitch import Z_COMMAND, mirrored_yaw_quaternion, scene_segments, to_scene, yaw_quaternion

    segments, _ = mark_shapes()[placed.shape]
    facing = math.radians(placed.heading)
    wxyz = mirrored_yaw_quaternion(facing) if placed.mirrored else yaw_quaternion(facing)
    local = scene_segments(segments, 0.0).reshape(-1, 3).astype(np.float64)
    scene = rotate(wxyz, local) + np.array(to_scene(*placed.at, Z_COMMAND))
    assert np.allclose(scene[:, 2], Z_COMMAND), "a mirrored shape left the pitch's plane"
    return np.stack([scene[:, 0], -scene[:, 1]], axis=1).reshape(-1, 2, 2)


def direction(degrees: float) -> np.ndarray:
    return np.array([math.cos(math.radians(degrees)), math.sin(math.radians(degrees))])


@pytest.mark.parametrize("rules", ["demo", "striker", "dribbler"])
def test_the_pitch_draws_each_command_from_prebuilt_shapes_where_it_belongs(rules):
    """The marks became pre-built shapes moved and turned (so a playing pitch changes only poses): an arrow's or an
    arc's runs lie end to end from where the command starts to its head, where its power or turn says, to the
    shapes' steps; a turn's arc ends at the facing the turn gave (it began there and overshot); a turn to the left
    is the right's mirror, not a right turn; a dashed line runs on the line to what was missing."""
    from soccer_lab.app.web.ui.command_mark import (ARC_RADIUS, ARROW_STEP, DASH_BASE, DASH_SCALE, KICK_BASE,
                                                    KICK_SCALE, TURN_STEP)
    from soccer_lab.soccer.examples import example
    from soccer_lab.soccer.skills import DASH, KICK, NOT_KICKABLE, TURN

    rulebase = demo_rulebase() if rules == "demo" else example(rules).rulebase(VOCABULARY)
    seen = set()
    for seed in range(3):
        game = Game(CONTEXT, rulebase, rules, seed=seed)
        for _ in range(120):
            game.step()
            state, mark = game.state, game.frame().command
            outcome = state.outcome
            assert mark.label in LABELS
            facing = state.facing  # degrees
            if outcome.kind in (KICK, DASH, TURN):
                *runs, head = mark.shapes
                assert head.shape.endswith("_head")
                chain = np.concatenate([drawn(run) for run in runs]) if runs else np.zeros((0, 2, 2))
                assert np.allclose(chain[1:, 0], chain[:-1, 1]), "the runs are not laid end to end"
                tip = drawn(head)[0][0]
            if outcome.kind in (KICK, DASH):
                kick = outcome.kind == KICK
                start = np.array(state.ball if kick else state.player)
                length = (KICK_BASE + KICK_SCALE * outcome.value) if kick else (DASH_BASE + DASH_SCALE * outcome.value)
                heading = facing + (outcome.direction if kick else 0.0)
                assert np.allclose(chain[0][0], start) and np.allclose(chain[-1][1], tip)
                assert np.linalg.norm(tip - (start + length * direction(heading))) <= ARROW_STEP / 2 + 1e-6
            elif outcome.kind == TURN:  # the facing is the tick's last: the arc ends there
                centre = np.array(state.player)
                assert np.allclose(tip, centre + ARC_RADIUS * direction(facing))
                start = centre + ARC_RADIUS * direction(facing - outcome.value)
                if len(chain):
                    assert np.allclose(chain[-1][1], tip)
                    assert np.linalg.norm(chain[0][0] - start) <= ARC_RADIUS * math.radians(TURN_STEP / 2) + 1e-6
                    assert np.allclose(np.linalg.norm(chain.reshape(-1, 2) - centre, axis=1), ARC_RADIUS)
                else:
                    assert abs(outcome.value) <= TURN_STEP / 2
            elif mark.shapes:
                dashes = np.concatenate([drawn(p) for p in mark.shapes]).reshape(-1, 2)
                player = np.array(state.player)
                target = np.array(state.ball if outcome.why == NOT_KICKABLE else game.geometry.goal)
                assert np.allclose(dashes[0], target)  # the dashes start at what was missing
                towards = (target - player) / np.linalg.norm(target - player)
                across = dashes - player
                assert np.allclose(across[:, 0] * towards[1] - across[:, 1] * towards[0], 0.0, atol=1e-6)
            seen.add((outcome.kind, outcome.kind == TURN and outcome.value < 0, bool(mark.shapes)))
    assert {(TURN, True, True), (TURN, False, True), (DASH, False, True)} <= seen, seen
