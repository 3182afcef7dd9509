"""Rule usage over games, counted from one batch, against the games' own tick-by-tick traces; and the
behaviour-checked simplification: the rules it drops leave every game identical."""

import numpy as np
import pytest

from soccer_lab.fuzzy.batched import NO_ACTION
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.simplify import CHECKED, EXACT
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.engine import play_game
from soccer_lab.soccer.simplify import NEVER_WON, replay_difference, simplify_rulebase
from soccer_lab.soccer.usage import measure_usage

VOCABULARY = Vocabulary.default()
GAME = GameConfig(max_ticks=200, idle_ticks=60)
SEEDS = [3, 4, 5, 6, 7]
STRIKER = parse_rulebase("""\
if Ball is At then KickTowardGoal High
if Ball is not At and Ball is not VeryFar then GoToBall VeryHigh
if Ball is Near then Dash High
if Ball is VeryFar then RunTowardBall Low
if Goal is Left then Turn Left
if Ball is Straight and Goal is Far then Dash Low
if Goal is At then Kick Left High
""", VOCABULARY)


def expected_usage(rulebase, seeds):
    """The same counts, in plain Python, from each game played alone with its trace."""
    actions = [VOCABULARY.action_names.index(rule.consequent.action) for rule in rulebase]
    fired, won, decided, strength = ([0] * len(rulebase) for _ in range(4))
    performed, hunt, ticks = {}, 0, 0
    for seed in seeds:
        _, trace = play_game(rulebase, seed, GAME)
        for strengths, action in zip(trace.strengths.tolist(), trace.action.tolist()):
            ticks += 1
            if action == NO_ACTION:
                hunt += 1
            else:
                performed[action] = performed.get(action, 0) + 1
                mine = [s if a == action else -1.0 for s, a in zip(strengths, actions)]
                decided[mine.index(max(mine))] += 1
            for r, s in enumerate(strengths):
                if s > 0:
                    fired[r] += 1
                    strength[r] += s
                    won[r] += actions[r] == action
    return fired, won, decided, strength, performed, hunt, ticks


def test_usage_counts_what_the_games_traces_show():
    usage, _ = measure_usage(STRIKER, SEEDS, GAME, VOCABULARY)
    fired, won, decided, strength, performed, hunt, ticks = expected_usage(STRIKER, SEEDS)
    assert [r.fired for r in usage.rules] == fired
    assert [r.won for r in usage.rules] == won
    assert [r.decided for r in usage.rules] == decided
    for rule, total, count in zip(usage.rules, strength, fired):
        assert (rule.mean_strength is None) if count == 0 else rule.mean_strength == pytest.approx(total / count)
    assert usage.actions == {a: performed.get(i, 0) for i, a in enumerate(VOCABULARY.action_names)}
    assert (usage.hunt, usage.ticks) == (hunt, ticks)
    assert usage.hunt_share == hunt / ticks
    assert [r.ticks for r in usage.results] == [play_game(STRIKER, s, GAME, trace=False)[0].ticks for s in SEEDS]


def test_usage_is_consistent_and_informative():
    usage, _ = measure_usage(STRIKER, SEEDS, GAME, VOCABULARY)
    assert all(r.decided <= r.won <= r.fired for r in usage.rules)
    assert sum(r.decided for r in usage.rules) == usage.ticks - usage.hunt == sum(usage.actions.values())
    assert usage.rules[0].won > 0 and usage.rules[1].won > 0  # the striker's two rules play
    # where the ball is Near (2 to 8 m) GoToBall's rule is 1 and comes first: Dash High fires but never wins
    assert usage.rules[2].fired > 0 and usage.rules[2].won == 0


def test_first_difference_finds_the_first_tick_that_changed():
    _, original = measure_usage(STRIKER, SEEDS, GAME, VOCABULARY, record=True)
    assert original.first_difference(original) is None
    without_kick = Rulebase(STRIKER.rules[1:])
    message, _ = replay_difference(original, measure_usage(STRIKER, SEEDS, GAME, VOCABULARY)[0].results,
                                   without_kick, SEEDS, GAME, VOCABULARY)
    # from the traces: the first game (and tick) where the decisions part
    first = None
    for game, seed in enumerate(SEEDS):
        _, a = play_game(STRIKER, seed, GAME)
        _, b = play_game(without_kick, seed, GAME)
        n = min(len(a), len(b))
        same = (a.action[:n] == b.action[:n]) & (a.power[:n] == b.power[:n]) & (a.direction[:n] == b.direction[:n])
        if not same.all() or len(a) != len(b):
            first = (game, int(np.argmin(same)) if not same.all() else n)
            break
    assert first is not None
    assert message == f"game {first[0] + 1} (seed {SEEDS[first[0]]}) differed at tick {first[1]}"


def test_checked_step_drops_never_won_rules_and_the_games_replay_identically():
    result = simplify_rulebase(STRIKER, VOCABULARY, SEEDS, GAME)
    step = result.simplification.steps[-1]
    assert (step.name, step.kind, step.applied, step.games) == (NEVER_WON, CHECKED, True, len(SEEDS))
    dropped = {c.rule for c in step.changes}
    assert 3 in dropped
    assert dropped == {i + 1 for i, r in enumerate(result.usage.rules) if r.won == 0}
    simplified = result.simplification.rulebase
    assert len(simplified) == len(STRIKER) - len(dropped)
    for seed, before in zip(SEEDS, result.usage.results):
        after, trace = play_game(simplified, seed, GAME)
        _, original = play_game(STRIKER, seed, GAME)
        assert after == before
        for field in ("action", "direction", "power", "player_x", "player_y", "facing", "ball_x", "ball_y"):
            assert getattr(trace, field).tobytes() == getattr(original, field).tobytes()
    assert all(s.kind == EXACT for s in result.simplification.steps[:-1])


def test_checked_step_on_evolved_rulebases_keeps_every_game(evolved_rulebases):
    dropped = 0
    for rulebase in evolved_rulebases[:8]:
        result = simplify_rulebase(rulebase, VOCABULARY, SEEDS, GAME)
        step = result.simplification.steps[-1]
        only_hunts = result.usage.hunt == result.usage.ticks
        assert step.applied != only_hunts or not step.changes
        dropped += len(step.changes) if step.applied else 0
        replayed, _ = measure_usage(result.simplification.rulebase, SEEDS, GAME, VOCABULARY)
        assert replayed.results == result.usage.results == result.results
    assert dropped > 0


def test_without_games_only_the_exact_steps_run():
    result = simplify_rulebase(STRIKER, VOCABULARY)
    assert result.usage is None and all(s.kind == EXACT for s in result.simplification.steps)


def test_a_player_that_only_hunts_keeps_its_rules():
    never = parse_rulebase("if Ball is VeryFar and Goal is At then Dash", VOCABULARY)
    result = simplify_rulebase(never, VOCABULARY, SEEDS[:2], GAME)
    assert result.usage.hunt == result.usage.ticks
    assert not result.simplification.steps[-1].applied and len(result.simplification.rulebase) == 1
