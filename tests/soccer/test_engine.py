"""The batched engine: world geometry, goals, restarts, end conditions, determinism (docs/research/index.md, "The model")."""

import sys

import numba
import numpy as np
import pymunk
import pytest

from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.random_rulebase import random_rulebase
from soccer_lab.fuzzy.rule import Consequent, Premise, Rule, Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.demo import demo_rulebase
from soccer_lab.soccer.engine import GameBatch, body_vectors, borrowed, play_game, play_games
from soccer_lab.soccer.physics import COLLISION_GAP
from soccer_lab.soccer.world import vectors_address

VOCABULARY = Vocabulary.default()

C = GameConfig().world.constants()
STILL = Rulebase((Rule((Premise("GOAL", "VERYFAR"), Premise("GOAL", "VERYFAR", True)), ("OR",),
                       Consequent("DONOTHING")),))  # fires whenever the goal is in view
EMPTY = Rulebase(())


def scripted(ball, velocity, player=(-40.0, 0.0), rulebase=STILL, config=GameConfig()):
    """A batch of one with the ball placed by hand (metres; velocity in metres per tick)."""
    batch = GameBatch([rulebase], [1], config, VOCABULARY)
    ox, oy = batch.world.pitches.offsets[0]
    p, _, b, _ = batch.world.objects(0)
    p.position = (ox + player[0], oy + player[1])
    b.position = (ox + ball[0], oy + ball[1])
    b.velocity = (velocity[0] / C.tick_seconds, velocity[1] / C.tick_seconds)
    batch.state.last_ball[0] = ball
    batch.state.last_player[0] = player
    return batch


def ball_position(batch):
    ox, oy = batch.world.pitches.offsets[0]
    b = batch.world.objects(0)[2]
    return b.position.x - ox, b.position.y - oy, b.velocity.x * C.tick_seconds, b.velocity.y * C.tick_seconds


def test_ball_rebounds_from_touch_line_with_elasticity():
    batch = scripted((0.0, 32.0), (0.0, 2.5))
    for _ in range(3):
        batch.step()
    x, y, vx, vy = ball_position(batch)
    assert y < 34.0 - C.ball_size + 1e-6
    assert vy < 0.0  # bounced back; about half the (decayed) speed
    assert abs(vy) == pytest.approx(0.5 * 2.5 * C.ball_decay ** 2, rel=0.25)


def test_ball_rebounds_from_end_line_beside_goal_and_does_not_score():
    batch = scripted((50.0, 20.0), (2.5, 0.0))
    for _ in range(5):
        batch.step()
    x, y, vx, _ = ball_position(batch)
    assert x < 52.5 and vx < 0.0 and batch.state.goals[0] == 0


@pytest.mark.parametrize("start, velocity", [
    ((-45.0, -C.half_width + C.ball_size), (-1.0, 0.0)),  # along the touch line into the corner behind
    ((-45.0, C.half_width - C.ball_size), (-1.0, 0.0)),
    ((45.0, C.half_width - C.ball_size), (1.0, 0.0)),  # into a corner of the attacked end, beside the goal
    ((-C.half_length + C.ball_size, -25.0), (0.0, -1.0)),  # along the end line into the corner
    ((C.half_length + 0.1, C.goal_half_width - C.ball_size), (0.3, 0.0)),  # along the net's side to its back
])
def test_a_ball_sliding_along_a_wall_stops_in_the_corner(start, velocity):
    """A ball rolling along a wall into a corner rebounds from the other wall as from the middle of it;
    it does not slide between the two walls' shapes and out of the pitch (they overlap in the corner).
    pymunk's contacts are soft: a ball hitting a wall at 1 m a tick sinks about 0.3 m into it for a tick."""
    batch = scripted(start, velocity, player=(0.0, 0.0))
    low_x, high_x = -C.half_length + C.ball_size, C.half_length + C.goal_depth - C.ball_size
    deepest = 0.0
    for _ in range(60):
        batch.step()
        x, y, _, _ = ball_position(batch)
        deepest = max(deepest, low_x - x, x - high_x, abs(y) - (C.half_width - C.ball_size))
    assert deepest < 0.5  # through the seam it went 2 m deep and stayed inside the wall
    x, y, _, _ = ball_position(batch)
    assert low_x - 1e-6 <= x <= high_x + 1e-6 and abs(y) <= C.half_width - C.ball_size + 1e-6  # resting on a wall
    assert batch.state.goals[0] == 0


def test_ball_rebounds_from_post():
    batch = scripted((51.0, 7.01), (0.3, 0.0))
    for _ in range(15):
        batch.step()
    x, _, vx, _ = ball_position(batch)
    assert x < 52.5 and vx < 0.0 and batch.state.goals[0] == 0


