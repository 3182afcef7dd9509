"""Every request's cost is bounded (issues 22 and 25): each upper bound refused with a message naming the
limit, in the API, the CLI and the UI's fields; the heaviest allowed usage request answers, one step past
it is refused before any game is played. docs/reference/limits.md lists the limits."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from soccer_lab.app.cli import app
from soccer_lab.app.rule_inspection import (MAX_RULES, MAX_WORK, SIMPLIFY_PLAYS, USAGE_PLAYS, affordable_games,
                                            request_work)
from soccer_lab.app.web.ui.panels.evolve import ga_fields
from soccer_lab.ga.config import MAX_POPULATION, MAX_WORKERS
from soccer_lab.soccer.config import MAX_GAMES_PER_EVALUATION, MAX_TICKS
from tests.app.api_client import api_client
from tests.app.test_ui_wiring import gui  # noqa: F401  (fixture)

RULE = "if Ball is not At then GoToBall VeryHigh"


@pytest.fixture(scope="module")
def client(tmp_path_factory):
    with api_client(tmp_path_factory.mktemp("limits")) as opened:
        yield opened


@pytest.mark.parametrize("body, where, limit", [
    ({"ga": {"population_size": MAX_POPULATION + 1}}, "ga.population_size", MAX_POPULATION),
    ({"ga": {"workers": MAX_WORKERS + 1}}, "ga.workers", MAX_WORKERS),
    ({"game": {"max_ticks": MAX_TICKS + 1}}, "game.max_ticks", MAX_TICKS),
    ({"game": {"goal_cap": MAX_TICKS + 1}}, "game.goal_cap", MAX_TICKS),
    ({"game": {"idle_ticks": 10**9}}, "game.idle_ticks", MAX_TICKS),
    ({"game": {"games_per_evaluation": MAX_GAMES_PER_EVALUATION + 1}}, "game.games_per_evaluation",
     MAX_GAMES_PER_EVALUATION),
])
def test_the_api_refuses_a_run_past_each_limit_naming_it(client, body, where, limit):
    response = client.post("/api/runs", json=body)
    assert response.status_code == 422, response.text
    detail = response.json()["detail"]
    assert where.split(".")[-1] in detail and (str(limit) in detail or f"{limit:,}" in detail), detail
    assert client.get("/api/runs").json() == []


def test_usage_and_simplify_refuse_too_many_rules_or_too_much_work(client):
    many = "\n".join([RULE] * (MAX_RULES + 1))
    for route in ("usage", "simplify"):
        response = client.post(f"/api/rules/{route}", json={"text": many, "games": 1, "game": {"max_ticks": 10}})
        assert response.status_code == 422 and f"{MAX_RULES:,}" in response.json()["detail"], route
        # 5,000 rules, 1 game of 20,000 ticks (the probe took 3 GB): refused at once
        probe = {"text": "\n".join([RULE] * 5000), "games": 1,
                 "game": {"max_ticks": 20_000, "goal_cap": 10**9, "idle_ticks": 10**9}}
        assert client.post(f"/api/rules/{route}", json=probe).status_code == 422
    # 30 rules x 1,000 games of 1,000 ticks: refused, saying how many games would be played
    thirty = "\n".join([RULE] * 30)
    response = client.post("/api/rules/usage", json={"text": thirty, "games": 1000, "game": {"max_ticks": 1000}})
    most = affordable_games(30, 1000, USAGE_PLAYS)
    assert response.status_code == 422 and f"at most {most:,} such games can be played" in response.json()["detail"]
    # Simplification plays each game twice: the most games usage may play is too many to simplify on
    twenty = "\n".join([RULE] * 20)
    usage_most = affordable_games(20, 1000, USAGE_PLAYS)
    body = {"text": twenty, "games": usage_most, "game": {"max_ticks": 1000}}
    response = client.post("/api/rules/simplify", json=body)
    assert response.status_code == 422 and "can be simplified on" in response.json()["detail"]
    # Not one game fits: the message says to play fewer ticks
    thousand = "\n".join([RULE] * MAX_RULES)
    response = client.post("/api/rules/usage", json={"text": thousand, "games": 1, "game": {"max_ticks": 10_000}})
    if request_work(MAX_RULES, 1, 10_000, USAGE_PLAYS) > MAX_WORK:
        assert response.status_code == 422 and "fewer ticks" in response.json()["detail"]


@pytest.mark.parametrize("route, plays", [("usage", USAGE_PLAYS), ("simplify", SIMPLIFY_PLAYS)])
def test_the_heaviest_allowed_request_answers(client, route, plays):
    """The most games the work bound allows (games end early here: the cost is the bound's)."""
    twenty = "\n".join([RULE] * 20)
    games = affordable_games(20, 1000, plays)
    assert request_work(20, games, 1000, plays) <= MAX_WORK < request_work(20, games + 1, 1000, plays)
    response = client.post(f"/api/rules/{route}", json={"text": twenty, "games": games, "game": {"max_ticks": 1000}})
    assert response.status_code == 200, response.text


@pytest.mark.parametrize("option, value, limit", [
    ("--population-size", MAX_POPULATION + 1, MAX_POPULATION),
    ("--workers", MAX_WORKERS + 1, MAX_WORKERS),
    ("--max-ticks", MAX_TICKS + 1, MAX_TICKS),
    ("--games-per-evaluation", MAX_GAMES_PER_EVALUATION + 1, MAX_GAMES_PER_EVALUATION),
])
def test_the_cli_refuses_each_limit_in_one_line(tmp_path, option, value, limit):
    result = CliRunner().invoke(app, ["evolve", option, str(value), "--out", str(tmp_path / "run")])
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and option in lines[0] and str(limit) in lines[0].replace(",", ""), result.output
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize("name, limit", [("population_size", MAX_POPULATION), ("workers", MAX_WORKERS)])
def test_the_ui_fields_refuse_past_the_limits_naming_them(gui, name, limit):  # noqa: F811
    from soccer_lab.app.web.ui.number_field import NumberField

    number = NumberField.for_field(gui, name, ga_fields()[name])
    number.text.value = str(limit + 1)
    assert number.problem is not None and f"≤ {limit}" in number.problem
    with pytest.raises(ValueError, match=str(limit)):
        number.value
    number.text.value = str(limit)
    assert number.problem is None and number.value == limit
