"""The client, the trials and the evaluator against real rcssservers (started by soccer-lab's launcher,
noise at the server's defaults): what the recorded transcripts cannot show, such as whether the server
accepts our commands at all."""

from __future__ import annotations

import math
import statistics
import threading
import time

import numpy as np
import pytest

from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.soccer.config import MAX_TICKS, WorldConfig
from soccer_lab.soccer.rcss.client import Session
from soccer_lab.soccer.rcss.errors import RcssConfigError, RcssError
from soccer_lab.soccer.rcss.evaluate import RcssEvaluator
from soccer_lab.soccer.rcss.player import RcssPlayer, load_compiled_skills
from soccer_lab.soccer.rcss.servers import NOISELESS_OPTIONS
from soccer_lab.soccer.rcss.trial import TrialConfig, run_trial, start_position

from .conftest import VOCABULARY
from .real_server import connected_players, kill

# The striker fetches the ball with the assisted skills and scores within 300 cycles from any start.
SHORT = TrialConfig(max_ticks=300, skills="assisted")


def test_the_striker_scores_on_a_real_server_with_default_noise(start_servers, chaser):
    pool = start_servers()
    with Session(pool.addresses[0]) as session:
        session.open()
        world = session.params.world
        assert (world.player_rand, world.ball_rand) == (WorldConfig().player_rand, WorldConfig().ball_rand) != (0, 0)
        first = run_trial(session, chaser, 1, SHORT)
        second = run_trial(session, chaser, 2, SHORT)  # the same session: the trainer resets for each trial
    for result in (first, second):
        assert result.goals >= 1 and result.kicks >= result.goals, result
        assert result.fitness == pytest.approx(1 / (2 * result.goals))
        assert (result.ticks, result.end) == (SHORT.max_ticks, "time")


def test_localisation_on_a_live_server_with_default_noise(start_servers, chaser):
    """The player's pose from the flags it sees against the trainer's see_global, cycle by cycle."""
    pool = start_servers()
    errors, facing = [], []
    with Session(pool.addresses[0]) as session:
        session.open()
        player = RcssPlayer(chaser, session.params)
        trainer = session.trainer
        trainer.move_ball(0.0, 0.0)
        trainer.move_player(session.player.team, session.player.unum, -20.0, 10.0, 30.0)
        trainer.change_mode("play_on")
        commands: list[str] = []
        for _ in range(150):
            player_cycle, trainer_cycle = session.step(commands)
            commands = player.decide(player_cycle)
            truth = trainer_cycle.see_global.player(session.player.team, session.player.unum)
            if player_cycle.see is not None and player.world.pose is not None:
                pose = player.world.pose
                errors.append(math.hypot(pose.x - truth.x, pose.y - truth.y))
                facing.append(abs((pose.body - truth.body + 180) % 360 - 180))
    assert len(errors) > 50
    assert statistics.median(errors) < 0.3 and max(errors) < 2.0
    assert statistics.median(facing) < 2.0  # see_global reports whole degrees


def test_two_servers_share_the_trials_and_keep_their_order(start_servers, chaser):
    pool = start_servers(2)
    with RcssEvaluator(pool.addresses, TrialConfig(max_ticks=60)) as evaluate:
        results = evaluate([chaser] * 4, [21, 22, 23, 24])
        again = evaluate([chaser] * 2, [25, 26])
        clients = [process.pid for process, _ in evaluate._clients.values()]
    assert [result.seed for result in results + again] == [21, 22, 23, 24, 25, 26]
    assert all(result.ticks == 60 for result in results + again)
    assert len(set(clients)) == 2  # a client process of its own per server
    assert [connected_players(server) for server in pool.servers] == [1, 1]  # one session each, kept


def test_a_server_killed_mid_trial_is_one_clear_error_within_seconds(start_servers):
    pool = start_servers()
    server = pool.servers[0]
    killed_at: list[float] = []

    def crash() -> None:
        killed_at.append(time.monotonic())  # before: the client may notice before kill() has seen it die
        kill(server)

    # A player that only turns on the spot (no rule fires away from the ball: it hunts): no goal, no
    # kick, nothing ends the trial before the server dies.
    turner = parse_rulebase("if Ball is At then DoNothing", VOCABULARY)
    with Session(server.address) as session:
        session.open()
        run_trial(session, turner, 3, TrialConfig(max_ticks=5))  # the player's skills loaded
        threading.Timer(0.5, crash).start()
        with pytest.raises(RcssError) as raised:
            run_trial(session, turner, 3, TrialConfig(max_ticks=MAX_TICKS, idle_ticks=MAX_TICKS))
    assert time.monotonic() - killed_at[0] < 5.0  # the client's cycle deadline (3 s), not a hang
    message = str(raised.value)
    assert "\n" not in message and server.address in message and "rcssserver" in message


