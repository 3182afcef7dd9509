"""`evolve`, `random-search` and `play` with --env rcss: option checks, the no-server path, and a whole
(one-generation) evolution against servers that replay recorded trials."""

from __future__ import annotations

import csv
import json
import time

import numpy as np
import pytest
from typer.testing import CliRunner

from soccer_lab.app.cli import app
from soccer_lab.soccer.rcss import client as rcss_client
from soccer_lab.soccer.rcss import servers as rcss_servers
from soccer_lab.soccer.rcss.messages import SeeGlobal, parse_message
from tests.app.rcss_fakes import (GOALS_CYCLES, GOALS_FITNESS, KICK_IN_FITNESS, replay_server, silent_server,
                                  transcripts_missing, two_recorded_trials)
from tests.app.test_cli_evolve import assert_one_line_error, read_recording
from tests.rcss.conftest import GOALS
from tests.rcss.replay import read_transcript

# Two rulebases (both with rules at this seed), one generation: one trial on each of two servers.
ONE_GENERATION = ["--population-size", "2", "--generations", "1", "--max-length", "16", "--seed", "0"]
NO_SERVER_WITHIN = 10.0  # seconds; the client gives up on init after 2 s: anything near this is a hang


def run(*args: object):
    return CliRunner().invoke(app, [str(a) for a in args])


@pytest.fixture(scope="module")
def evolved_on_rcss(tmp_path_factory):
    reason = transcripts_missing()
    if reason:
        pytest.skip(reason)
    folder = tmp_path_factory.mktemp("rcss") / "run"
    with two_recorded_trials() as (goals, kick_in):
        servers = [goals.server, kick_in.server]
        result = run("evolve", "--env", "rcss", "--server", servers[0], "--server", servers[1],
                     *ONE_GENERATION, "--max-ticks", GOALS_CYCLES, "--out", folder)
        logs = goals.wait(), kick_in.wait()
    return folder, result, logs, servers


def recorded_ball(transcript) -> list[tuple[float, float]]:
    """The ball where the recorded server's see_global put it, cycle by cycle (a replay keeps it as float32)."""
    trainer = (line.text for line in read_transcript(transcript) if not line.sent and line.role == "T")
    messages = map(parse_message, trainer)
    return [(message.ball.x, message.ball.y) for message in messages if isinstance(message, SeeGlobal)]


def test_evolve_on_two_servers_plays_one_trial_on_each(evolved_on_rcss):
    folder, result, (goals_log, kick_in_log), servers = evolved_on_rcss
    assert result.exit_code == 0, result.output
    assert goals_log.error is None and goals_log.finished  # the whole recorded trial was played
    assert kick_in_log.error is None and kick_in_log.left_at is not None  # left when the referee stopped play
    with (folder / "statistics.csv").open(newline="") as handle:
        (row,) = csv.DictReader(handle)
    assert float(row["best"]) == pytest.approx(GOALS_FITNESS, abs=1e-4)
    assert float(row["worst"]) == pytest.approx(KICK_IN_FITNESS, abs=1e-4)
    assert int(row["evaluations"]) == 2
    assert f"best fitness {GOALS_FITNESS:.4f}" in result.output and "3 goals" in result.output
    assert (f"play the best on rcssserver: soccer-lab play {folder / 'best.rules'} --env rcss "
            f"--server {servers[0]} --server {servers[1]}") in result.output


def test_the_recording_replays_the_best_trial_as_the_server_played_it(evolved_on_rcss):
    """The goals trial was the best: its replay is the ball where the server's see_global put it, cycle by
    cycle, and the goals it scored."""
    folder, result, _, _ = evolved_on_rcss
    entities = read_recording(folder / "run.rrd")
    replayed = [tuple(p[0]) for p in entities["/replay/generation_0/ball"]["columns"]["Points2D:positions"]]
    np.testing.assert_array_equal(np.array(replayed), np.array(recorded_ball(GOALS), dtype=np.float32))
    goals = [v[0] for v in entities["/replay/generation_0/score/goals"]["columns"]["Scalars:scalars"]]
    assert (goals[0], goals[-1]) == (0, 3) and sorted(goals) == goals
    assert "replay of the best player's first trial" in result.output and "3 goals" in result.output


