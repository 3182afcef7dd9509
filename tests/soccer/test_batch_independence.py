"""A game's result and trace do not depend on the batch it is played in (docs/design.md, "A game does not depend on its batch")."""

import json
import subprocess
import sys

import numpy as np
import pytest

from soccer_lab.fuzzy.random_rulebase import random_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.demo import demo_rulebase
from soccer_lab.soccer.engine import GameBatch, play_game
from soccer_lab.soccer.random_stream import mix64, next_uniform, seed_states
from soccer_lab.soccer.config import WorldConfig
from soccer_lab.soccer.world import PitchOutline, PitchSpace, RoundBody, pitch_offset, pitch_slot

VOCABULARY = Vocabulary.default()

# Assisted skills: random rulebases then reach the ball often, so contacts are part of what is compared.
SHORT = GameConfig(max_ticks=300, skills="assisted")
GAMES = 60


@pytest.fixture(scope="module")
def population():
    rng = np.random.default_rng(2024)
    demo = demo_rulebase()
    rulebases = [demo if g % 5 == 0 else random_rulebase(rng, VOCABULARY, rules=10) for g in range(GAMES)]
    seeds = [int(s) for s in rng.integers(0, 2**63, GAMES)]
    return rulebases, seeds


def play_recorded(rulebases, seeds, config=SHORT):
    """Results and, per game, every tick's (observed pose and ball, action, direction, power, goals)."""
    batch = GameBatch(rulebases, seeds, config, VOCABULARY)
    rows = [[] for _ in rulebases]
    seen, decided = batch.observation, batch.decision
    while not batch.finished:
        before = batch.state.ticks.copy()
        batch.step()
        for g in np.flatnonzero(batch.state.ticks > before):
            pose = [seen.player_x[g], seen.player_y[g], seen.facing[g], seen.ball_x[g], seen.ball_y[g]]
            rows[g].append(np.concatenate([pose, [decided.action[g], batch.state.goals[g]], decided.values[g]]))
    return batch.results(), [np.array(r) for r in rows]


@pytest.fixture(scope="module")
def together(population):
    return play_recorded(*population)


def assert_same(expected, got, games):
    results, traces = expected
    got_results, got_traces = got
    for i, g in enumerate(games):
        assert got_results[i] == results[g], f"game {g}"
        np.testing.assert_array_equal(got_traces[i], traces[g], err_msg=f"game {g}")


