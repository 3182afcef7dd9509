"""Matches in the engine (soccer/match.py): two players and one ball on a pitch with two goals, the right player
in the pitch turned half a turn, halves batched like games, mirrored starts, bodies colliding, goals at both ends."""

from __future__ import annotations

import math

import numpy as np
import pytest

from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig
from soccer_lab.soccer.examples import example
from soccer_lab.soccer.match import OPPONENT, MatchBatch, play_matches

V = SOCCER_VOCABULARY
STRIKER, DEMO, HUNTER, DRIBBLER = (example(name).rulebase(V) for name in ("striker", "demo", "hunter", "dribbler"))
STILL = parse_rulebase("if Ball is not At then DoNothing", V)  # stands still while it sees the ball
SHORT = GameConfig(max_ticks=300)
HALF_LENGTH = GameConfig().world.pitch_length / 2


def place(batch: MatchBatch, h: int, left=None, right=None, ball=None, ball_velocity=None) -> None:
    """Put half h's bodies at pitch positions (metres, the left player's frame) before its first tick."""
    left_body, _, ball_body, _, right_body, _ = batch.world.objects(h)
    ox, oy = batch.world.pitches.offsets[h]
    for body, xy in ((left_body, left), (right_body, right), (ball_body, ball)):
        if xy is not None:
            body.position = (ox + xy[0], oy + xy[1])
    if ball_velocity is not None:
        ball_body.velocity = ball_velocity
    batch.state.last_players[h] = [*(left_body.position - (ox, oy)), *(right_body.position - (ox, oy))]
    batch.state.last_ball[h] = ball_body.position - (ox, oy)


def pitch_positions(batch: MatchBatch, h: int) -> list[tuple[float, float]]:
    left_body, _, ball_body, _, right_body, _ = batch.world.objects(h)
    ox, oy = batch.world.pitches.offsets[h]
    return [(body.position.x - ox, body.position.y - oy) for body in (left_body, right_body, ball_body)]


def test_a_match_alone_plays_as_in_a_batch_with_others():
    config = GameConfig(max_ticks=400, noise=True)
    seeds = [3, 11, 12, 40]
    together = play_matches(STRIKER, DEMO, seeds, config, V)
    alone = [play_matches(STRIKER, DEMO, [seed], config, V)[0] for seed in seeds]
    assert together == alone
    mixed = MatchBatch([(HUNTER, DRIBBLER), (STRIKER, DEMO), (DRIBBLER, STRIKER), (DEMO, STRIKER)], [5, 3, 3, 3],
                       config, V).run()
    assert (mixed[1], mixed[3]) == together[0].halves
    assert sum(sum(m.goals) for m in together) > 0  # the matches were played, not stalled


def test_each_match_is_two_halves_from_one_start_with_the_sides_swapped():
    batch = MatchBatch([(STRIKER, DEMO), (DEMO, STRIKER)], [7, 7], SHORT, V)
    first, second = pitch_positions(batch, 0), pitch_positions(batch, 1)
    assert first == second
    (lx, _), (rx, _), (bx, _) = first
    assert lx < 0 < rx and bx == 0  # each player in its own half, the ball on the centre line
    played = play_matches(STRIKER, DEMO, [7], SHORT, V)[0]
    assert played.goals == (played.halves[0].goals[0] + played.halves[1].goals[1],
                            played.halves[0].goals[1] + played.halves[1].goals[0])


@pytest.mark.parametrize("vocabulary", [V, Vocabulary.with_opponent()], ids=["chapter", "opponent"])
def test_the_right_player_perceives_the_pitch_turned_half_a_turn(vocabulary):
    """Placed point-symmetrically, both players see the same: ball and goal ahead and to their left
    (a right player seeing the pitch only flipped in x would see them to its right)."""
    batch = MatchBatch([(STRIKER, STRIKER)], [1], SHORT, vocabulary)
    place(batch, 0, left=(-20.0, 7.0), right=(20.0, -7.0), ball=(0.0, 0.0))
    batch.step()
    seen, layout = batch.observation, batch.layout
    assert seen.inputs[0, layout.ball_direction] < 0 and seen.inputs[0, layout.goal_direction] < 0
    np.testing.assert_allclose(seen.inputs[1], seen.inputs[0], atol=1e-6)  # the pitch offset's rounding apart
    np.testing.assert_array_equal(seen.visible[0], seen.visible[1])
    assert (seen.player_x[1], seen.player_y[1]) == pytest.approx((-20.0, 7.0))