def test_player_running_into_the_ball_collides_as_in_rcssserver():
    # player dashing at 1 m/tick onto a ball at rest 0.5 m ahead: pymunk lets them overlap, then the
    # engine parts them along the line of centres and multiplies both velocities by -0.1
    batch = scripted((0.5, 0.0), (0.0, 0.0), player=(0.0, 0.0))
    p = batch.world.objects(0)[0]
    p.velocity = (1.0 / C.tick_seconds, 0.0)
    batch.state.last_player[0] = (0.0, 0.0)
    batch.step()  # decides and moves: the player's velocity decays to 0.4 m/tick first
    batch.step()  # closes the step: the player at 0.4 overlaps the ball at 0.5
    ox, oy = batch.world.pitches.offsets[0]
    x, y, vx, vy = ball_position(batch)
    half = (C.player_size + C.ball_size) / 2 + COLLISION_GAP
    assert x == pytest.approx(0.45 + half, abs=1e-9) and vx == 0.0  # parted from the midpoint 0.45, at rest
    # the player's 0.4 m/tick became -0.04 (rebound), decayed to -0.016 and moved it back from 0.45 - half
    assert p.position.x - ox == pytest.approx(0.45 - half - 0.016, abs=1e-9)
    assert p.velocity.x * C.tick_seconds == pytest.approx(-0.016)


def test_ball_through_mouth_scores_and_restarts_on_centre_line():
    batch = scripted((50.0, 3.0), (2.0, 0.0), player=(-30.0, 5.0))
    ox, oy = batch.world.pitches.offsets[0]
    player_before = batch.world.objects(0)[0].position
    for _ in range(3):
        batch.step()
    assert batch.state.goals[0] == 1
    x, y, vx, vy = ball_position(batch)
    assert x == 0.0 and -34.0 <= y <= 34.0 and (vx, vy) == (0.0, 0.0)
    assert batch.world.objects(0)[0].position == player_before  # the player stays


def test_ball_in_net_cannot_leave_through_the_back():
    batch = scripted((53.0, 0.0), (1.0, 0.0))
    batch.state.last_ball[0] = (53.0, 0.0)  # already in: not a new crossing
    for _ in range(10):
        batch.step()
    assert ball_position(batch)[0] < 54.5


def test_idle_player_ends_the_game_after_idle_ticks():
    result, trace = play_game(EMPTY, 5)
    assert result.end_reason == "idle" and result.ticks == 100 and result.fitness == 1.0
    assert (trace.action == -1).all()  # no rule fires: the hunt only turns


def test_max_ticks_and_goal_cap():
    demo = demo_rulebase()
    short = play_games([demo], [3], GameConfig(max_ticks=40))[0]
    assert short.end_reason == "max-ticks" and short.ticks == 40
    capped = play_games([demo], [3], GameConfig(goal_cap=2))[0]
    assert capped.end_reason == "goal-cap" and capped.goals == 2 and capped.fitness == 0.25


def test_demo_rulebase_scores_from_most_random_starts():
    results = play_games([demo_rulebase()] * 12, list(range(100, 112)))
    assert sum(r.goals > 0 for r in results) >= 10
    assert np.mean([r.fitness for r in results]) < 0.2


def test_game_alone_equals_game_inside_a_batch_of_200():
    rng = np.random.default_rng(7)
    demo = demo_rulebase()
    rulebases = [demo if g % 4 == 0 else random_rulebase(rng, VOCABULARY, rules=8) for g in range(200)]
    seeds = [1000 + 17 * g for g in range(200)]
    batched = play_games(rulebases, seeds)
    assert sum(r.goals for r in batched) > 0
    for g in (0, 1, 4, 57, 120, 199):
        assert play_games([rulebases[g]], [seeds[g]]) == [batched[g]]


def test_trace_matches_result_and_is_deterministic():
    result, trace = play_game(demo_rulebase(), 11, GameConfig(max_ticks=200))
    again, trace2 = play_game(demo_rulebase(), 11, GameConfig(max_ticks=200))
    assert result == again and len(trace) == result.ticks == 200
    np.testing.assert_array_equal(trace.player_x, trace2.player_x)
    assert trace.goals[-1] <= result.goals and trace.player_x[0] <= 0.0 and trace.ball_x[0] == 0.0
    seen = trace.visible[:, 0]
    assert np.isnan(trace.inputs[~seen, 0]).all() and not np.isnan(trace.inputs[seen, 0]).any()
    demo_actions = [VOCABULARY.action_names.index(name) for name in ("GOTOBALL", "KICKTOWARDGOAL", "DRIBBLE")]
    assert np.isin(trace.action, [-1] + demo_actions).all()  # the hunt or one of the demo's actions


def test_one_seed_per_game_is_required():
    with pytest.raises(ValueError, match="one seed per game"):
        play_games([EMPTY, EMPTY], [1])


def test_noise_changes_the_game_but_stays_deterministic():
    demo = demo_rulebase()
    noisy = GameConfig(noise=True, max_ticks=300)
    a = play_games([demo], [4], noisy)
    assert a == play_games([demo], [4], noisy)
    assert a != play_games([demo], [4], GameConfig(max_ticks=300))


