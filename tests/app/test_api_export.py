"""GET /api/rulebases/{id}/export: the CLI's export formats as downloads."""

from __future__ import annotations

import pytest

from soccer_lab.app.paths import DATABASE_FILE
from soccer_lab.app.store import Store
from soccer_lab.fuzzy.export import FORMATS, export_rulebase, rulebase_from_json
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from tests.app.api_client import api_client

VOCABULARY = Vocabulary.default()
TEXT = "if Ball is Near or Ball is not Far then Kick SlightlyRight High\nif Goal is Left then Turn Left\n"
MEDIA_TYPES = {"json": "application/json", "fcl": "text/plain", "fll": "text/plain", "fis": "text/plain"}


@pytest.fixture
def client(tmp_path):
    with api_client(tmp_path) as opened:
        yield opened


@pytest.mark.parametrize("fmt", FORMATS)
def test_export_downloads_what_the_cli_writes(client, fmt):
    saved = client.post("/api/rulebases", json={"name": "my striker", "text": TEXT}).json()
    response = client.get(f"/api/rulebases/{saved['id']}/export", params={"format": fmt})
    assert response.status_code == 200
    assert response.headers["content-type"].split(";")[0] == MEDIA_TYPES[fmt]
    assert response.headers["content-disposition"] == f'attachment; filename="my_striker.{fmt}"'
    assert response.text == export_rulebase(parse_rulebase(TEXT, VOCABULARY), fmt, VOCABULARY)
    if fmt == "json":
        assert rulebase_from_json(response.text)[0] == parse_rulebase(TEXT, VOCABULARY)


def test_export_file_names_keep_only_safe_characters(client):
    saved = client.post("/api/rulebases", json={"name": "../best \"run\" #3", "text": TEXT}).json()
    response = client.get(f"/api/rulebases/{saved['id']}/export", params={"format": "fcl"})
    assert response.headers["content-disposition"] == 'attachment; filename="best_run_3.fcl"'


@pytest.mark.parametrize("query, status, message", [
    ({"format": "xml"}, 422, "format: Input should be 'json', 'fcl', 'fll' or 'fis'"),
    ({}, 422, "format: Field required"),
])
def test_export_refuses_an_unknown_format(client, query, status, message):
    saved = client.post("/api/rulebases", json={"name": "a", "text": TEXT}).json()
    response = client.get(f"/api/rulebases/{saved['id']}/export", params=query)
    assert response.status_code == status and message in response.json()["detail"]


def test_export_of_a_missing_rulebase_is_404(client):
    response = client.get("/api/rulebases/999/export", params={"format": "fis"})
    assert response.status_code == 404 and response.json()["detail"] == "no rulebase with id 999"
    assert client.get("/api/rulebases/0/export", params={"format": "fis"}).status_code == 422


def test_export_of_a_stored_text_that_no_longer_parses_is_422(client, tmp_path):
    """Text saved before a vocabulary change may not parse now: a 422 naming the line, never a 500."""
    store = Store(tmp_path / DATABASE_FILE)
    record = store.create_rulebase("old", "if Ball is Nearish then Kick High\n")
    store.close()
    response = client.get(f"/api/rulebases/{record.id}/export", params={"format": "fll"})
    assert response.status_code == 422 and "line 1" in response.json()["detail"]