def test_a_goal_for_one_is_a_goal_against_the_other():
    batch = MatchBatch([(STILL, STILL), (STILL, STILL)], [2, 9], GameConfig(max_ticks=20), V)
    place(batch, 0, left=(-30.0, 20.0), right=(30.0, 20.0), ball=(HALF_LENGTH - 2.0, 0.0), ball_velocity=(20.0, 0.0))
    place(batch, 1, left=(-30.0, 20.0), right=(30.0, 20.0), ball=(2.0 - HALF_LENGTH, 0.0),
          ball_velocity=(-20.0, 0.0))
    first, second = batch.run()
    assert first.goals == (1, 0)  # into the +x goal: the left player's
    assert second.goals == (0, 1)


def test_the_players_bodies_collide_with_each_other():
    batch = MatchBatch([(STILL, STILL)], [4], GameConfig(max_ticks=5), V)
    place(batch, 0, left=(0.0, 20.0), right=(0.3, 20.0), ball=(0.0, -20.0))
    batch.step()
    batch.step()
    (lx, ly), (rx, ry), _ = pitch_positions(batch, 0)
    assert math.hypot(rx - lx, ry - ly) >= 2 * GameConfig().world.player_size


def test_a_half_ends_idle_only_when_both_players_idle():
    both_still, striker_plays = MatchBatch([(STILL, STILL), (STILL, STRIKER)], [6, 6], SHORT, V).run()
    assert both_still.end_reason == "idle" and both_still.ticks < SHORT.max_ticks
    # the still player idles from the start as in the first half; the half went on while the striker played
    assert striker_plays.ticks > both_still.ticks + SHORT.idle_ticks and striker_plays.goals[1] >= 1


def test_the_opponent_vocabulary_is_off_by_default_and_lets_rules_see_the_opponent():
    assert OPPONENT not in V.objects  # the chapter's model unchanged
    vocabulary = Vocabulary.with_opponent()
    watcher = parse_rulebase("if Opponent is not VeryFar then DoNothing", vocabulary)
    batch = MatchBatch([(watcher, watcher)], [5], SHORT, vocabulary)
    place(batch, 0, left=(-10.0, 0.0), right=(10.0, 0.0), ball=(0.0, 30.0))
    batch.step()
    distance = vocabulary.input_names.index("opponent_distance")
    assert batch.observation.inputs[:, distance] == pytest.approx([20.0, 20.0])
    assert batch.decision.strengths[:, 0].min() > 0  # the rule naming the opponent fired on both sides


def test_the_ga_writes_plays_and_notates_rules_about_the_opponent():
    from soccer_lab.fuzzy.random_rulebase import random_rulebase
    from soccer_lab.ga.codec import ChromosomeCodec
    from soccer_lab.ga.notation import CompactNotation

    vocabulary = Vocabulary.with_opponent()
    rng = np.random.default_rng(0)
    players = [random_rulebase(rng, vocabulary, rules=10) for _ in range(10)]
    assert any(premise.object == OPPONENT for player in players for rule in player for premise in rule.premises)
    codec, notation = ChromosomeCodec(vocabulary), CompactNotation(vocabulary)
    for player in players:
        chromosome = codec.encode(player)
        assert codec.decode(chromosome) == player
        assert ("(Op," in notation.format(chromosome)) == (OPPONENT in str(player))  # the chapter's notation
    played = play_matches(players[0], players[1], [0, 1], SHORT, vocabulary)
    assert play_matches(players[0], players[1], [0, 1], SHORT, vocabulary) == played


def test_a_malformed_vocabulary_extension_is_one_clear_error(tmp_path):
    from soccer_lab.fuzzy.vocabulary import VocabularyError

    broken, unknown = tmp_path / "broken.json", tmp_path / "unknown.json"
    broken.write_text('{"objects": ["OPPONENT"]}')
    unknown.write_text('{"objects": {"OPPONENT": {"distance": "nowhere", "direction": "nowhere"}}}')
    for path, fragment in ((broken, "objects is not a mapping"), (unknown, "not a distance input"),
                           (tmp_path / "missing.json", "cannot read")):
        with pytest.raises(VocabularyError, match=fragment):
            V.extended(path)


