"""Matches on a real rcssserver (soccer/rcss/match.py): two of our clients, one per side, on a server soccer-lab
starts; the command's table, the sides swapped at half time, goals credited to the player who scored, the
right side's own frame, and (noise off) the same match twice."""

from __future__ import annotations

import json
import math
import statistics

import pytest
from typer.testing import CliRunner

import soccer_lab as sl
from soccer_lab.app.cli import app
from soccer_lab.soccer.rcss.client import Session
from soccer_lab.soccer.rcss.errors import RcssConfigError, RcssRefusedError
from soccer_lab.soccer.rcss.localisation import normalise_angle
from soccer_lab.soccer.rcss.match import RcssMatchConfig, play_rcss_matches
from soccer_lab.soccer.rcss.match_session import TEAMS, MatchSession
from soccer_lab.soccer.rcss.player import RcssPlayer, load_compiled_skills
from soccer_lab.soccer.rcss.servers import NOISELESS_OPTIONS
from tests.app.test_cli_match import DEMO, STRIKER

# The chaser (tests/rcss/conftest.py) scores within 300 cycles with the assisted skills; the hunter example turns
# toward the ball but never runs or kicks: whatever is scored, the chaser scored.
QUIET = RcssMatchConfig(max_ticks=300, skills="assisted", noise=False)


@pytest.fixture(scope="module", autouse=True)
def compiled_skills() -> None:
    load_compiled_skills()  # before any server waits for a player: loading them mid-match would miss cycles


def test_a_match_on_rcssserver_prints_the_table_with_both_sides_goals(rcssserver):
    """`soccer-lab match A B --env rcss --rcssserver PATH`: one match of 2 x 100 cycles on a server it starts,
    the same table as in SimpleSoccer, and the JSON's halves with A on the left first and on the right second."""
    options = ["match", str(DEMO), str(STRIKER), "--matches", "1", "--max-ticks", "100", "--env", "rcss",
               "--rcssserver", str(rcssserver)]
    printed = CliRunner().invoke(app, options)
    assert printed.exit_code == 0, printed.output
    header, row_a, row_b = [line for line in printed.stdout.splitlines() if not line.startswith("started")]
    assert header.split() == ["player", "wins", "draws", "losses", "goals", "for", "goals", "against"]
    assert row_a.split()[:2] == ["A", "demo.rules"] and row_b.split()[:2] == ["B", "striker.rules"]
    a, b = (list(map(int, row.split()[2:])) for row in (row_a, row_b))
    assert a[:3] == b[2::-1] and sum(a[:3]) == 1  # A's wins are B's losses, one match
    assert (a[3], a[4]) == (b[4], b[3])  # each side's goals for are the other's against
    played = json.loads(CliRunner().invoke(app, [*options, "--json"]).stdout)
    assert played["env"] == "rcss"
    (only,) = played["matches"]
    assert [half["left"] for half in only["halves"]] == ["A", "B"]
    assert [half["ticks"] for half in only["halves"]] == [100, 100]
    first, second = only["halves"]
    assert only["goals"] == [first["goals"][0] + second["goals"][1], first["goals"][1] + second["goals"][0]]


def test_sides_swap_at_half_time_and_each_goal_goes_to_the_player_who_scored(start_servers, chaser):
    """The referee's goal_l in the first half and goal_r in the second are both the chaser's (A's): it played the
    left connection, then the right one, and the server counted its kicks on each side in turn."""
    pool = start_servers(1, NOISELESS_OPTIONS)
    hunter = sl.example("hunter")
    with MatchSession(pool.addresses[0]) as session:
        session.open()
        assert [player.side for player in session.players] == ["l", "r"]
        (result,) = play_rcss_matches(session, chaser, hunter, [3], QUIET)
        assert session.late_cycles == 0  # the player that connected first caught up before play (MatchSession._settle)
    first, second = result.halves
    assert first.goals[0] >= 1 and first.goals[1] == 0 and first.kicks[0] >= first.goals[0] and first.kicks[1] == 0
    assert second.goals[1] >= 1 and second.goals[0] == 0 and second.kicks[1] >= second.goals[1] and second.kicks[0] == 0
    assert result.goals == (first.goals[0] + second.goals[1], 0) and result.winner == "A"
    # the ball's closest approach: near the goal the scorer attacks, the other goal untouched from the centre line
    assert first.min_ball_goal_distance[0] < 1.0 < 40.0 < first.min_ball_goal_distance[1]
    assert second.min_ball_goal_distance[1] < 1.0 < 40.0 < second.min_ball_goal_distance[0]
    assert (first.ticks, first.end_reason) == (second.ticks, second.end_reason) == (300, "max-ticks")


