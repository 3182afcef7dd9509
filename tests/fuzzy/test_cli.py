"""`soccer-lab rules check|infer|export` through typer's CliRunner."""

import json

import pytest
from typer.testing import CliRunner

from soccer_lab.app.cli import rules
from soccer_lab.fuzzy.export import rulebase_from_json
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary

VOCABULARY = Vocabulary.default()

RUNNER = CliRunner()
TEXT = (
    "# demo\n"
    "if ball is near OR Ball is not Far and Goal is Near then RunTowardBall Low\n"
    "if Ball is At then Kick SlightlyRight High\n"
    "if Ball is Straight then Turn Left [power High]\n"
)
NORMALISED = (
    "if (Ball is Near or Ball is not Far) and Goal is Near then RunTowardBall Low\n"
    "if Ball is At then Kick SlightlyRight High\n"
    "if Ball is Straight then Turn Left [power High]\n"
)


@pytest.fixture
def rule_file(tmp_path):
    path = tmp_path / "rules.txt"
    path.write_text(TEXT)
    return path


def run(*args):
    return RUNNER.invoke(rules.app, [str(a) for a in args])


def test_check_prints_normalised_rules(rule_file):
    result = run("check", rule_file)
    assert result.exit_code == 0 and result.stdout == NORMALISED


def test_check_reports_every_error_with_position(tmp_path):
    path = tmp_path / "bad.txt"
    path.write_text("if Ball is Nearr then Turn\nif Ball is Near then Turn\nif Ball is Near Jump\n")
    result = run("check", path)
    assert result.exit_code == 2
    lines = result.stderr.splitlines()
    assert len(lines) == 2
    assert lines[0].startswith(f"{path}:1:12: expected 'not' or a term")
    assert lines[1] == f"{path}:3:17: expected 'and', 'or' or 'then', found 'Jump'"


def test_infer_prints_degrees_strengths_fired_and_selected(rule_file):
    result = run("infer", rule_file, "--input", "ball_distance=3", "--input", "ball_direction=0",
                 "-i", "goal_distance=4", "-i", "goal_direction=10")
    assert result.exit_code == 0, result.stderr
    report = json.loads(result.stdout)
    assert report["visible"] == {"BALL": True, "GOAL": True}
    assert report["rules"][0]["premises"] == [
        {"premise": "Ball is Near", "degree": 0.5}, {"premise": "Ball is not Far", "degree": 1.0},
        {"premise": "Goal is Near", "degree": 1.0}]
    assert [r["strength"] for r in report["rules"]] == [1.0, 0.0, 1.0]
    assert report["fired"] == [
        {"action": "RUNTOWARDBALL", "support": 1.0, "parameters": {"power": 25.0}},
        {"action": "TURN", "support": 1.0, "parameters": {"direction": -45.0}}]
    assert report["selected"]["action"] == "RUNTOWARDBALL" and report["hunt"] is False


def test_infer_with_no_object_visible_hunts(rule_file):
    report = json.loads(run("infer", rule_file).stdout)
    assert report["visible"] == {"BALL": False, "GOAL": False}
    assert report["fired"] == [] and report["selected"] is None and report["hunt"] is True


@pytest.mark.parametrize("argument, message", [
    ("ball_distance", "expected NAME=VALUE"),
    ("ball_speed=3", "unknown input 'ball_speed'"),
    ("ball_distance=far", "'far' is not a number"),
    ("ball_distance=nan", "must be a finite number"),
    ("ball_distance=3", "ball_direction is missing"),
])
def test_infer_rejects_bad_inputs_in_one_line(rule_file, argument, message):
    result = run("infer", rule_file, "--input", argument)
    assert result.exit_code == 2
    assert result.stderr.startswith("error: ") and message in result.stderr and result.stderr.count("\n") == 1


@pytest.mark.parametrize("fmt, marker", [("json", '"format": "soccer-lab-rulebase"'), ("fcl", "FUNCTION_BLOCK"),
                                         ("fll", "Engine: soccer_lab"), ("fis", "Type='mamdani'")])
def test_export_formats(rule_file, tmp_path, fmt, marker):
    result = run("export", rule_file, "--format", fmt)
    assert result.exit_code == 0 and marker in result.stdout
    out = tmp_path / f"out.{fmt}"
    assert run("export", rule_file, "-f", fmt, "-o", out).exit_code == 0
    assert out.read_text() == result.stdout


def test_exported_json_is_accepted_back(rule_file, tmp_path):
    out = tmp_path / "rules.json"
    run("export", rule_file, "-o", out)
    assert rulebase_from_json(out.read_text())[0] == parse_rulebase(TEXT, VOCABULARY)
    assert run("check", out).stdout == NORMALISED


@pytest.mark.parametrize("args, message", [
    (["export", "RULES", "--format", "xml"], "unknown format 'xml'"),
    (["check", "MISSING"], "cannot read"),
    (["check", "JSON"], "rules[0].premises: expected a non-empty list"),
])
def test_bad_files_and_options(rule_file, tmp_path, args, message):
    bad_json = tmp_path / "bad.json"
    bad_json.write_text('{"format": "soccer-lab-rulebase", "version": 1, "rules": [{"premises": [], '
                        '"connectors": [], "consequent": {"action": "DASH", "direction": null, "power": null}}]}')
    paths = {"RULES": rule_file, "MISSING": tmp_path / "missing.txt", "JSON": bad_json}
    result = run(*[paths.get(a, a) for a in args])
    assert result.exit_code == 2 and message in result.stderr and result.stderr.count("\n") == 1