def test_a_client_that_falls_behind_catches_up_with_the_server(start_servers, chaser, monkeypatch):
    """The server waits 1.25 s for a (done), then steps on: a player that stalls for longer reads on to the
    newest cycle and the trial (and the next one on the session) goes on."""
    pool = start_servers()
    stalled = []
    decide = RcssPlayer.decide

    def stall_once(self, cycle):
        if cycle.sense_body.time == 20 and not stalled:
            stalled.append(cycle.sense_body.time)
            time.sleep(2.0)
        return decide(self, cycle)

    monkeypatch.setattr(RcssPlayer, "decide", stall_once)
    with Session(pool.addresses[0]) as session:
        session.open()
        behind = run_trial(session, chaser, 4, TrialConfig(max_ticks=60))
        clock_after_stall = session.time
        after = run_trial(session, chaser, 5, TrialConfig(max_ticks=30))
    assert stalled == [20]
    assert behind.end == "time" and behind.ticks == 60
    assert clock_after_stall > 60  # the server stepped on while the player stalled; it skipped those cycles
    assert after.ticks == 30 and after.end == "time"


@pytest.mark.parametrize("option, value, fragment", [
    ("server::synch_mode", "false", "not in synch mode: start it with server::synch_mode=true"),
    ("server::coach_w_referee", "false", "add server::coach_w_referee=true"),
    ("server::coach", "false", "start it with server::coach=true"),
])
def test_a_server_started_without_a_required_option_is_named(start_servers, option, value, fragment):
    pool = start_servers(options={option: value})
    started = time.monotonic()
    with pytest.raises(RcssConfigError, match=fragment):
        Session(pool.addresses[0]).open()
    assert time.monotonic() - started < 3.0


def test_a_traced_trial_is_where_the_server_put_player_and_ball_cycle_by_cycle(start_servers, chaser):
    """What a run's recording replays of an rcss trial (app/runs/run.py, GenerationReplays): one row a cycle,
    from the trainer's see_global, traced in the clients' own processes and sent back with the result."""
    pool = start_servers(2)
    with RcssEvaluator(pool.addresses, SHORT, trace=True) as evaluate:
        results = evaluate([chaser, chaser], [1, 2])
    assert [evaluate.traced[(chaser, seed)] for seed in (1, 2)] == results
    for result in results:
        trace = result.trace
        assert len(trace) == result.ticks == SHORT.max_ticks
        # The first cycle, before the player's first command: where the trainer put it, the ball on the spot.
        start = start_position(np.random.default_rng(result.seed))
        assert (trace.player_x[0], trace.player_y[0]) == pytest.approx(start, abs=0.01)
        assert (trace.ball_x[0], trace.ball_y[0]) == pytest.approx((0.0, 0.0), abs=0.01)
        assert np.all(np.abs(trace.player_x) < 60) and np.all(np.abs(trace.ball_y) < 40)  # on the pitch
        # The goals before each cycle rise one at a time up to the trial's; the striker's chosen actions.
        assert trace.goals[0] == 0 and set(np.diff(trace.goals)) <= {0, 1} and trace.goals[-1] <= result.goals
        chosen = {VOCABULARY.action_names[a] for a in trace.action if a >= 0}
        assert chosen and chosen <= {rule.consequent.action for rule in chaser}
    assert not RcssEvaluator(pool.addresses, SHORT).trace  # untraced unless asked: results carry no trace


QUIET = TrialConfig(max_ticks=300, skills="assisted", noise=False)


def test_without_noise_a_trial_plays_the_same_on_a_new_server_and_a_used_one(start_servers, chaser):
    """Each trial starts fresh (stamina recovered, the referees' counters reset, the see in phase), so with the
    server's noise off the same rulebase and seed play the same trial cycle by cycle on a new server and on
    one whose player has dashed for a thousand cycles before (its stamina spent, the ball stuck somewhere)."""
    pool = start_servers(2, NOISELESS_OPTIONS)
    dasher = parse_rulebase("if Ball is not At then GoToBall VeryHigh\nif Ball is At then DoNothing", VOCABULARY)
    load_compiled_skills()  # as the evaluator does: loading them mid-trial would miss a cycle
    with Session(pool.addresses[0]) as new, Session(pool.addresses[1]) as used:
        new.open()
        used.open()
        for seed in range(4):
            run_trial(used, dasher, 10 + seed, QUIET)
        for seed in (1, 2):
            fresh, after = (run_trial(session, chaser, seed, QUIET, trace=True) for session in (new, used))
            assert (fresh.goals, fresh.kicks, fresh.ticks, fresh.end, fresh.fitness) == (
                after.goals, after.kicks, after.ticks, after.end, after.fitness)
            for column in ("player_x", "player_y", "facing", "ball_x", "ball_y", "action", "goals"):
                assert np.array_equal(getattr(fresh.trace, column), getattr(after.trace, column)), column
            assert fresh.goals >= 1 and fresh.late_cycles == after.late_cycles == 0


