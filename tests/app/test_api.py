"""The JSON API through FastAPI's test client: rulebases, rules, vocabulary, errors."""

from __future__ import annotations

import pytest

from tests.app.api_client import api_client

NEAR_DASH = "if Ball is Near then Dash High"
TWO_RULES = "if Ball is Near then Dash High\nif Goal is not Far and Ball is At then KickTowardGoal Low\n"


@pytest.fixture
def client(tmp_path):
    with api_client(tmp_path) as opened:
        yield opened


def test_landing_page_docs_and_openapi(client):
    home = client.get("/")
    assert home.status_code == 200 and "soccer-lab" in home.text and 'href="docs"' in home.text
    assert client.get("/favicon.svg").status_code == 200
    assert client.get("/docs").status_code == 200
    paths = client.get("/openapi.json").json()["paths"]
    for path in ("/api/vocabulary", "/api/rulebases/{rulebase_id}", "/api/rules/evaluate", "/api/runs/{run_id}/best"):
        assert path in paths


def test_vocabulary_publishes_terms_actions_and_defaults(client):
    vocabulary = client.get("/api/vocabulary").json()
    assert vocabulary["variables"]["distance"]["terms"]["NEAR"] == [2.0, 4.0, 4.0, 8.0]
    assert vocabulary["actions"]["KICK"] == ["direction", "power"]
    assert vocabulary["ga_defaults"]["population_size"] == 200
    assert vocabulary["ga_defaults"]["mutation_probability"] == 0.35
    assert vocabulary["game_defaults"]["max_ticks"] == 1000
    assert vocabulary["game_defaults"]["world"]["ball_decay"] == 0.94


def test_rulebase_create_list_read_update_delete(client):
    created = client.post("/api/rulebases", json={"name": "near", "text": NEAR_DASH})
    assert created.status_code == 201
    rulebase = created.json()
    assert rulebase["name"] == "near" and rulebase["text"] == NEAR_DASH
    other = client.post("/api/rulebases", json={"name": "two", "text": TWO_RULES}).json()
    assert [r["id"] for r in client.get("/api/rulebases").json()] == [other["id"], rulebase["id"]]  # newest first
    assert client.get(f"/api/rulebases/{rulebase['id']}").json() == rulebase

    renamed = client.put(f"/api/rulebases/{rulebase['id']}", json={"name": "renamed"}).json()
    assert renamed["name"] == "renamed" and renamed["text"] == NEAR_DASH
    retexted = client.put(f"/api/rulebases/{rulebase['id']}", json={"text": TWO_RULES}).json()
    assert retexted["name"] == "renamed" and retexted["text"] == TWO_RULES

    assert client.delete(f"/api/rulebases/{rulebase['id']}").status_code == 204
    missing = client.get(f"/api/rulebases/{rulebase['id']}")
    assert missing.status_code == 404 and missing.json()["detail"] == f"no rulebase with id {rulebase['id']}"
    assert client.delete(f"/api/rulebases/{rulebase['id']}").status_code == 404
    assert [r["id"] for r in client.get("/api/rulebases").json()] == [other["id"]]


def test_invalid_rule_text_is_refused_with_line_and_column_and_nothing_changes(client):
    saved = client.post("/api/rulebases", json={"name": "kept", "text": NEAR_DASH}).json()
    bad = "if Ball is Near then Dash High\nif Ball is Nearby then Dash High\nif Goal then Turn Left\n"
    for response in (
        client.post("/api/rulebases", json={"name": "bad", "text": bad}),
        client.put(f"/api/rulebases/{saved['id']}", json={"name": "bad", "text": bad}),
    ):
        assert response.status_code == 422
        errors = response.json()["errors"]
        assert [(e["line"], e["column"]) for e in errors] == [(2, 12), (3, 9)]
        assert "expected" in errors[0]["message"] and "Nearby" in errors[0]["message"]
        assert response.json()["detail"].startswith("invalid rule text: line 2, column 12")
    assert client.get("/api/rulebases").json() == [saved]


def test_a_rulebase_without_rules_is_refused_as_the_ui_refuses_it(client):
    saved = client.post("/api/rulebases", json={"name": "kept", "text": NEAR_DASH}).json()
    for empty in ("", "# only a comment\n", "\n\n"):
        for response in (client.post("/api/rulebases", json={"name": "empty", "text": empty}),
                         client.put(f"/api/rulebases/{saved['id']}", json={"text": empty})):
            assert response.status_code == 422
            assert "holds no rule" in response.json()["detail"]
    assert client.get("/api/rulebases").json() == [saved]


def test_rulebase_bodies_are_checked(client):
    assert client.post("/api/rulebases", json={"name": "", "text": NEAR_DASH}).status_code == 422
    assert client.post("/api/rulebases", json={"name": "   ", "text": NEAR_DASH}).status_code == 422
    assert client.post("/api/rulebases", json={"text": NEAR_DASH}).status_code == 422
    unknown = client.post("/api/rulebases", json={"name": "a", "text": NEAR_DASH, "owner": "me"})
    assert unknown.status_code == 422 and "owner" in unknown.json()["detail"]
    empty_update = client.put("/api/rulebases/1", json={})
    assert empty_update.status_code == 422 and "give 'name', 'text' or both" in empty_update.json()["detail"]