def test_match_fitness_carries_the_chapters_composite_over_to_goal_difference():
    from soccer_lab.soccer.match import match_fitness

    length = 100.0
    assert match_fitness(2, 5, 0.0, length) == 0.25  # a win by 2 scores as 2 goals alone
    assert match_fitness(1, 0, 50.0, length) == 0.5  # a win needs no kick (a goal pushed in)
    assert match_fitness(0, 0, 0.0, length) == 1.0  # no kick, no win: the chapter's "no ball movement"
    assert match_fitness(0, 3, 0.0, length) == 0.5
    assert match_fitness(0, 3, 50.0, length) == 0.625  # a draw: the ball's approach at half weight
    assert match_fitness(-1, 3, 0.0, length) == 0.625  # a loss by 1: half the margin's range
    assert match_fitness(-3, 3, 150.0, length) == 0.9375  # the approach capped at the field's length
    assert match_fitness(-1000, 3, 150.0, length) < 1.0  # any player that kicked beats one that never did


def test_the_match_evaluator_scores_each_player_by_its_matches_alone_or_in_a_population():
    from soccer_lab.soccer.match import MatchEvaluator, match_fitness

    evaluate = MatchEvaluator(DEMO, SHORT, V)
    players, seeds = [STRIKER, HUNTER, DRIBBLER, DEMO], [10, 11, 12, 13]
    together = evaluate(players, seeds)
    assert together == [evaluate([player], [seed])[0] for player, seed in zip(players, seeds)]
    for player, seed, result in zip(players, seeds, together):
        played = play_matches(player, DEMO, [seed], SHORT, V)[0]
        kicks = played.halves[0].kicks[0] + played.halves[1].kicks[1]
        assert (result.goals, result.kicks) == (played.goals[0], kicks)
        assert result.fitness == match_fitness(played.goals[0] - played.goals[1], kicks,
                                               result.min_ball_goal_distance, SHORT.world.pitch_length)
    twice = MatchEvaluator(DEMO, SHORT.model_copy(update={"games_per_evaluation": 2}), V)([STRIKER], [10])[0]
    assert twice.ticks > 0 and twice.fitness <= 1.0


def test_rules_that_do_not_name_the_opponent_play_the_same_in_both_vocabularies():
    seeds = [0, 1, 2]
    assert play_matches(STRIKER, DEMO, seeds, SHORT, Vocabulary.with_opponent()) == play_matches(
        STRIKER, DEMO, seeds, SHORT, V)


def test_crowded_ticks_count_when_both_players_are_near_the_ball_and_only_then():
    from soccer_lab.soccer.match import CROWD_DISTANCE

    batch = MatchBatch([(STILL, STILL), (STILL, STILL)], [1, 2], GameConfig(max_ticks=10, idle_ticks=1000), V)
    place(batch, 0, left=(-1.0, 0.0), right=(1.0, 0.0), ball=(0.0, CROWD_DISTANCE / 2))  # both near
    place(batch, 1, left=(-1.0, 0.0), right=(30.0, 0.0), ball=(0.0, CROWD_DISTANCE / 2))  # only the left
    crowded, apart = batch.run()
    assert crowded.crowded == crowded.ticks == 10 and crowded.crowd_share == 1.0
    assert apart.crowded == 0 and apart.crowd_share == 0.0


def test_the_hall_evaluator_scores_each_opponent_alike_alone_or_in_a_population():
    from soccer_lab.soccer.evaluate import game_seeds
    from soccer_lab.soccer.match import HallEvaluator, match_fitness

    evaluate = HallEvaluator(config=SHORT).against([DEMO, HUNTER])
    players, seeds = [STRIKER, DRIBBLER, DEMO], [21, 22, 23]
    together = evaluate(players, seeds)
    assert together == [evaluate([player], [seed])[0] for player, seed in zip(players, seeds)]
    for player, seed, result in zip(players, seeds, together):
        fitnesses = []
        for opponent, match_seed in zip([DEMO, HUNTER], game_seeds(seed, 2)):
            played = play_matches(player, opponent, [match_seed], SHORT, V)[0]
            kicks = played.halves[0].kicks[0] + played.halves[1].kicks[1]
            distance = min(played.halves[0].min_ball_goal_distance[0], played.halves[1].min_ball_goal_distance[1])
            fitnesses.append(match_fitness(played.goals[0] - played.goals[1], kicks, distance,
                                           SHORT.world.pitch_length))
        assert result.fitness == pytest.approx(sum(fitnesses) / 2)  # the mean over the opponents
    with pytest.raises(ValueError, match="opponent"):
        HallEvaluator(config=SHORT)([STRIKER], [1])
