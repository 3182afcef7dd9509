"""The client's state machine driven by recorded server messages over loopback UDP."""

import time

import pytest

from soccer_lab.soccer.rcss.client import Session, Timeouts
from soccer_lab.soccer.rcss.errors import (RcssCommandError, RcssConfigError, RcssNoServerError, RcssRefusedError,
                                           RcssTimeoutError)
from soccer_lab.soccer.rcss.evaluate import RcssEvaluator
from soccer_lab.soccer.rcss.player import load_compiled_skills
from tests.rcss.replay import TRAINER, Line, ReplayServer, read_transcript, with_fresh_start
from soccer_lab.soccer.rcss.trial import TrialConfig, run_trial

from .conftest import GOALS, player_thinks

FAST = Timeouts(connect=0.5, cycle=1.0)
RECORDED_TEAM = "LabTeam"  # see_global names the player by the recorded team


def play(lines, rulebase, config, seed=1, **server_options):
    load_compiled_skills()  # as the evaluator does: loading them takes about a cycle's answer window
    with ReplayServer(lines, client_timeout=5.0, **server_options) as server:
        session = Session(server.server, trainer_port=server.trainer_port, team=RECORDED_TEAM, timeouts=FAST)
        try:
            session.open()
            result = run_trial(session, rulebase, seed, config)
        finally:
            session.close()
        return result, server.wait()


def replaced(lines, old, new):
    return [Line(l.number, l.sent, l.role, l.text.replace(old, new)) for l in lines]


def test_goals_transcript_counts_three_goals_and_six_kicks(goals_lines, chaser):
    trial_cycles = player_thinks(goals_lines) - 2  # before the trial: the connection's (think), the fresh start's
    result, log = play(goals_lines, chaser, TrialConfig(max_ticks=trial_cycles))
    assert log.error is None and log.finished and not log.init_port_misuse
    assert (result.goals, result.kicks, result.ticks, result.end) == (3, 6, trial_cycles, "time")
    assert result.fitness == pytest.approx(1 / 6)
    fresh_start, setup = log.commands["T"][:2]
    assert fresh_start == ["(eye on)", "(ear on)", "(recover)", "(change_mode before_kick_off)",
                           "(move (ball) 0.0000 0.0000)"]
    assert setup[0].startswith("(move (ball) 0.0000 0.0000") and setup[1].startswith("(move (player LabTeam 1) -")
    assert setup[-1] == "(change_mode play_on)"
    # After each goal the trainer restarted play in the very cycle the recorded trainer did (otherwise
    # the recorded (ok move) would not have arrived in time and the client would have raised).
    restarts = [cycle for cycle, sent in enumerate(log.commands["T"]) if "(change_mode play_on)" in sent]
    assert len(restarts) == 4
    assert all(sent[0].startswith("(move (ball) 0.0000 ") for sent in (log.commands["T"][c] for c in restarts[1:]))
    # First decision: the ball is seen 51 degrees to the left at rest, so the player turns by -51.
    assert log.commands["P"][2] == ["(turn -51.00)"]  # after the fresh start's cycle and the placing one
    assert any(c.startswith("(kick ") for sent in log.commands["P"] for c in sent)


def test_out_of_play_transcript_ends_the_trial_on_kick_in(out_of_play_lines, chaser):
    result, log = play(out_of_play_lines, chaser, TrialConfig())
    assert log.error is None
    assert result.end == "out of play (kick_in_r)"
    assert result.ticks == 12 and result.kicks == 1 and result.goals == 0
    assert result.fitness == pytest.approx(1 - 1 / 24)
    kick_in = next(l.number for l in out_of_play_lines if "kick_in_r" in l.text)
    next_done = next(l.number for l in out_of_play_lines if l.number > kick_in and l.text == "(done)")
    assert log.left_at == next_done  # the client left in the cycle the referee stopped play


def test_trial_ends_when_the_player_stands_still(goals_lines, chaser):
    # The recorded player's first command was a turn: see_global 1 and 2 both put it at (-15, 0).
    result, log = play(goals_lines, chaser, TrialConfig(idle_ticks=1))
    assert log.error is None
    assert (result.end, result.ticks, result.goals) == ("idle", 2, 0)
    second = next(l.number for l in goals_lines if l.text.startswith("(see_global 2 "))
    assert log.left_at == next(l.number for l in goals_lines if l.number > second and l.text == "(done)")