def test_parse_returns_rules_and_canonical_text(client):
    response = client.post("/api/rules/parse", json={"text": "IF ball IS near THEN dash high  # comment\n"})
    assert response.status_code == 200
    body = response.json()
    assert body["text"].strip() == NEAR_DASH
    (rule,) = body["rules"]
    assert rule["premises"] == [{"object": "BALL", "term": "NEAR", "negated": False}]
    assert rule["connectors"] == []
    assert rule["consequent"] == {"action": "DASH", "direction": None, "power": "HIGH"}


def test_parse_reports_every_error(client):
    response = client.post("/api/rules/parse", json={"text": "if Ball is Near then\nif Ball Near then Dash Low"})
    assert response.status_code == 422
    assert [e["line"] for e in response.json()["errors"]] == [1, 2]


def test_evaluate_gives_premise_degrees_fired_and_selected_actions(client):
    # NEAR is (2, 4, 8): at 3 m its degree is 0.5; HIGH (70, 85, 100) clipped at 0.5 keeps
    # [77.5, 92.5] at the top, whose mean is 85.
    body = {"text": TWO_RULES, "inputs": {"ball_distance": 3.0, "ball_direction": 0.0}}
    result = client.post("/api/rules/evaluate", json=body).json()
    assert result["visible"] == ["BALL"]
    assert result["rules"][0]["premise_degrees"] == [0.5] and result["rules"][0]["strength"] == 0.5
    assert result["rules"][1]["premise_degrees"] == [0.0, 0.0]  # the goal is out of view
    assert result["fired"] == [{"action": "DASH", "support": 0.5, "parameters": {"power": 85.0}}]
    assert result["selected"] == result["fired"][0]


def test_evaluate_with_nothing_in_view_selects_no_action(client):
    result = client.post("/api/rules/evaluate", json={"text": NEAR_DASH, "inputs": {}}).json()
    assert result["visible"] == [] and result["fired"] == [] and result["selected"] is None


def test_evaluate_a_saved_rulebase(client):
    saved = client.post("/api/rulebases", json={"name": "near", "text": NEAR_DASH}).json()
    body = {"rulebase_id": saved["id"], "inputs": {"ball_distance": 4.0, "ball_direction": 10.0}}
    assert client.post("/api/rules/evaluate", json=body).json()["selected"]["support"] == 1.0
    assert client.post("/api/rules/evaluate", json={**body, "rulebase_id": 999}).status_code == 404


@pytest.mark.parametrize(
    "body, message",
    [
        ({"inputs": {}}, "exactly one of 'text' and 'rulebase_id'"),
        ({"text": NEAR_DASH, "rulebase_id": 1}, "exactly one of 'text' and 'rulebase_id'"),
        ({"text": NEAR_DASH, "inputs": {"ball_distance": -1}}, "inputs.ball_distance"),
        ({"text": NEAR_DASH, "inputs": {"ball_direction": 181}}, "inputs.ball_direction"),
        ({"text": NEAR_DASH, "inputs": {"ball_distance": "near"}}, "inputs.ball_distance"),
        ({"text": NEAR_DASH, "inputs": {"ball_speed": 1}}, "inputs.ball_speed"),
    ],
)
def test_evaluate_refuses_bad_bodies(client, body, message):
    response = client.post("/api/rules/evaluate", json=body)
    assert response.status_code == 422 and message in response.json()["detail"]


def test_malformed_json_is_a_400_saying_so(client):
    response = client.post("/api/rulebases", content=b'{"name": "x", "text": ', headers={"content-type": "application/json"})
    assert response.status_code == 400 and response.json()["detail"].startswith("malformed JSON")


def test_huge_payloads_are_refused_with_413(client):
    huge = "#" * 1_100_000
    declared = client.post("/api/rules/parse", json={"text": huge})
    assert declared.status_code == 413 and "larger than" in declared.json()["detail"]

    def chunks():  # no Content-Length: counted as it streams
        for _ in range(12):
            yield b" " * 100_000

    streamed = client.post("/api/rules/parse", content=chunks(), headers={"content-type": "application/json"})
    assert streamed.status_code == 413
    assert client.get("/api/rulebases").status_code == 200


@pytest.mark.parametrize("bad_id, status", [("abc", 422), ("0", 422), ("-3", 422), ("9" * 30, 422), ("424242", 404)])
def test_bad_ids_are_4xx(client, bad_id, status):
    for path in (f"/api/rulebases/{bad_id}", f"/api/runs/{bad_id}", f"/api/runs/{bad_id}/best"):
        assert client.get(path).status_code == status, path
