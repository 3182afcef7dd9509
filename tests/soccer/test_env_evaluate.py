"""SoccerEnv (the UI's batch of one) and the GA's evaluator."""

import pickle
from statistics import fmean

from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.demo import demo_rulebase
from soccer_lab.soccer.engine import play_game, play_games
from soccer_lab.soccer.env import SoccerEnv
from soccer_lab.soccer.evaluate import SimpleSoccerEvaluator, game_seeds

VOCABULARY = Vocabulary.default()


def run(env, seed, ticks):
    env.reset(seed)
    return [env.step() for _ in range(ticks)]


def test_env_reset_step_is_deterministic_and_follows_the_engine():
    env = SoccerEnv(demo_rulebase(), GameConfig(max_ticks=150))
    first = run(env, 9, 150)
    assert first == run(env, 9, 150)
    assert first[0].tick == 1 and first[-1].tick == 150
    result, trace = play_game(demo_rulebase(), 9, GameConfig(max_ticks=150))
    assert [s.action for s in first[:20]] == [None if a < 0 else env._batch.vocabulary.action_names[a]
                                             for a in trace.action[:20]]
    final = env.step()  # closes the books of the 150th tick
    assert final.done and final.end_reason == "max-ticks" and final.goals == result.goals
    assert final.fitness == result.fitness
    assert env.step() == final  # a finished game stays finished


def test_env_state_shows_what_the_player_sees():
    env = SoccerEnv(demo_rulebase())
    start = env.reset(3)
    assert start.tick == 0 and start.facing == 0.0 and start.ball[0] == 0.0 and not start.done
    # reset returns the first observation: the goal is always in view from the start
    assert start.visible["GOAL"] and start.inputs["goal_distance"] > 50.0 and start.action is None
    state = env.step()
    assert state.visible["GOAL"] and state.inputs["goal_distance"] > 50.0
    assert (state.inputs["ball_distance"] is None) == (not state.visible["BALL"])
    assert len(state.strengths) == len(demo_rulebase()) and len(state.ball_trail) >= 1


def test_env_set_rulebase_keeps_the_game_going():
    env = SoccerEnv(demo_rulebase())
    env.reset(3)
    for _ in range(5):
        env.step()
    state = env.set_rulebase(parse_rulebase("if Goal is not At then Turn Right", VOCABULARY))
    assert state.tick == 5
    after = env.step()
    assert after.action == "TURN" and after.parameters == {"direction": 45.0}
    assert after.facing != state.facing


def test_evaluator_is_picklable_and_matches_play_games():
    evaluator = pickle.loads(pickle.dumps(SimpleSoccerEvaluator(GameConfig(max_ticks=100))))
    demo = demo_rulebase()
    assert evaluator([demo, demo], [1, 2]) == play_games([demo, demo], [1, 2], GameConfig(max_ticks=100))


def test_evaluator_means_over_several_games():
    config = GameConfig(max_ticks=100, games_per_evaluation=3)
    demo = demo_rulebase()
    [mean] = SimpleSoccerEvaluator(config)([demo], [5])
    games = play_games([demo] * 3, game_seeds(5, 3), GameConfig(max_ticks=100))
    assert mean.fitness == fmean(g.fitness for g in games)  # exactly rounded, whatever the order of the sum
    assert mean.min_ball_goal_distance == min(g.min_ball_goal_distance for g in games)
    assert len(set(game_seeds(5, 3))) == 3 and game_seeds(5, 1) == [5]


def test_the_ball_trail_is_the_last_six_seconds_of_its_path_not_its_last_moves():
    """A shot long past leaves the pitch: once the ball has rested TRAIL_LENGTH ticks its trail is one point."""
    from soccer_lab.soccer.env import TRAIL_LENGTH

    spinning = parse_rulebase("if Goal is not At then Turn Right", VOCABULARY)  # the ball is never touched
    env = SoccerEnv(spinning)
    env.reset(seed=3)
    for _ in range(TRAIL_LENGTH + 5):
        state = env.step()
    assert len(state.ball_trail) == TRAIL_LENGTH and len(set(state.ball_trail)) == 1


def test_new_rules_forget_what_the_old_ones_did_in_the_world():
    """The outcome shown under a decision is that decision's: after new rules, none until the next tick."""
    env = SoccerEnv(demo_rulebase())
    env.reset(seed=3)
    assert env.step().outcome is not None
    state = env.set_rulebase(parse_rulebase("if Goal is not At then Turn Right", VOCABULARY))
    assert state.outcome is None
    assert env.step().outcome is not None
