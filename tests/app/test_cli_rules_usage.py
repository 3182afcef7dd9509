"""`soccer-lab rules usage` and `rules simplify`: what they print, write and refuse."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from typer.testing import CliRunner

from soccer_lab.app.cli import app
from soccer_lab.fuzzy.export import rulebase_from_json
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.printer import format_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.engine import play_game

VOCABULARY = Vocabulary.default()
SHORT = ["--max-ticks", "150", "--idle-ticks", "60"]
RULES = """\
if Ball is At then KickTowardGoal High
if Ball is not At and Ball is not VeryFar then GoToBall VeryHigh
if Ball is At then KickTowardGoal High
if Ball is Near and Ball is not Far then Dash High [direction Left]
if Ball is VeryFar or Ball is VeryFar then RunTowardBall Low
if Ball is Straight and Goal is Far then Dash Low
"""



def run(*args):
    return CliRunner().invoke(app, [str(a) for a in args])


@pytest.fixture
def rules_file(tmp_path):
    path = tmp_path / "player.rules"
    path.write_text(RULES)
    return path


def assert_one_line_error(result, fragment):
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and fragment in lines[0], result.output


def test_usage_prints_a_row_per_rule_and_the_hunt_share(rules_file):
    result = run("rules", "usage", rules_file, "--games", "3", "--seed", "2", *SHORT)
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    assert lines[0].startswith("rule usage over 3 games (seeds 2-4)")
    assert "hunted" in lines[0]
    rows = [line for line in lines if line[:4].strip().isdigit()]
    assert [int(r[:4]) for r in rows] == [1, 2, 3, 4, 5, 6]
    assert any(line.startswith("actions performed: ") for line in lines)


def test_usage_json_counts_match_the_games(rules_file):
    result = run("rules", "usage", rules_file, "--games", "2", "--json", *SHORT)
    assert result.exit_code == 0, result.output
    document = json.loads(result.output)
    config = GameConfig(max_ticks=150, idle_ticks=60)
    rulebase = parse_rulebase(RULES, VOCABULARY)
    traces = [play_game(rulebase, seed, config)[1] for seed in (0, 1)]
    assert document["ticks"] == sum(len(t) for t in traces)
    assert document["hunt"] == sum(int((t.action == -1).sum()) for t in traces)
    for r, rule in enumerate(document["rules"]):
        assert rule["fired"] == sum(int((t.strengths[:, r] > 0).sum()) for t in traces)
    assert [g["seed"] for g in document["results"]["games"]] == [0, 1]


def test_simplify_exact_only_by_default_and_writes_the_rules(rules_file, tmp_path):
    out = tmp_path / "short.rules"
    result = run("rules", "simplify", rules_file, "-o", out)
    assert result.exit_code == 0, result.output
    assert "exact steps" in result.output and "checked steps" not in result.output
    assert "size: 6 rules, 10 premises -> " in result.output
    written = parse_rulebase(out.read_text(), VOCABULARY)
    assert format_rulebase(written, VOCABULARY).splitlines() == [
        "if Ball is At then KickTowardGoal High",
        "if Ball is not At and Ball is not VeryFar then GoToBall VeryHigh",
        "if Ball is Near then Dash High [direction Left]",
        "if Ball is VeryFar then RunTowardBall Low",
        "if Ball is Straight and Goal is Far then Dash Low",
    ]


def test_simplify_with_games_checks_and_says_so(rules_file, tmp_path):
    out = tmp_path / "short.json"
    result = run("rules", "simplify", rules_file, "--games", "3", "--drop-unused-fields", "-o", out, *SHORT)
    assert result.exit_code == 0, result.output
    assert "checked on 3 games: all 3 games replayed identically, tick for tick" in result.output
    rulebase, _ = rulebase_from_json(out.read_text())
    before, after = [line for line in result.output.splitlines() if line.startswith(("before:", "after:"))]
    assert before.split(":", 1)[1].strip() == after.split(":", 1)[1].strip()
    assert len(rulebase) < 5 and all(r.consequent.direction is None for r in rulebase)


def test_simplify_json_names_every_step_and_its_kind(rules_file):
    result = run("rules", "simplify", rules_file, "--games", "2", "--json", *SHORT)
    assert result.exit_code == 0, result.output
    document = json.loads(result.output)
    kinds = {s["name"]: s["kind"] for s in document["steps"]}
    assert kinds["duplicate-rules"] == "exact" and kinds["never-won-rules"] == "checked"
    assert document["games"] == 2 and document["results"]["before"] == document["results"]["after"]
    duplicate = next(s for s in document["steps"] if s["name"] == "duplicate-rules")
    assert duplicate["changes"] == [{"rule": 3, "before": "if Ball is At then KickTowardGoal High", "after": None,
                                     "reason": "the same as rule 1"}]


@pytest.mark.parametrize("args, fragment", [
    (["rules", "usage", "missing.rules"], "cannot read missing.rules"),
    (["rules", "usage", "{file}", "--games", "0"], "--games"),
    (["rules", "simplify", "{file}", "--games", "-1"], "--games"),
    (["rules", "usage", "{file}", "--max-ticks", "0"], "--max-ticks"),
    (["rules", "simplify", "{file}", "-o", "{folder}"], "is a folder"),
    (["rules", "usage", "{empty}"], "holds no rule"),
])
def test_bad_input_gives_one_line(rules_file, tmp_path, args, fragment):
    empty = tmp_path / "empty.rules"
    empty.write_text("# nothing\n")
    values = {"file": rules_file, "folder": tmp_path, "empty": empty}
    result = run(*[a.format(**values) for a in args])
    assert_one_line_error(result, fragment)


def test_the_installed_command_runs(rules_file):
    script = Path(sys.executable).parent / "soccer-lab"
    result = subprocess.run([str(script), "rules", "simplify", str(rules_file)], capture_output=True, text=True,
                            timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.rstrip().endswith("if Ball is Straight and Goal is Far then Dash Low")
