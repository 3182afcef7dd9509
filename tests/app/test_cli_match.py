"""`soccer-lab match A B` (run as a real process) and `sl.match`: the same seed gives the same table, the command
and the API agree, bad input is one line and exit status 2."""

from __future__ import annotations

import json
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

import soccer_lab as sl

REPOSITORY = Path(__file__).resolve().parents[2]
EXAMPLES = REPOSITORY / "soccer" / "data" / "examples"
STRIKER, DEMO = EXAMPLES / "striker.rules", EXAMPLES / "demo.rules"
SOCCER_LAB = Path(sys.executable).parent / "soccer-lab"
SHORT = ["--matches", "3", "--max-ticks", "300"]


def match(*args: object) -> subprocess.CompletedProcess:
    return subprocess.run([str(SOCCER_LAB), "match", *map(str, args)], capture_output=True, text=True, timeout=600)


def test_the_same_seed_gives_the_same_table_and_another_seed_other_matches():
    first, again, other = match(STRIKER, DEMO, *SHORT, "--seed", 4), match(STRIKER, DEMO, *SHORT, "--seed", 4), \
        match(STRIKER, DEMO, *SHORT, "--seed", 5, "--json")
    assert first.returncode == 0, first.stderr
    assert first.stdout == again.stdout
    header, row_a, row_b = first.stdout.splitlines()
    assert header.split()[:4] == ["player", "wins", "draws", "losses"]
    assert row_a.split()[:2] == ["A", "striker.rules"] and row_b.split()[:2] == ["B", "demo.rules"]
    wins_a, draws_a, losses_a, for_a, against_a = map(int, row_a.split()[2:])
    wins_b, draws_b, losses_b, for_b, against_b = map(int, row_b.split()[2:])
    assert (wins_a, draws_a, losses_a) == (losses_b, draws_b, wins_b) and wins_a + draws_a + losses_a == 3
    assert (for_a, against_a) == (against_b, for_b)
    assert [m["seed"] for m in json.loads(other.stdout)["matches"]] == [5, 6, 7]


def test_the_api_gives_the_table_and_matches_the_command_prints():
    printed = json.loads(match(STRIKER, DEMO, *SHORT, "--seed", 2, "--json").stdout)
    played = sl.match(STRIKER, DEMO, matches=3, seed=2, max_ticks=300)
    assert printed["players"] == {"A": str(STRIKER), "B": str(DEMO)}
    assert printed["env"] == "simple"
    assert {k: v for k, v in printed.items() if k not in ("players", "seed", "env")} == json.loads(json.dumps(
        played.to_dict()))
    assert sum(m.goals[0] + m.goals[1] for m in played.matches) > 0
    assert played.a.goals_for == sum(m.goals[0] for m in played.matches)


def test_seeing_the_opponent_plays_rules_that_name_it(tmp_path):
    watcher = tmp_path / "watcher.rules"
    watcher.write_text("if Opponent is not VeryFar and Ball is not At then GoToBall VeryHigh\n")
    refused = match(watcher, DEMO, *SHORT)
    assert refused.returncode == 2 and "watcher.rules" in refused.stderr
    played = match(watcher, DEMO, *SHORT, "--see-opponent", "--json")
    assert played.returncode == 0, played.stderr
    assert json.loads(played.stdout)["a"] == sl.match(watcher, DEMO, matches=3, max_ticks=300,
                                                      see_opponent=True).to_dict()["a"]


@pytest.mark.parametrize("args, fragment", [
    ([STRIKER, "missing.rules"], "missing.rules: no such file"),
    ([STRIKER, DEMO, "--matches", "0"], "--matches"),
    ([STRIKER, DEMO, "--seed", "-1"], "--seed"),
    ([STRIKER, DEMO, "--max-ticks", "0"], "--max-ticks"),
    ([STRIKER, DEMO, "--skills", "magic"], "--skills"),
    ([STRIKER], "Missing argument"),
    ([STRIKER, DEMO, "--env", "rcss", "--see-opponent", "--server", "127.0.0.1:6000"],
     "--see-opponent: SimpleSoccer only, not with --env rcss"),
    ([STRIKER, DEMO, "--rcssserver", "/usr/bin/rcssserver"], "--rcssserver needs --env rcss"),
    ([STRIKER, DEMO, "--env", "rcss", "--server", "127.0.0.1:6000", "--server", "127.0.0.1:6010"],
     "--server: a match plays on one server"),
    ([STRIKER, DEMO, "--env", "rcss", "--server", "127.0.0.1:6000", "--rcssserver", "/usr/bin/rcssserver"],
     "give one or the other"),
    ([STRIKER, DEMO, "--env", "rcss", "--rcssserver", "/nowhere/rcssserver"], "no rcssserver: '/nowhere/rcssserver'"),
    ([STRIKER, DEMO, "--env", "rcss", "--server", "127.0.0.1:9", "--max-ticks", "0"], "--max-ticks"),
])
def test_bad_input_is_one_line_and_status_2(args, fragment):
    done = match(*args)
    assert done.returncode == 2
    assert fragment in done.stderr and len(done.stderr.strip().splitlines()) == 1 and "Traceback" not in done.stderr