@pytest.mark.parametrize("cut", [GAMES // 2, 17])
def test_split_batches_give_identical_results_and_traces(population, together, cut):
    rulebases, seeds = population
    assert_same(together, play_recorded(rulebases[:cut], seeds[:cut]), range(cut))
    assert_same(together, play_recorded(rulebases[cut:], seeds[cut:]), range(cut, GAMES))


def test_reversed_order_gives_identical_results_and_traces(population, together):
    rulebases, seeds = population
    results, traces = play_recorded(rulebases[::-1], seeds[::-1])
    assert_same(together, (results[::-1], traces[::-1]), range(GAMES))


def test_games_alone_match_the_batch_and_play_game_traces(population, together):
    rulebases, seeds = population
    results, traces = together
    for g in (0, 1, 7, 33, GAMES - 1):
        assert_same(together, play_recorded([rulebases[g]], [seeds[g]]), [g])
        result, trace = play_game(rulebases[g], seeds[g], SHORT)
        assert result == results[g]
        np.testing.assert_array_equal(trace.player_x, traces[g][:, 0])
        np.testing.assert_array_equal(trace.ball_y, traces[g][:, 4])
        np.testing.assert_array_equal(trace.action, traces[g][:, 5])


def test_the_population_really_plays(together):
    results, _ = together
    assert sum(r.kicks > 0 for r in results) >= GAMES // 3  # contacts with ball, walls and posts happen
    assert sum(r.goals for r in results) > 0


def test_games_sharing_a_slot_play_in_separate_spaces_with_the_same_result():
    demo = demo_rulebase()
    seeds = [41, 41, 41, 42]
    assert pitch_slot(41) != pitch_slot(42)
    batch = GameBatch([demo] * 4, seeds, SHORT, VOCABULARY)
    assert len(batch.world.spaces) == 3 and batch.world.pitches.layer.tolist() == [0, 1, 2, 0]
    results = batch.run()
    alone = play_game(demo, 41, SHORT, trace=False)[0]
    assert results[:3] == [alone] * 3
    assert results[3] == play_game(demo, 42, SHORT, trace=False)[0]


def test_slots_spread_nearby_seeds():
    slots = {pitch_slot(s) for s in range(1000)}
    assert len(slots) >= 995


def test_game_pushed_into_the_end_line_wall_is_the_same_alone_and_as_the_116th_game():
    # Found by scoring 195 random rulebases: the player pins the ball against the end line wall,
    # pymunk's contact geometry differed by one ulp between pitch offsets, and the game diverged.
    rng = np.random.default_rng(0)
    rulebases = [random_rulebase(rng, VOCABULARY, rules=10) for _ in range(116)]
    seeds = [5000 + g for g in range(116)]
    found = GameConfig(skills="assisted")  # the skill set it was found with
    in_batch = GameBatch(rulebases, seeds, found, VOCABULARY).run()[115]
    assert in_batch.kicks > 0 and in_batch.ticks == 1000
    assert GameBatch(rulebases[97:], seeds[97:], found, VOCABULARY).run()[18] == in_batch
    assert GameBatch([rulebases[115]], [seeds[115]], found, VOCABULARY).run()[0] == in_batch


def test_slot_hash_is_splitmix64_as_the_game_streams_use_it():
    states = seed_states([12345, 2**64 + 7])  # seeds are taken modulo 2**64
    assert next_uniform(states, 0) == (mix64(12345) >> 11) * 2.0**-53
    assert next_uniform(states, 1) == (mix64(7) >> 11) * 2.0**-53


# The game found against the end line wall (above), played as the first game of a fresh process.
WALL_GAME = """
import json, sys
import numpy as np
from soccer_lab.fuzzy.random_rulebase import random_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.engine import play_game
rng = np.random.default_rng(0)
rulebase = [random_rulebase(rng, Vocabulary.default(), rules=10) for _ in range(116)][115]
result, trace = play_game(rulebase, 5115, GameConfig(skills="assisted"))
json.dump({"result": repr(result), "player_x": trace.player_x.tolist(), "ball_y": trace.ball_y.tolist(),
           "action": trace.action.tolist()}, sys.stdout)
"""


def test_a_game_in_reused_spaces_equals_it_first_in_a_fresh_process():
    # Spaces and pitches are kept for the process (soccer/world.py): the game meets a moved pitch, the
    # idle pitch left at its own slot by another game, and a batch around it, after batches of other
    # sizes; each time it must be the very game a fresh process plays first.
    fresh = json.loads(subprocess.run([sys.executable, "-c", WALL_GAME], capture_output=True, text=True,
                                      check=True).stdout)
    rng = np.random.default_rng(0)
    rulebases = [random_rulebase(rng, VOCABULARY, rules=10) for _ in range(116)]
    wall, config = rulebases[115], GameConfig(skills="assisted")
    others = [random_rulebase(rng, VOCABULARY, rules=10) for _ in range(40)]
    plays = []
    GameBatch(others, [900 + g for g in range(40)], config, VOCABULARY).run()  # idle pitches at other slots
    plays.append(play_game(wall, 5115, config))  # on a moved pitch
    GameBatch(others[:7], [5115, *range(700, 706)], config, VOCABULARY).run()  # another game at its slot
    plays.append(play_game(wall, 5115, config))  # on the idle pitch left at its slot
    batch = GameBatch([*others[:9], wall, *others[9:20]], [*range(800, 809), 5115, *range(809, 820)], config,
                      VOCABULARY)
    in_batch = batch.run()[9]
    for result, trace in plays:
        assert repr(result) == fresh["result"]
        assert trace.player_x.tolist() == fresh["player_x"]
        assert trace.ball_y.tolist() == fresh["ball_y"]
        assert trace.action.tolist() == fresh["action"]
    assert repr(in_batch) == fresh["result"]
    assert in_batch.kicks > 0 and in_batch.ticks == 1000


def test_a_body_a_game_left_in_a_wall_contact_is_taken_again_at_rest_as_a_new_one():
    # A ball pressed into the own end line wall leaves its last step with Chipmunk's bias velocity
    # (the contact's position correction); taken again for another game, it must stay where it is
    # put for a step, as a new body does.
    world = WorldConfig()
    pitch_space = PitchSpace(PitchOutline.of(world))
    ball = RoundBody(world.ball_mass, world.ball_size, world.elasticity)
    ox, oy = pitch_offset(0)
    pitch_space.take_pitch(0)
    rest = (ox, oy + 10.0)

    body, shape = pitch_space.take_body(ball, ox - world.pitch_length / 2 + world.ball_size / 2, oy)
    pitch_space.space.add(body, shape)
    body.velocity = (-10.0, 0.0)
    pitch_space.space.step(world.tick_seconds)
    assert pitch_space.space.shape_query(shape)  # still in contact with the wall
    pitch_space.space.remove(body, shape)
    pitch_space.give_back_body(ball, body, shape)

    again, again_shape = pitch_space.take_body(ball, *rest)
    assert again is body
    new, new_shape = RoundBody(*ball).build()
    new.position = rest
    for taken, taken_shape in ((again, again_shape), (new, new_shape)):
        pitch_space.space.add(taken, taken_shape)
        pitch_space.space.step(world.tick_seconds)
        assert (taken.position, taken.velocity) == (rest, (0.0, 0.0))
        pitch_space.space.remove(taken, taken_shape)
