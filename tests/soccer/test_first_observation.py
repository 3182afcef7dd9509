"""A new GameBatch has already perceived: its observation is the one its first tick decides on, as
Gymnasium's reset returns the first observation (the UI shows it before anything moves)."""

import numpy as np
import pytest

from soccer_lab.fuzzy.batched import NO_ACTION
from soccer_lab.fuzzy.random_rulebase import random_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.demo import demo_rulebase
from soccer_lab.soccer.engine import GameBatch
from soccer_lab.soccer.perception import BALL, DISTANCE, GOAL, perceive

VOCABULARY = Vocabulary.default()
SHORT = GameConfig(max_ticks=50)


@pytest.fixture(scope="module")
def games():
    rng = np.random.default_rng(3)
    rulebases = [demo_rulebase()] + [random_rulebase(rng, VOCABULARY, rules=6) for _ in range(11)]
    seeds = [41, 41] + list(range(700, 710))  # two games share a pitch slot: two spaces
    return rulebases, seeds


def test_the_first_observation_is_there_before_the_first_tick(games):
    batch = GameBatch(*games, SHORT, VOCABULARY)
    seen = batch.observation
    assert len(batch.world.spaces) == 2 and (batch.state.ticks == 0).all()
    ball, goal = VOCABULARY.object_names.index(BALL), VOCABULARY.object_names.index(GOAL)
    goal_distance = VOCABULARY.input_names.index(VOCABULARY.objects[GOAL][DISTANCE])
    assert seen.visible[:, goal].all()  # the player starts facing the goal it attacks
    assert (seen.inputs[:, goal_distance] > 50.0).all()
    assert (np.isnan(seen.inputs).any(axis=1) == ~seen.visible[:, ball]).all()
    assert (seen.facing == 0.0).all() and (seen.ball_x == 0.0).all() and (seen.player_x <= 0.0).all()
    constants = SHORT.world.constants()
    for g in range(batch.games):  # what perception gives from the start positions
        _, _, ball_seen, distance, _, goal_seen = perceive(seen.player_x[g], seen.player_y[g], 0.0, seen.ball_x[g],
                                                           seen.ball_y[g], constants)
        assert (ball_seen, goal_seen, distance) == (seen.visible[g, ball], True, seen.inputs[g, goal_distance])
    assert (batch.decision.action == NO_ACTION).all() and (batch.decision.strengths == 0.0).all()


def test_the_first_tick_decides_on_exactly_that_observation(games):
    batch = GameBatch(*games, SHORT, VOCABULARY)
    first = [field.copy() for field in batch.observation]
    batch.step()
    for name, before, after in zip(batch.observation._fields, first, batch.observation):
        np.testing.assert_array_equal(after, before, err_msg=name)
    assert (batch.state.ticks == 1).all()