def test_the_run_folder_records_where_it_played(evolved_on_rcss):
    folder, result, _, servers = evolved_on_rcss
    manifest = json.loads((folder / "run.json").read_text())
    assert manifest["env"] == "rcss" and manifest["servers"] == servers and "game" not in manifest
    # Unset game options take the chapter's RoboCup trial settings; --max-ticks sets the trial's cycles.
    assert manifest["trial"]["max_ticks"] == GOALS_CYCLES and manifest["trial"]["fitness"] == "robocup-composite"
    assert manifest["ga"]["workers"] == 1
    for name in ("best.rules", "best.json", "checkpoint", "run.rrd"):
        assert (folder / name).is_file(), name


def test_resume_of_an_rcss_run_takes_new_servers_and_fails_cleanly_without_one(evolved_on_rcss):
    folder, *_ = evolved_on_rcss
    with silent_server() as server:
        started = time.monotonic()
        result = run("evolve", "--resume", folder, "--server", server)
        assert time.monotonic() - started < NO_SERVER_WITHIN
    assert_one_line_error(result, f"no reply from rcssserver at {server} within 2 s")


def test_no_server_is_one_line_within_seconds_and_leaves_no_run_folder(tmp_path):
    with silent_server() as server:
        started = time.monotonic()
        result = run("evolve", "--env", "rcss", "--server", server, *ONE_GENERATION, "--out", tmp_path / "run")
        assert time.monotonic() - started < NO_SERVER_WITHIN
    assert_one_line_error(result, f"player: no reply from rcssserver at {server} within 2 s",
                          "is it running, on this host and port?")
    assert not (tmp_path / "run").exists()


def test_random_search_on_rcss_takes_the_same_path(tmp_path):
    with silent_server() as server:
        result = run("random-search", "--env", "rcss", "--server", server, *ONE_GENERATION, "--out", tmp_path / "r")
    assert_one_line_error(result, f"no reply from rcssserver at {server}")


def test_rcss_without_a_server_or_an_executable_says_how_to_give_one(tmp_path, monkeypatch):
    monkeypatch.delenv("RCSSSERVER", raising=False)
    monkeypatch.setenv("PATH", str(tmp_path))
    result = run("evolve", "--env", "rcss", *ONE_GENERATION, "--out", tmp_path / "run")
    assert_one_line_error(result, "no rcssserver: 'rcssserver' is not on PATH: give --rcssserver PATH "
                                  "(see docs/robocup/index.md), or --server HOST:PORT for a server you run")
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize("arguments, message", [
    (["--env", "rcss", "--server", "localhost:port"], "--server: bad server address 'localhost:port': expected HOST:PORT"),
    (["--env", "rcss", "--server", "127.0.0.1:70000"], "--server: bad server address '127.0.0.1:70000'"),
    (["--env", "rcss", "--server", "127.0.0.1:6000", "--server", "127.0.0.1:6000"], "a server is listed twice"),
    (["--env", "rcss", "--workers", "2"], "--workers: with env rcss the GA runs 1 worker"),
    (["--env", "rcss", "--count-touches"], "--count-touches: SimpleSoccer only"),
    (["--executor", "ray"], "--executor: for --env rcss only"),
    (["--env", "rcss", "--executor", "slurm"], "--executor: unknown executor 'slurm'"),
    (["--env", "rcss", "--address", "127.0.0.1:6379"], "--address needs --executor ray"),
    (["--env", "rcss", "--executor", "ray", "--server", "127.0.0.1:6000"], "--server names servers you run; with "
                                                                            "--executor ray every node starts its own"),
    (["--env", "rcss", "--games-per-evaluation", "3"], "--games-per-evaluation: SimpleSoccer only"),
    (["--env", "rcss", "--fitness", "style"], "--fitness: Input should be"),
    (["--env", "rcss", "--max-ticks", "0"], "--max-ticks: Input should be greater than 0"),
    (["--env", "rcss", "--skills", "lazy"], "--skills: Input should be 'strict', 'assisted' or 'sighted'"),
    (["--server", "127.0.0.1:6000"], "--server needs --env rcss"),
    (["--servers", "2", "--rcssserver", "/x"], "--rcssserver, --servers need --env rcss"),
    (["--env", "rcss", "--server", "127.0.0.1:6000", "--servers", "2"], "--server names servers you run; "
                                                                         "--rcssserver and --servers start servers"),
    (["--env", "rcss", "--servers", "0"], "--servers"),
    (["--env", "rcss", "--rcssserver", "/no/such/rcssserver"], "no rcssserver: '/no/such/rcssserver' does not exist"),
    (["--env", "robocup"], "--env: expected simple or rcss, got 'robocup'"),
])
def test_bad_options_are_one_line_before_any_connection(arguments, message, tmp_path, monkeypatch):
    def refuse(*_: object, **__: object) -> None:
        raise AssertionError("an rcss client or server was started before the options were checked")

    monkeypatch.setattr(rcss_client.Endpoint, "__init__", refuse)  # every player and trainer socket
    monkeypatch.setattr(rcss_servers.subprocess, "Popen", refuse)  # every rcssserver soccer-lab starts
    result = run("evolve", *arguments, "--out", tmp_path / "run")
    assert_one_line_error(result, message)
    assert not (tmp_path / "run").exists()


