"""Names are one line of plain text (issue 25): control characters (NUL, ESC, CR, LF, TAB...) and
bidirectional overrides are refused with a message naming the character, in every place a name is given."""

from __future__ import annotations

import re

import pytest

from soccer_lab.app.paths import DATABASE_FILE
from soccer_lab.app.store import Store, StoreError
from tests.app.api_client import api_client

TEXT = "if Ball is At then Kick Straight High"
BAD = [("nul\x00", "U+0000", "control"), ("esc\x1b[31m", "U+001B", "control"), ("two\r\nlines", "U+000D", "control"),
       ("tab\there", "U+0009", "control"), ("abc\u202efdp.exe", "U+202E", "bidirectional"),
       ("\u2066isolate", "U+2066", "bidirectional"), ("mark\u200f", "U+200F", "bidirectional")]


@pytest.mark.parametrize("name, code, kind", BAD)
def test_the_api_refuses_control_and_bidi_characters_in_names(tmp_path, name, code, kind):
    with api_client(tmp_path) as client:
        response = client.post("/api/rulebases", json={"name": name, "text": TEXT})
        assert response.status_code == 422
        assert code in response.json()["detail"] and kind in response.json()["detail"]
        run = client.post("/api/runs", json={"name": name, "ga": {"population_size": 4, "max_generations": 1}})
        assert run.status_code == 422 and code in run.json()["detail"]
        assert client.get("/api/rulebases").json() == [] and client.get("/api/runs").json() == []


def test_the_store_refuses_them_on_every_write_and_keeps_plain_text(tmp_path):
    store = Store(tmp_path / DATABASE_FILE)
    try:
        kept = store.create_rulebase("Stürmer 日本 ⚽ (v2)", TEXT)
        assert kept.name == "Stürmer 日本 ⚽ (v2)"
        for name, code, _ in BAD:
            with pytest.raises(StoreError, match=re.escape(code)):
                store.update_rulebase(kept.id, name=name)
            with pytest.raises(StoreError, match=re.escape(code)):
                store.create_rulebase(name, TEXT)
        assert store.get_rulebase(kept.id).name == "Stürmer 日本 ⚽ (v2)"
    finally:
        store.close()