@pytest.mark.parametrize("arguments, error", [({"matches": 0}, ValueError), ({"seed": -1}, ValueError),
                                              ({"max_ticks": 0}, ValueError), ({"colour": "red"}, TypeError),
                                              ({"env": "robocup"}, ValueError),
                                              ({"server": "127.0.0.1:6000"}, ValueError),
                                              ({"env": "rcss", "see_opponent": True}, ValueError),
                                              ({"env": "rcss", "colour": "red"}, TypeError),
                                              ({"env": "rcss", "count_touches": True}, TypeError)])
def test_the_api_refuses_bad_options(arguments, error):
    with pytest.raises(error):
        sl.match(STRIKER, DEMO, **arguments)


# ---- evolve --opponent: the GA's fitness over matches against a fixed player ------------------------------
EVOLVE = ["--population-size", "12", "--generations", "2", "--max-ticks", "300", "--workers", "1", "--seed", "1"]


def evolve(*args: object) -> subprocess.CompletedProcess:
    return subprocess.run([str(SOCCER_LAB), "evolve", *map(str, args)], capture_output=True, text=True, timeout=600)


def test_evolve_against_an_opponent_plays_matches_keeps_the_opponent_and_the_api_agrees(tmp_path):
    from soccer_lab.app.runs.run import Run, RunSettings
    from soccer_lab.fuzzy.printer import format_rulebase
    from soccer_lab.soccer.config import SOCCER_VOCABULARY
    from soccer_lab.soccer.match import MatchEvaluator

    done = evolve(*EVOLVE, "--opponent", STRIKER, "--out", tmp_path / "cli")
    assert done.returncode == 0, done.stderr
    assert "each evaluation was a match against the opponent" in done.stdout
    run = Run.open(tmp_path / "cli")
    striker = sl.load_rules(STRIKER)
    assert run.settings.opponent == format_rulebase(striker, SOCCER_VOCABULARY)
    assert RunSettings.from_dict(run.settings.to_dict()) == run.settings  # resume plays the same opponent
    with run.evaluator() as evaluate:
        assert evaluate == MatchEvaluator(striker, run.settings.game)
    # its best's true quality: one match against the opponent from each common start
    from soccer_lab.app.runs.true_quality import common_seeds, replayed_quality

    best = sl.open_run(tmp_path / "cli").best
    assert run.best_quality == replayed_quality(best.rules, MatchEvaluator(striker, run.settings.game), common_seeds())
    assert "best player's true quality: re-played on 20 fresh starts" in done.stdout
    alone = evolve(*EVOLVE, "--out", tmp_path / "alone")
    assert alone.returncode == 0, alone.stderr
    api = sl.evolve(population_size=12, generations=2, max_ticks=300, workers=1, seed=1, opponent=STRIKER,
                    out=tmp_path / "api")
    cli = sl.open_run(tmp_path / "cli")
    assert _without_wall_time(api.statistics) == _without_wall_time(cli.statistics)
    assert _without_wall_time(cli.statistics) != _without_wall_time(sl.open_run(tmp_path / "alone").statistics)
    assert sl.format_rules(api.best.rules) == sl.format_rules(cli.best.rules)
    assert 0.5 < cli.best.fitness < 1.0  # a match drawn or lost with the ball brought closer: match_fitness's range


def _without_wall_time(statistics: list[dict]) -> list[dict]:
    return [{k: v for k, v in row.items() if k != "wall_time"} for row in statistics]


@pytest.mark.parametrize("args, fragment", [
    (["--opponent", "missing.rules"], "--opponent: missing.rules: no such file"),
    (["--opponent", STRIKER, "--env", "rcss", "--server", "localhost:6000"], "--opponent"),
])
def test_evolve_refuses_a_bad_opponent_in_one_line(args, fragment, tmp_path):
    done = evolve(*EVOLVE, *args, "--out", tmp_path / "run")
    assert done.returncode == 2 and fragment in done.stderr and len(done.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "run").exists()


def test_the_api_refuses_an_opponent_with_no_rules(tmp_path):
    empty = tmp_path / "empty.rules"
    empty.write_text("\n")
    with pytest.raises(ValueError):
        sl.evolve(population_size=4, generations=1, opponent=empty, out=tmp_path / "run")


def test_a_match_on_an_rcssserver_that_does_not_answer_is_one_line_within_seconds():
    started = time.monotonic()
    done = match(STRIKER, DEMO, "--env", "rcss", "--server", f"127.0.0.1:{silent_port()}")
    assert done.returncode == 2 and "no reply from rcssserver at 127.0.0.1:" in done.stderr, done.stderr
    assert len(done.stderr.strip().splitlines()) == 1 and time.monotonic() - started < 30


def silent_port() -> int:
    """A UDP port nobody answers on (bound and closed: free for a moment)."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]
