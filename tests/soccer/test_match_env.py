"""The steppable match the UI shows (soccer/match_env.py): tick by tick, the same match play_matches counts."""

from __future__ import annotations

import math

import pytest

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig
from soccer_lab.soccer.examples import example
from soccer_lab.soccer.match import play_matches
from soccer_lab.soccer.match_env import MatchEnv

V = SOCCER_VOCABULARY
STRIKER, DEMO = (example(name).rulebase(V) for name in ("striker", "demo"))
SHORT = GameConfig(max_ticks=300, noise=True)
HALF_LENGTH = GameConfig().world.pitch_length / 2


def play_out(env: MatchEnv, seed: int) -> list:
    states = [env.reset(seed)]
    while not states[-1].done:
        states.append(env.step())
    return states


@pytest.mark.parametrize("seed", [3, 12])
def test_a_match_stepped_tick_by_tick_is_the_match_play_matches_counts(seed):
    states = play_out(MatchEnv(STRIKER, DEMO, SHORT, V), seed)
    expected = play_matches(STRIKER, DEMO, [seed], SHORT, V)[0]
    assert states[-1].result == expected
    assert states[-1].goals == expected.goals
    # the score shown along the way only ever grows, to the result's
    scores = [s.goals for s in states]
    assert all(a <= b for earlier, later in zip(scores, scores[1:]) for a, b in zip(earlier, later))


def test_a_match_with_goals_shows_them_to_the_player_who_scored():
    for seed in range(20):
        expected = play_matches(STRIKER, DEMO, [seed], SHORT, V)[0]
        if expected.halves[0].goals[0] and expected.halves[1].goals[1]:
            break
    else:
        pytest.fail("no start where the striker scores in both halves")
    states = play_out(MatchEnv(STRIKER, DEMO, SHORT, V), seed)
    first_half_end = next(s for s in states if s.half_over)
    assert first_half_end.half == 1 and first_half_end.goals[0] == expected.halves[0].goals[0]
    assert states[-1].goals == expected.goals


def test_the_second_half_kicks_off_from_the_same_start_with_the_sides_swapped():
    env = MatchEnv(STRIKER, DEMO, SHORT, V)
    first = env.reset(5)
    while not env.state.half_over:
        env.step()
    assert env.state.half == 1  # the first half's end is shown before the kick-off
    second = env.step()
    assert (second.half, second.tick, second.a_on_left, first.a_on_left) == (2, 0, False, True)
    assert second.players == first.players[::-1]  # B starts where A did, and A where B did
    assert second.ball == first.ball
    assert first.facings == (0.0, 180.0) and second.facings == (180.0, 0.0)  # each faces the goal it attacks
    assert second.goals == env.state.goals  # the first half's goals carry over


def test_each_player_thinks_in_its_own_frame_with_its_own_rules():
    env = MatchEnv(STRIKER, DEMO, SHORT, V)
    kick_offs = [env.reset(5)]
    while not env.state.half_over:
        env.step()
    kick_offs.append(env.step())
    for start in kick_offs:  # the first half's kick-off, then the second's
        env.reset(5)
        while env.state.half != start.half:
            env.step()
        minds = env.step().minds
        assert [len(m.strengths) for m in minds] == [len(STRIKER), len(DEMO)]
        for player, mind, attacked_x in zip(start.players, minds, (1, -1) if start.a_on_left else (-1, 1)):
            # facing the goal it attacks from its own half, each sees that goal at its true distance
            goal = (attacked_x * HALF_LENGTH, 0.0)
            assert mind.visible["GOAL"]
            assert mind.inputs["goal_distance"] == pytest.approx(math.dist(player, goal))
            assert mind.inputs["goal_direction"] == pytest.approx(
                math.degrees(math.atan2(attacked_x * (goal[1] - player[1]), attacked_x * (goal[0] - player[0]))))


def test_the_same_seed_plays_the_same_match_bit_for_bit():
    runs = [play_out(MatchEnv(STRIKER, DEMO, SHORT, V), 9) for _ in range(2)]
    assert runs[0] == runs[1]
    other = play_out(MatchEnv(STRIKER, DEMO, SHORT, V), 10)
    assert [s.players for s in other] != [s.players for s in runs[0]]


def test_a_match_in_the_opponent_vocabulary_agrees_too():
    vocabulary = Vocabulary.with_opponent()
    a, b = (example(name).rulebase(vocabulary) for name in ("striker", "dribbler"))
    states = play_out(MatchEnv(a, b, SHORT, vocabulary), 4)
    assert states[-1].result == play_matches(a, b, [4], SHORT, vocabulary)[0]
    assert "opponent_distance" in states[1].minds[0].inputs


def test_stepping_a_finished_match_changes_nothing_and_step_before_reset_is_refused():
    env = MatchEnv(STRIKER, DEMO, GameConfig(max_ticks=20), V)
    with pytest.raises(RuntimeError):
        env.step()
    states = play_out(env, 1)
    assert env.step() == states[-1]


def test_each_kick_off_shows_the_observation_the_first_tick_decides_on():
    env = MatchEnv(STRIKER, DEMO, SHORT, V)
    kick_off = env.reset(8)
    first_tick = env.step()
    for before, decided in zip(kick_off.minds, first_tick.minds):
        assert before.inputs == decided.inputs and before.visible == decided.visible
        assert before.action is None and before.outcome is None  # nothing decided yet
    while not env.state.half_over:
        env.step()
    second_kick_off = env.step()
    assert second_kick_off.half == 2
    assert [m.inputs for m in second_kick_off.minds] == [m.inputs for m in env.step().minds]