def test_a_server_plays_one_match_command_after_another(start_servers, chaser):
    """A server you run keeps each team's earlier players (gone, but numbered): the next command's players are
    numbers 2, then 3, and the trainer must place those (not number 1); and it lets the next trainer in only once
    it has found the last one gone. The same noiseless match three times over, the chaser's goals each time."""
    pool = start_servers(1, NOISELESS_OPTIONS)
    numbers, results = [], []
    for _ in range(3):
        with MatchSession(pool.addresses[0]) as session:
            session.open()
            numbers.append([player.unum for player in session.players])
            results += play_rcss_matches(session, chaser, sl.example("hunter"), [3], QUIET)
    assert numbers == [[1, 1], [2, 2], [3, 3]]
    assert results[0] == results[1] == results[2] and results[0].goals[0] >= 2


def test_the_right_side_player_knows_where_it_is_in_its_own_frame(start_servers, chaser):
    """Flag names are global, so the right side localises in side l's frame and turns it half a turn: its pose
    against the trainer's see_global (turned too), cycle by cycle, while it chases the ball."""
    pool = start_servers(1, NOISELESS_OPTIONS)
    errors, facing = [], []
    with MatchSession(pool.addresses[0]) as session:
        session.open()
        right = RcssPlayer(chaser, session.params, skills="assisted", side="r")
        trainer = session.trainer
        trainer.move_ball(10.0, 5.0)
        trainer.move_player(TEAMS[1], 1, 30.0, -12.0, 150.0)
        trainer.change_mode("play_on")
        commands: tuple[list[str], list[str]] = ([], [])
        for _ in range(80):
            cycles, trainer_cycle = session.step(commands)
            commands = ([], right.decide(cycles[1]))
            truth = trainer_cycle.see_global.player(TEAMS[1], 1)
            if cycles[1].see is not None and right.world.pose is not None:
                pose = right.world.pose
                errors.append(math.hypot(pose.x + truth.x, pose.y + truth.y))
                facing.append(abs(normalise_angle(pose.body - truth.body - 180.0)))
    assert len(errors) > 30
    assert statistics.median(errors) < 0.3 and max(errors) < 2.0
    assert statistics.median(facing) < 2.0


def test_without_noise_the_api_plays_the_match_the_command_printed_whatever_the_players_see_phases(rcssserver,
                                                                                                  monkeypatch):
    """Starts and restarts come from the match's seed, and each half puts both players' sees in the same step
    (without it the right player's see came in either phase, by when it connected, and the same seed played
    another match), so with the server's noise off the same match plays the same on another server: the
    command's JSON and sl.match(env="rcss") agree, half by half."""
    monkeypatch.setenv("RCSSSERVER", str(rcssserver))
    printed = CliRunner().invoke(app, ["match", str(STRIKER), str(DEMO), "--matches", "1", "--seed", "2",
                                       "--max-ticks", "150", "--skills", "assisted", "--env", "rcss", "--no-noise",
                                       "--json"])
    assert printed.exit_code == 0, printed.output
    played = sl.match(STRIKER, DEMO, matches=1, seed=2, env="rcss", max_ticks=150, skills="assisted", noise=False)
    as_printed = json.loads(printed.stdout)
    assert {key: as_printed[key] for key in ("a", "b", "matches")} == json.loads(json.dumps(played.to_dict()))
    assert sum(played.matches[0].goals) > 0


def test_a_server_with_another_team_on_it_is_refused_in_one_line(start_servers, chaser):
    pool = start_servers(1)
    with Session(pool.addresses[0]) as other:
        other.open()  # someone else's player: side l is taken
        with pytest.raises(RcssRefusedError, match="another team is connected to it; a match needs a server with "
                                                   "no other players"):
            MatchSession(pool.addresses[0]).open()


def test_a_match_needs_a_server_whose_noise_is_the_matchs(start_servers, chaser):
    pool = start_servers(1)
    with MatchSession(pool.addresses[0]) as session:
        session.open()
        with pytest.raises(RcssConfigError, match="adds noise, but the match wants none"):
            play_rcss_matches(session, chaser, chaser, [0], QUIET)
