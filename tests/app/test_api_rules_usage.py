"""POST /api/rules/usage and /api/rules/simplify through FastAPI's test client."""

from __future__ import annotations

import pytest

from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.engine import play_game
from tests.app.api_client import api_client

VOCABULARY = Vocabulary.default()
SHORT = {"max_ticks": 150, "idle_ticks": 60}
PLAYER = ("if Ball is At then KickTowardGoal High\n"
          "if Ball is not At and Ball is not VeryFar then GoToBall VeryHigh\n"
          "if Ball is At then KickTowardGoal High\n"
          "if Ball is Near and Ball is not Far then Dash High\n"
          "if Ball is Straight and Goal is Far then Dash Low\n")


@pytest.fixture
def client(tmp_path):
    with api_client(tmp_path) as opened:
        yield opened


def test_usage_of_text_and_of_a_saved_rulebase(client):
    body = {"text": PLAYER, "games": 2, "seed": 5, "game": SHORT}
    usage = client.post("/api/rules/usage", json=body)
    assert usage.status_code == 200, usage.text
    document = usage.json()
    traces = [play_game(parse_rulebase(PLAYER, VOCABULARY), seed, GameConfig(**SHORT))[1] for seed in (5, 6)]
    assert document["seeds"] == [5, 6] and document["ticks"] == sum(len(t) for t in traces)
    assert [r["fired"] for r in document["rules"]] == [sum(int((t.strengths[:, r] > 0).sum()) for t in traces)
                                                       for r in range(5)]
    assert document["hunt"] == sum(int((t.action == -1).sum()) for t in traces)
    assert {a["action"] for a in document["actions"]} == set(VOCABULARY.action_names)
    saved = client.post("/api/rulebases", json={"name": "p", "text": PLAYER}).json()
    by_id = client.post("/api/rules/usage", json={"rulebase_id": saved["id"], "games": 2, "seed": 5, "game": SHORT})
    assert by_id.json() == document


def test_simplify_exact_and_checked(client):
    exact = client.post("/api/rules/simplify", json={"text": PLAYER})
    assert exact.status_code == 200, exact.text
    document = exact.json()
    assert document["games"] == 0 and document["results"] is None
    assert {s["kind"] for s in document["steps"]} == {"exact"}
    assert document["before"] == {"rules": 5, "premises": 8} and document["after"] == {"rules": 4, "premises": 6}
    assert document["origins"] == [1, 2, 4, 5]
    checked = client.post("/api/rules/simplify", json={"text": PLAYER, "games": 3, "game": SHORT}).json()
    step = checked["steps"][-1]
    assert (step["name"], step["kind"], step["games"], step["applied"]) == ("never-won-rules", "checked", 3, True)
    assert checked["results"]["before"] == checked["results"]["after"]
    usage = client.post("/api/rules/usage", json={"text": PLAYER, "games": 3, "game": SHORT}).json()
    never_won = {r["rule"] for r in usage["rules"] if r["won"] == 0} & set(document["origins"])
    assert never_won and {c["rule"] for c in step["changes"]} == never_won
    exact_lines = dict(zip(document["origins"], document["text"].splitlines()))
    assert checked["text"].splitlines() == [line for rule, line in exact_lines.items() if rule not in never_won]


@pytest.mark.parametrize("path, body, status, fragment", [
    ("usage", {"games": 2}, 422, "exactly one of 'text' and 'rulebase_id'"),
    ("usage", {"text": PLAYER, "games": 0}, 422, "games"),
    ("usage", {"text": PLAYER, "games": 100_000}, 422, "games"),
    ("usage", {"text": PLAYER, "games": 1000, "game": {"max_ticks": 5000}}, 422, "such games can be played"),
    ("usage", {"text": "# nothing"}, 422, "holds no rule"),
    ("usage", {"text": "if Ball is Nearr then Dash"}, 422, "invalid rule text: line 1"),
    ("usage", {"rulebase_id": 99}, 404, "no rulebase with id 99"),
    ("simplify", {"text": PLAYER, "games": -1}, 422, "games"),
    ("simplify", {"text": PLAYER, "drop_unused": True}, 422, "drop_unused"),
    ("simplify", {"text": PLAYER, "game": {"max_ticks": 0}}, 422, "max_ticks"),
])
def test_bad_requests_are_refused_with_a_reason(client, path, body, status, fragment):
    response = client.post(f"/api/rules/{path}", json=body)
    assert response.status_code == status, response.text
    assert fragment in response.json()["detail"]


def test_simplify_of_nothing_playable_without_games_is_fine(client):
    response = client.post("/api/rules/simplify", json={"text": "if Ball is At and Ball is Far then Dash"})
    assert response.status_code == 200 and response.json()["text"] == ""
