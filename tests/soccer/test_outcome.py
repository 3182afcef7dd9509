"""What the player did after each decision: the engine keeps every tick's command and why, and the words
a teacher reads for them (soccer/outcome.py)."""

from collections import Counter

from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.engine import play_game
from soccer_lab.soccer.examples import example
from soccer_lab.soccer.outcome import Outcome, end_reason_sentence, skill_set_sentence
from soccer_lab.soccer.skills import (ACTED, AT_BALL, BALL_OUT_OF_VIEW, DASH, FETCHING, GOAL_OUT_OF_VIEW, HUNT_BALL,
                                      HUNT_LAST_SEEN, KICK, NO_DASH_NEEDED, NONE, NOT_KICKABLE, TURN, TURN_FIRST)

VOCABULARY = Vocabulary.default()
STRIKER = example("striker").rulebase(VOCABULARY)


def test_the_two_rule_striker_freezes_under_sighted_skills_and_the_trace_says_why():
    """The issue's first complaint: "KickTowardGoal 1.00" on screen, nothing moves, game over (idle)."""
    result, trace = play_game(STRIKER, seed=1, config=GameConfig(skills="sighted"))
    assert result.end_reason == "idle"
    idle_tail = trace.outcome[-90:]  # the last ticks before the end: the refused shot
    assert (idle_tail == GOAL_OUT_OF_VIEW).all()
    assert (trace.command[-90:] == NONE).all()
    kick = VOCABULARY.action_names.index("KICKTOWARDGOAL")
    assert (trace.action[-90:] == kick).all()


def test_under_strict_skills_the_same_rules_shoot_and_never_need_the_goal_in_view():
    result, trace = play_game(STRIKER, seed=1, config=GameConfig(skills="strict"))
    assert result.goals > 0
    reasons = Counter(trace.outcome.tolist())
    assert reasons[GOAL_OUT_OF_VIEW] == 0 and reasons[ACTED] > 0
    kicks = trace.command == KICK
    assert kicks.sum() == result.kicks  # every kick counted is a KICK command the skill sent
    assert (trace.command_value[kicks] > 0).all()


def test_the_hunter_only_hunts():
    """No rule fires: every tick is the default hunt, and says so."""
    result, trace = play_game(example("hunter").rulebase(VOCABULARY), seed=2, config=GameConfig())
    assert result.fitness == 1.0 and (trace.action == -1).all()
    assert set(trace.outcome.tolist()) <= {HUNT_BALL, HUNT_LAST_SEEN} and (trace.command == TURN).all()


def test_assisted_kicking_skills_say_they_are_fetching_the_ball():
    """A kicking rule that wins with the ball out of reach: under assisted skills it runs to the ball first."""
    far_kick = parse_rulebase("if Ball is not At then KickTowardGoal High", VOCABULARY)
    _, trace = play_game(far_kick, seed=3, config=GameConfig(skills="assisted", max_ticks=200))
    fetching = [code - FETCHING for code in trace.outcome.tolist() if code & FETCHING]
    assert fetching and set(fetching) <= {ACTED, TURN_FIRST, BALL_OUT_OF_VIEW, AT_BALL, NO_DASH_NEEDED}
    _, strict = play_game(far_kick, seed=3, config=GameConfig(skills="strict", max_ticks=200))
    assert not any(code & FETCHING for code in strict.outcome.tolist())
    assert NOT_KICKABLE in strict.outcome.tolist()


def test_the_words_for_a_tick():
    kick = Outcome("KICKTOWARDGOAL", NONE, 0.0, 0.0, GOAL_OUT_OF_VIEW)
    assert kick.refused
    assert kick.describe("sighted", VOCABULARY) == (
        "KickTowardGoal: no kick, the goal is not in view (sighted skills: the player knows where the goal is "
        "only while it sees it)")
    assert Outcome("KICK", NONE, 0.0, 0.0, NOT_KICKABLE).describe("strict", VOCABULARY).startswith(
        "Kick: no kick, the ball is not kickable")
    assert Outcome("GOTOBALL", DASH, 62.4, 0.0, ACTED).describe("strict", VOCABULARY) == "GoToBall: dash 62"
    assert Outcome(None, TURN, 45.0, 0.0, HUNT_LAST_SEEN).describe("strict", VOCABULARY) == (
        "No rule fired: the player hunts: turn +45° toward where it last saw the ball")
    fetching = Outcome("KICKTOWARDGOAL", DASH, 100.0, 0.0, ACTED + FETCHING).describe("assisted", VOCABULARY)
    assert "goes to the ball first (assisted skills): dash 100" in fetching and not Outcome(
        "KICKTOWARDGOAL", DASH, 100.0, 0.0, ACTED + FETCHING).refused


def test_end_reasons_and_skill_sets_in_a_sentence():
    assert end_reason_sentence("idle", 1000, 10, 100) == "the player neither moved nor kicked for 100 ticks in a row"
    assert end_reason_sentence("max-ticks", 1000, 10, 100) == "the time was up (1000 ticks)"
    assert end_reason_sentence("goal-cap", 1000, 10, 100) == "the player reached the goal cap (10 goals)"
    for skills in ("strict", "assisted", "sighted"):
        assert len(skill_set_sentence(skills)) > 40