def test_a_server_whose_noise_is_not_the_trials_is_refused(start_servers, chaser):
    noisy, quiet = start_servers(1), start_servers(1, NOISELESS_OPTIONS)
    with Session(noisy.addresses[0]) as session:
        session.open()
        with pytest.raises(RcssConfigError, match="adds noise, but the trials want none: start it with "
                                                  "server::player_rand=0 server::ball_rand=0 server::kick_rand=0"):
            run_trial(session, chaser, 1, QUIET)
    with Session(quiet.addresses[0]) as session:
        session.open()
        with pytest.raises(RcssConfigError, match="runs without noise, but the trials want the server's noise"):
            run_trial(session, chaser, 1, SHORT)


def first_change(trace) -> int:
    """The first cycle at which the player has moved or turned since the trial's first cycle."""
    moved = (np.hypot(trace.player_x - trace.player_x[0], trace.player_y - trace.player_y[0]) > 0.01) | (
        trace.facing != trace.facing[0])
    return int(np.flatnonzero(moved)[0])


def test_late_answers_reach_the_server_as_many_cycles_later_and_play_the_same_under_a_seed(start_servers, chaser):
    """TrialConfig.answer_delay: each decision reaches the server that many cycles after the one it was made for
    (the player's first move comes as much later); answer_delay_spread adds random delays drawn from the trial's
    seed, so a trial plays the same twice (the server's noise off), and unlike one answered in time."""
    pool = start_servers(1, NOISELESS_OPTIONS)
    load_compiled_skills()
    short = QUIET.model_copy(update={"max_ticks": 150})
    with Session(pool.addresses[0]) as session:
        session.open()
        on_time, late = (run_trial(session, chaser, 4, short.model_copy(update={"answer_delay": delay}), trace=True)
                         for delay in (0, 2))
        spread = short.model_copy(update={"answer_delay_spread": 3})
        first, second = (run_trial(session, chaser, 4, spread, trace=True) for _ in range(2))
    assert first_change(late.trace) == first_change(on_time.trace) + 2
    for column in ("player_x", "player_y", "facing", "ball_x", "ball_y"):
        assert np.array_equal(getattr(first.trace, column), getattr(second.trace, column)), column
    assert not np.array_equal(first.trace.player_x, on_time.trace.player_x)
    assert {r.late_cycles for r in (on_time, late, first, second)} == {0}  # the delays are the trial's, not the machine's


def test_left_to_rcssserver_play_restarts_after_its_pause_and_the_other_sides_kick_off(start_servers, chaser):
    """TrialConfig.restart = "server": after a goal nobody restarts play. rcssserver keeps the ball where it went in
    for 50 cycles, then gives the other side the kick-off (the ball on the centre spot), which nobody takes, and
    drops the ball there 100 cycles later. The trial plays on through it: the kick-off does not end it."""
    pool = start_servers(1, NOISELESS_OPTIONS)
    load_compiled_skills()
    trainer = QUIET.model_copy(update={"max_ticks": 400})
    with Session(pool.addresses[0]) as session:
        session.open()
        restarted, left = (run_trial(session, chaser, 3, config, trace=True)
                           for config in (trainer, trainer.model_copy(update={"restart": "server"})))
    goal = int(np.argmax(left.trace.goals > 0))  # the first cycle after the first goal
    assert goal > 0 and goal == int(np.argmax(restarted.trace.goals > 0))  # the same play up to the first goal
    assert left.end == "time" and left.goals >= 1
    def stretch(inside: np.ndarray) -> int:  # consecutive cycles from the first
        return int(np.argmin(inside)) if not inside.all() else len(inside)

    in_goal = stretch(left.trace.ball_x[goal:] > 52.5)  # rcssserver's pause; then the kick-off and the drop ball
    on_spot = stretch(np.hypot(left.trace.ball_x, left.trace.ball_y)[goal + in_goal:] < 0.01)  # till the player comes
    assert 48 <= in_goal <= 52 and 100 <= on_spot <= 130, (in_goal, on_spot)
    assert stretch(restarted.trace.ball_x[goal:] > 52.5) <= 6  # the trainer's restart, 5 cycles after the goal