def test_resume_keeps_its_settings_but_a_simple_run_takes_no_server(tmp_path):
    folder = tmp_path / "simple"
    made = run("evolve", "--population-size", "2", "--generations", "1", "--max-ticks", "20", "--workers", "1",
               "--out", folder)
    assert made.exit_code == 0, made.output
    assert json.loads((folder / "run.json").read_text())["env"] == "simple"
    assert_one_line_error(run("evolve", "--resume", folder, "--env", "rcss"), "drop --env")
    assert_one_line_error(run("evolve", "--resume", folder, "--server", "127.0.0.1:6000"),
                          f"--server: the run in {folder} plays SimpleSoccer")


def test_play_shares_the_environment_options(tmp_path):
    rules = tmp_path / "kick.rules"
    rules.write_text("if Ball is At then Kick Straight High\n")
    assert_one_line_error(run("play", rules, "--env", "rcss", "--server", "nohost:x"), "--server: bad server address")
    assert_one_line_error(run("play", rules, "--server", "127.0.0.1:6000"), "--server needs --env rcss")
    with silent_server() as server:
        assert_one_line_error(run("play", rules, "--env", "rcss", "--server", server, "-n", "1"),
                              f"no reply from rcssserver at {server}")


def test_play_on_rcss_writes_each_trials_replay_as_the_server_played_it(tmp_path):
    reason = transcripts_missing()
    if reason:
        pytest.skip(reason)
    rules, rrd = tmp_path / "kick.rules", tmp_path / "trials.rrd"
    rules.write_text("if Ball is At then Kick Straight High\n")
    with replay_server(GOALS) as goals:
        result = run("play", rules, "--env", "rcss", "--server", goals.server, "-n", "1", "--max-ticks", GOALS_CYCLES,
                     "--rrd", rrd)
        assert goals.wait().error is None
    assert result.exit_code == 0, result.output
    assert f"replays written to {rrd}" in result.output
    replayed = [tuple(p[0]) for p in read_recording(rrd)["/game_1/ball"]["columns"]["Points2D:positions"]]
    np.testing.assert_array_equal(np.array(replayed), np.array(recorded_ball(GOALS), dtype=np.float32))


def test_help_says_how_workers_and_servers_go_together():
    text = " ".join(run("evolve", "--help").output.replace("│", " ").split())
    assert "Not with --env rcss" in text and "trials run in parallel over the servers" in text
    assert "server::synch_mode=true server::coach_w_referee=true" in text
