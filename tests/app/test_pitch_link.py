"""A link that reproduces a pitch (issue 26): what it carries comes back as it was, the game it opens is
the same game bit for bit at the same tick (game rules that differ from the app's included), and a damaged,
tampered or oversized link gives one line saying why, never a broken page."""

from __future__ import annotations

import base64
import json
import zlib

import pytest
from fastapi.testclient import TestClient

from soccer_lab.app.web.api import create_app
from soccer_lab.app.paths import DATABASE_FILE
from soccer_lab.app.web.pitch_link import MAX_TOKEN_LENGTH, LinkError, PitchLink, decode_link
from soccer_lab.app.runs.manager import RunManager
from soccer_lab.app.store import Store
from soccer_lab.app.web.ui.context import UiContext
from soccer_lab.app.web.ui.game import Game
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.printer import format_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.demo import demo_rules_text

VOCABULARY = Vocabulary.default()
APP_GAME = GameConfig()
CONTEXT = UiContext(store=None, runs=None, vocabulary=VOCABULARY, game=APP_GAME)


def token_of(state: dict) -> str:
    packed = zlib.compress(json.dumps(state).encode())
    return base64.urlsafe_b64encode(packed).rstrip(b"=").decode()


def opened(token: str) -> Game:
    """What a tab opened with the link plays (app/web/ui/session.py, Session._open_link)."""
    link = decode_link(token)
    game = Game(CONTEXT, link.rulebase(VOCABULARY), link.name, link.seed, link.game_config(APP_GAME))
    while game.state.tick < link.tick and not game.done:
        game.step()
    return game


def test_a_link_carries_the_pitch_back_as_it_was():
    game = APP_GAME.model_copy(update={"skills": "strict", "max_ticks": 900, "noise": True})
    link = PitchLink.of(demo_rules_text(), "Ada's « player »", 12345, 77, 3.5, True, game, APP_GAME)
    assert link.game == {"skills": "strict", "max_ticks": 900, "noise": True}  # only what differs
    token = link.token()
    assert len(token) < 2000 and token.isascii()
    assert decode_link(token) == link
    assert link.game_config(APP_GAME) == game


@pytest.mark.parametrize("update", [{}, {"skills": "assisted", "noise": True}])
def test_the_linked_game_is_the_same_game_bit_for_bit(update):
    config = APP_GAME.model_copy(update=update)
    rulebase = parse_rulebase(demo_rules_text(), VOCABULARY)
    original = Game(CONTEXT, rulebase, "demo", 7, config)
    for _ in range(150):
        original.step()
    link = PitchLink.of(format_rulebase(rulebase, VOCABULARY), "demo", 7, int(original.state.tick), 2.0, True,
                        config, APP_GAME)
    copy = opened(link.token())
    assert copy.state.tick == original.state.tick == 150
    for field in ("player", "ball", "facing", "inputs", "strengths", "action"):
        assert getattr(copy.state, field) == getattr(original.state, field), field
    for _ in range(50):  # and they go on alike
        original.step(), copy.step()
    assert copy.state.ball == original.state.ball and copy.state.player == original.state.player


def test_damaged_and_tampered_links_say_why_in_one_line():
    good = PitchLink.of(demo_rules_text(), "demo", 1, 0, 1.0, False, APP_GAME, APP_GAME).token()
    cases = {
        good[:-10]: "damaged",
        good[:40] + ("A" if good[40] != "A" else "B") + good[41:]: "damaged",
        good + "<script>": "characters a soccer-lab link never has",
        "A" * (MAX_TOKEN_LENGTH + 1): "longer than",
        base64.urlsafe_b64encode(zlib.compress(b" " * 2_000_000, 9)).decode().rstrip("="): "too large",
        token_of({"v": 2}): "another version",
        token_of({"v": 1, "r": "if Ball is Sideways then Kick", "n": "x", "s": 1, "t": 0, "x": 1, "p": 0, "g": {}}):
            None,  # decodes; its rules fail when opened
        token_of({"v": 1, "r": "", "n": "a\u202eb", "s": 1, "t": 0, "x": 1, "p": 0, "g": {}}): "not plain text",
        token_of({"v": 1, "r": "", "n": "x", "s": -1, "t": 0, "x": 1, "p": 0, "g": {}}): "seed",
        token_of({"v": 1, "r": "", "n": "x", "s": 1, "t": 10**9, "x": 1, "p": 0, "g": {}}): "tick",
        token_of({"v": 1, "r": "", "n": "x", "s": 1, "t": 0, "x": 1e9, "p": 0, "g": {}}): "speed",
        token_of({"v": 1, "r": "", "n": "x", "s": 1, "t": 0, "x": 1, "p": 0, "g": {"world": {}}}): "game rules",
    }
    for token, reason in cases.items():
        if reason is None:
            with pytest.raises(LinkError, match="do not parse"):
                opened(token)
            continue
        with pytest.raises(LinkError, match=reason) as refused:
            decode_link(token)
        assert "\n" not in str(refused.value)
    bad_game = token_of({"v": 1, "r": demo_rules_text(), "n": "x", "s": 1, "t": 0, "x": 1, "p": 0,
                         "g": {"max_ticks": -5}})
    with pytest.raises(LinkError, match="game rules are not valid"):
        opened(bad_game)


def test_a_bad_link_in_the_address_bar_answers_one_line_not_a_broken_page(tmp_path):
    store = Store(tmp_path / DATABASE_FILE)
    runs = RunManager(store, tmp_path)
    app = create_app(store, runs, ui_websocket="ws://127.0.0.1:8080")
    try:
        with TestClient(app, base_url="http://127.0.0.1:8000", follow_redirects=False) as client:
            page = client.get("/ui/?pitch=%3Cscript%3Ealert(1)%3C/script%3E")
            assert page.status_code == 400 and page.headers["content-type"].startswith("text/html")
            assert "This link could not be opened" in page.text and "<script>alert" not in page.text
            good = PitchLink.of(demo_rules_text(), "demo", 1, 0, 1.0, False, APP_GAME, APP_GAME).token()
            passed = client.get(f"/ui/?pitch={good}")
            assert passed.status_code == 307
            assert f"pitch={good}" in passed.headers["location"]  # on to the UI's websocket, whose hook opens it
    finally:
        runs.shutdown()
        store.close()
