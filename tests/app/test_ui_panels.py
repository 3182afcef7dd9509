"""The UI's panels as pure renderers: what they show for hand-computed inferences (no browser)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from soccer_lab.app.web.ui.panels import membership as membership_module
from soccer_lab.app.web.ui.panels.membership import kick_reach, membership_html
from soccer_lab.app.web.ui.panels.outputs import outputs_html
from soccer_lab.app.web.ui.panels.policy import COLUMNS, ROWS, policy_grid, policy_map_html
from soccer_lab.app.web.ui.panels.rules import HUNT_TEXT, decision_html, rules_html
from soccer_lab.app.web.ui.panels.svg import Axis
from soccer_lab.app.web.ui.pitch import PitchGeometry, to_scene, yaw_quaternion
from soccer_lab.app.web.ui.pitch_pictures import marking_segments
from soccer_lab.fuzzy.batched import NO_ACTION
from soccer_lab.fuzzy.engine import Engine
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import WorldConfig

VOCABULARY = Vocabulary.default()
RULES = parse_rulebase(
    "if Ball is Near then KickTowardGoal High\n"
    "if Ball is SlightlyNear and Ball is SlightlyLeft then Kick Left Low\n"
    "if Goal is Far then Turn Right\n", VOCABULARY
)
INPUTS = {"ball_distance": 5.0, "ball_direction": -20.0, "goal_distance": None, "goal_direction": None}


def degrees_of(html: str, input_name: str) -> dict[str, float]:
    block = html.split(f'data-input="{input_name}"', 1)[1].split('class="membership-input"', 1)[0]
    return {name: float(value) for value, name in re.findall(r'data-degree="([0-9.]+)"[^>]*>([A-Za-z0-9]+) ', block)}


def test_ball_distance_chart_marks_where_the_ball_becomes_kickable():
    # "Ball is At" reaches 2 m, a kick only 1.085 m: without the mark the chart hid why "At 0.7" did not kick.
    world = WorldConfig()
    html = membership_html(VOCABULARY, INPUTS, kick_reach(VOCABULARY, world))
    ball_block = html.split('data-input="ball_distance"', 1)[1].split('class="membership-input"', 1)[0]
    mark = re.search(r'class="kick-reach" data-reach="([0-9.]+)"><line x1="([0-9.]+)"', ball_block)
    assert mark and float(mark.group(1)) == pytest.approx(world.kickable_distance) == pytest.approx(1.085)
    axis = Axis(VOCABULARY.variables["distance"], membership_module.PAD, membership_module.WIDTH - membership_module.PAD)
    assert float(mark.group(2)) == pytest.approx(axis(1.085), abs=0.05)
    assert "kick reach 1.085 m" in ball_block
    assert html.count('class="kick-reach"') == 1  # the goal's distance has no reach


def test_membership_shows_hand_computed_degrees_and_greys_unseen_objects():
    html = membership_html(VOCABULARY, INPUTS)
    ball = degrees_of(html, "ball_distance")
    # Near is (2, 4, 8): (8 - 5) / 4; SlightlyNear is (4, 8, 15): (5 - 4) / 4.
    assert ball["Near"] == pytest.approx(0.75) and ball["SlightlyNear"] == pytest.approx(0.25)
    assert sum(ball.values()) == pytest.approx(1.0)
    direction = degrees_of(html, "ball_direction")
    # SlightlyLeft is (-45, -15, 0): (-20 + 45) / 30; Left is (-90, -45, -15): (-15 + 20) / 30.
    assert direction["SlightlyLeft"] == pytest.approx(25 / 30, abs=1e-4)
    assert direction["Left"] == pytest.approx(5 / 30, abs=1e-4)
    assert 'data-input="goal_distance" data-visible="false"' in html
    assert set(degrees_of(html, "goal_distance").values()) == {0.0}
    assert "not in view" in html


def test_rules_panel_shows_strengths_and_only_fired_switch():
    inference = Engine(RULES, VOCABULARY).infer(INPUTS)
    all_rows = rules_html(["r1", "r2", "r3"], inference, only_fired=False)
    fired_rows = rules_html(["r1", "r2", "r3"], inference, only_fired=True)
    strengths = [float(s) for s in re.findall(r'data-strength="([0-9.]+)"', all_rows)]
    assert strengths == pytest.approx([0.75, 0.25, 0.0])
    assert re.findall(r'class="rule" data-index="(\d)"', fired_rows) == ["0", "1"]
    turner = parse_rulebase("if Goal is Far then Turn Right", VOCABULARY)
    assert "No rule fired" in rules_html(["r3"], Engine(turner, VOCABULARY).infer(INPUTS), True)


def test_decision_names_the_selected_action_and_the_hunt():
    inference = Engine(RULES, VOCABULARY).infer(INPUTS)
    html = decision_html(VOCABULARY, inference)
    assert 'data-action="KICKTOWARDGOAL"' in html and "KickTowardGoal" in html and "0.75" in html
    unseen = {name: None for name in INPUTS}
    assert HUNT_TEXT in decision_html(VOCABULARY, Engine(RULES, VOCABULARY).infer(unseen))


def test_output_sets_mark_the_exact_mean_of_maximum():
    rules = parse_rulebase("if Ball is Near then Kick Left Low\nif Ball is SlightlyNear then Kick Right High",
                           VOCABULARY)
    inference = Engine(rules, VOCABULARY).infer(INPUTS)
    html = outputs_html(VOCABULARY, inference)
    values = [float(v) for v in re.findall(r'class="mom" data-value="(-?[0-9.]+)"', html)]
    # Only the strongest rule (0.75) reaches the maximum: Left (-90,-45,-15) cut at 0.75 is [-56.25, -37.5].
    assert values[0] == pytest.approx((-56.25 - 37.5) / 2) == pytest.approx(inference.selected.parameters["direction"])
    assert values[1] == pytest.approx(inference.selected.parameters["power"])
    levels = sorted(float(v) for v in re.findall(r'class="clipped" data-term="[A-Z]+" data-level="([0-9.]+)"', html))
    assert levels == pytest.approx([0.25, 0.25, 0.75, 0.75])


def test_policy_grid_agrees_with_the_scalar_engine_and_hides_the_ball_out_of_view():
    grid = policy_grid(VOCABULARY, RULES, 50.0, 10.0, True, 45.0, "power")
    assert grid.actions.shape == (ROWS, COLUMNS)
    engine = Engine(RULES, VOCABULARY)
    for i, j in [(3, 25), (10, 29), (20, 30), (5, 2), (30, 58)]:
        d, a = grid.distances[i], grid.directions[j]
        seen = abs(a) <= 45.0
        inputs = {"ball_distance": d if seen else None, "ball_direction": a if seen else None,
                  "goal_distance": 50.0, "goal_direction": 10.0}
        expected = engine.infer(inputs).selected
        action = grid.actions[i, j]
        if expected is None:
            assert action == NO_ACTION
        else:
            assert VOCABULARY.action_names[action] == expected.action
            if "power" in expected.parameters:
                assert grid.values[i, j] == expected.parameters["power"]
    # Beyond the view angle only the goal rule can fire: Turn (Goal is Far at 50 m: (60 - 50) / 20 > 0).
    assert VOCABULARY.action_names[grid.actions[0, 0]] == "TURN"
    assert math.isnan(grid.values[0, 0])  # Turn does not use power
    html = policy_map_html(VOCABULARY, grid, "power", (5.0, -20.0))
    assert 'class="current"' in html and "KickTowardGoal" in html


def test_pitch_is_drawn_in_scene_coordinates_with_y_flipped():
    geometry = PitchGeometry.from_world(WorldConfig())
    assert (geometry.half_length, geometry.half_width, geometry.goal_half_width) == (52.5, 34.0, 7.01)
    segments = marking_segments(geometry)
    assert np.abs(segments[..., 0]).max() == pytest.approx(52.5 + geometry.goal_depth)
    assert np.abs(segments[..., 1]).max() == pytest.approx(34.0)
    assert to_scene(1.0, 2.0) == (1.0, -2.0, 0.0)
    # Facing +y (the player's right) must look down the screen: a -90 degree turn about the scene's z.
    w, x, y, z = yaw_quaternion(math.pi / 2)
    assert (w, x, y) == pytest.approx((math.cos(math.pi / 4), 0.0, 0.0)) and z == pytest.approx(-math.sin(math.pi / 4))


def test_population_grid_draws_one_small_pitch_per_game():
    from types import SimpleNamespace

    from soccer_lab.app.web.ui.panels.population import population_html
    from soccer_lab.soccer.engine import END_REASONS, Observation

    geometry = PitchGeometry.from_world(WorldConfig())
    observation = Observation(player_x=np.array([-10.0, 20.0]), player_y=np.array([5.0, -4.0]),
                              facing=np.array([30.0, -90.0]), ball_x=np.array([0.0, 25.0]), ball_y=np.array([-3.0, 0.0]),
                              inputs=np.zeros((2, 4)), visible=np.zeros((2, 2), dtype=bool))
    state = SimpleNamespace(goals=np.array([0, 3]), done=np.array([False, True]),
                            end_reason=np.array([END_REASONS.index("running"), END_REASONS.index("idle")]))
    html = population_html(geometry, observation, state, ["gen 0", "gen 1"])
    assert html.count('class="mini-pitch"') == 2
    assert 'data-goals="3" data-done="true" data-end-reason="idle"' in html and "gen 1" in html
    assert "3 goals" in html and "0 goals" in html  # said in words over each pitch, not a bare number
    # a game that is over says why on its grey pitch; one still running says nothing
    assert html.count("stood still too long") == 1 and 'data-end-reason="running"' in html
