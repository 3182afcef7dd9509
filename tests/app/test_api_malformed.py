"""A malformed-input corpus against every route of the OpenAPI document: always a 4xx (or a
success), never a 500, and nothing saved is lost."""

from __future__ import annotations

import json

import pytest

from tests.app.api_client import api_client

PATH_VALUES = ["1", "0", "-1", "abc", "1.5", "9" * 40, "%00", "1;DROP TABLE runs", "424242"]
BODIES: list[bytes] = [
    b"",
    b"{",
    b"not json",
    b"null",
    b"[]",
    b"{}",
    b'"text"',
    b"12",
    b'{"name": null, "text": null}',
    b'{"name": 5, "text": ["a"]}',
    b'{"text": "if Ball is then"}',
    b'{"text": "if Ball is Near then Dash High", "inputs": {"ball_distance": NaN}}',
    b'{"text": "if Ball is Near then Dash High", "inputs": {"ball_distance": 1e999}}',
    b'{"rulebase_id": 99999999999999999999999, "inputs": {}}',
    b'{"ga": {"population_size": -5}, "game": {"max_ticks": "long"}}',
    b'{"ga": {"seed": 1e300}}',
    b'{"ga": "fast"}',
    b"\xff\xfe\x00garbage",
    json.dumps({"name": "x" * 5000, "text": ""}).encode(),
    b"[" * 5000 + b"]" * 5000,
]


@pytest.fixture(scope="module")
def client(tmp_path_factory):
    # No run may start (the limit is 0): a body that happens to be valid gets a 409, not a long run.
    with api_client(tmp_path_factory.mktemp("data"), max_concurrent_runs=0) as opened:
        yield opened


def operations(client):
    for path, methods in client.get("/openapi.json").json()["paths"].items():
        for method in methods:
            yield path, method.upper()


def concrete(path: str, value: str) -> str:
    while "{" in path:
        start, end = path.index("{"), path.index("}")
        path = path[:start] + value + path[end + 1 :]
    return path


def test_every_route_answers_every_malformed_input_with_a_4xx(client):
    rule = {"name": "kept", "text": "if Ball is At then Kick Straight High"}
    client.post("/api/rulebases", json=rule)  # id 1: the corpus may delete it (DELETE /api/rulebases/1)
    kept = client.post("/api/rulebases", json=rule).json()  # id 2: no request names it
    checked = 0
    for path, method in operations(client):
        for value in PATH_VALUES:
            url = concrete(path, value)
            bodies = BODIES if method in ("POST", "PUT", "PATCH") else [b""]
            for body in bodies:
                response = client.request(method, url, content=body, headers={"content-type": "application/json"})
                assert response.status_code < 500, (method, url, body[:60], response.text[:200])
                if response.status_code >= 400:
                    assert response.json()["detail"], (method, url, body[:60])
                checked += 1
    assert checked > 500
    assert client.get(f"/api/rulebases/{kept['id']}").json() == kept


@pytest.mark.parametrize("content_type", ["text/plain", "application/x-www-form-urlencoded", "multipart/form-data"])
def test_wrong_content_types_are_4xx(client, content_type):
    response = client.post("/api/rules/parse", content=b"text=if", headers={"content-type": content_type})
    assert 400 <= response.status_code < 500