def test_strict_kicking_skills_leave_an_unreachable_ball_alone():
    """One rule "KickTowardGoal whenever the ball is in view" is a whole striker with assisted skills
    (it fetches the ball) and does nothing with strict ones (the ball never comes within reach)."""
    kicker = Rulebase((Rule((Premise("BALL", "VERYFAR"), Premise("BALL", "VERYFAR", True)), ("OR",),
                            Consequent("KICKTOWARDGOAL", power="HIGH")),))
    assisted = play_games([kicker] * 3, [1, 2, 3], GameConfig(skills="assisted"))
    strict = play_games([kicker] * 3, [1, 2, 3], GameConfig(skills="strict"))
    assert all(result.goals >= 5 for result in assisted)
    assert all(result.kicks == 0 and result.fitness == 1.0 and result.end_reason == "idle" for result in strict)


def test_counting_touches_changes_what_counts_as_a_kick_not_the_game():
    """A ball chaser that never kicks shoves the ball along with its body: fitness 1.0 ("no ball movement")
    when only kicks count, ball movement (0.5 + closest approach / 210) when its pushes count as kicks;
    the game itself, tick for tick, is the same."""
    chaser = parse_rulebase("if Ball is VeryFar or Ball is not VeryFar then RunTowardBall High", VOCABULARY)
    for seed in (1, 2):
        kicks_only, plain = play_game(chaser, seed, GameConfig())
        touches, counted = play_game(chaser, seed, GameConfig(count_touches=True))
        for field in ("player_x", "player_y", "ball_x", "ball_y", "action"):
            assert np.array_equal(getattr(plain, field), getattr(counted, field))
        assert kicks_only.kicks == 0 and kicks_only.fitness == 1.0 and kicks_only.goals == touches.goals == 0
        assert touches.kicks > 100  # a push most ticks once it reaches the ball
        assert touches.fitness == 0.5 + touches.min_ball_goal_distance / (2 * GameConfig().world.pitch_length)
        assert touches.fitness < 0.8 and touches.min_ball_goal_distance == kicks_only.min_ball_goal_distance


@numba.njit
def _through_borrowed_views(values):
    first, (second, scale) = borrowed(values)
    first[0] = scale
    second[1, 1] = 2.0 * scale
    return first.sum() + second.sum()


def test_borrowed_views_read_and_write_the_callers_arrays_and_keep_no_reference():
    first, second = np.ones(3), np.zeros((2, 2))
    references = sys.getrefcount(first), sys.getrefcount(second)
    assert _through_borrowed_views((first, (second, 5.0))) == 5.0 + 2.0 + 10.0
    assert first.tolist() == [5.0, 1.0, 1.0] and second.tolist() == [[0.0, 0.0], [0.0, 10.0]]
    assert (sys.getrefcount(first), sys.getrefcount(second)) == references


@numba.njit
def _swap_position_and_velocity(address):
    body = body_vectors(address)
    body[0], body[1], body[2], body[3] = body[2], body[3], body[0], body[1]


def test_the_kernel_reads_and_writes_a_body_where_pymunk_keeps_it():
    space = pymunk.Space()
    body = pymunk.Body(1.0, float("inf"))
    space.add(body, pymunk.Circle(body, 0.1))
    body.position, body.velocity = (2.0**20 + 0.1, 3.5), (-1.5, 0.25)
    _swap_position_and_velocity(np.uint64(vectors_address(body)))
    assert tuple(body.velocity) == (2.0**20 + 0.1, 3.5)
    space.step(0.5)  # pymunk moves the body from the position written, at the velocity written
    assert tuple(body.position) == (-1.5 + (2.0**20 + 0.1) * 0.5, 0.25 + 3.5 * 0.5)


def test_sighted_skills_shoot_only_at_a_goal_in_view():
    """`sighted` differs from `strict` in one thing: KickTowardGoal with the goal out of view does
    nothing. So the two games are the same tick for tick until the first time the striker has the
    ball at its feet and the goal out of view; there `strict` shoots and `sighted` leaves the ball."""
    striker = parse_rulebase("if Ball is At then KickTowardGoal High\nif Ball is not At then GoToBall VeryHigh",
                             VOCABULARY)
    kick_toward_goal = VOCABULARY.action_names.index("KICKTOWARDGOAL")
    goal = VOCABULARY.object_names.index("GOAL")
    diverged = 0
    for seed in range(6):
        _, strict = play_game(striker, seed, GameConfig(skills="strict", max_ticks=400))
        _, sighted = play_game(striker, seed, GameConfig(skills="sighted", max_ticks=400))
        ticks = min(len(strict), len(sighted))
        same = (strict.ball_x[:ticks] == sighted.ball_x[:ticks]) & (strict.player_x[:ticks] == sighted.player_x[:ticks])
        if same.all():
            continue
        first = int(np.argmin(same))  # the first tick whose positions differ: the command before it did
        shot_blind = (strict.action[first - 1] == kick_toward_goal) and not strict.visible[first - 1, goal]
        assert shot_blind, f"seed {seed}: the games part at tick {first} without a shot at an unseen goal"
        diverged += 1
    assert diverged >= 1