def test_no_server_gives_a_clear_error_within_seconds():
    started = time.monotonic()
    with pytest.raises(RcssNoServerError, match="no reply from rcssserver at 127.0.0.1:9 within 0.5 s"):
        Session("127.0.0.1:9", timeouts=FAST).open()
    assert time.monotonic() - started < 3.0


def test_server_not_in_synch_mode(goals_lines, chaser):
    lines = replaced(goals_lines, "(synch_mode 1)", "(synch_mode 0)")
    with pytest.raises(RcssConfigError, match="not in synch mode"):
        play(lines, chaser, TrialConfig())


def test_trainer_refused(goals_lines, chaser):
    lines = replaced(goals_lines, "(init ok)", "(error no_more_trainer)")
    with pytest.raises(RcssRefusedError, match="refused the offline trainer .no_more_trainer."):
        play(lines, chaser, TrialConfig())


def test_error_reply_to_a_command(transcripts_available, chaser):
    lines = with_fresh_start(read_transcript(GOALS))  # with the recording's deliberate bad commands and errors
    with pytest.raises(RcssCommandError, match="trainer: rcssserver rejected .*: unknown_command"):
        play(lines, chaser, TrialConfig())  # the trainer's cycle is read first: its error is the first met
    player_errors_only = [l for l in lines if not (l.role == TRAINER and l.text.startswith("(error"))]
    with pytest.raises(RcssCommandError, match="player: rcssserver rejected a command: illegal_command_form"):
        play(player_errors_only, chaser, TrialConfig())


def test_server_silent_mid_trial(goals_lines, chaser):
    quit_at = next(l.number for l in goals_lines if l.text.startswith("(sense_body 40 "))
    started = time.monotonic()
    with pytest.raises(RcssTimeoutError, match="sent nothing for 1 s"):
        play(goals_lines, chaser, TrialConfig(), stop_before_line=quit_at)
    assert time.monotonic() - started < 5.0


def test_evaluator_runs_servers_in_parallel_and_keeps_order(goals_lines, out_of_play_lines, chaser):
    config = TrialConfig(max_ticks=player_thinks(goals_lines) - 2)
    with ReplayServer(goals_lines) as first, ReplayServer(out_of_play_lines) as second:
        with RcssEvaluator(
            [first.server, second.server], config, team=RECORDED_TEAM, timeouts=FAST, trainer_ports=[first.trainer_port, second.trainer_port]
        ) as evaluate:
            results = evaluate([chaser, chaser], [11, 12])
        assert first.wait().error is None and second.wait().error is None
    assert [r.seed for r in results] == [11, 12]
    assert sorted(r.goals for r in results) == [0, 3]
    assert {r.end for r in results} == {"time", "out of play (kick_in_r)"}


def test_empty_rulebase_scores_worst_without_playing():
    from soccer_lab.fuzzy.rule import Rulebase

    result = run_trial(None, Rulebase(()), 5)  # no session needed: nothing is played
    assert (result.fitness, result.ticks, result.end) == (1.0, 0, "no rules")


def test_bad_server_address():
    with pytest.raises(ValueError, match="expected HOST:PORT"):
        RcssEvaluator(["localhost:notaport"])


def test_server_silent_before_acknowledging_a_trainer_command(goals_lines, chaser):
    """A server that quits between the trainer's command and its (ok ...): one line naming the server and
    the command, as every other timeout names the server (a killed server's error says where it was)."""
    first_done = next(l.number for l in goals_lines if l.sent and l.role == TRAINER and l.text == "(done)")
    quit_at = next(l.number for l in goals_lines  # the recorded ok, after the fresh start's inserted one
                   if l.role == TRAINER and l.text.startswith("(ok move") and l.number > first_done)
    with pytest.raises(RcssCommandError) as raised:
        play(goals_lines, chaser, TrialConfig(), stop_before_line=quit_at)
    message = str(raised.value)
    assert message.startswith("trainer: rcssserver at 127.0.0.1:") and "did not answer (move (ball)" in message
    assert message.endswith("within 1 s (did the server quit?)")
