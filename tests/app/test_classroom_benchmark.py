"""benchmarks/classroom.py's pupils against a real `soccer-lab serve --class`: a protocol tab opens the class's
pitch link, and a game that ends (it stays ended until its pupil starts the next: app/web/ui/session.py) is
restarted by the pupil's "New random start", the message a browser sends for the click. Without it the
benchmark's ticks per second fell to 0 once each session's first game ended."""

from __future__ import annotations

import asyncio
import importlib.util
import math
import sys
from pathlib import Path

import httpx
import pytest

from soccer_lab.app.web.classroom.address import lan_address
from soccer_lab.app.web.pitch_link import decode_link
from soccer_lab.app.web.ui import style
from soccer_lab.soccer.config import MAX_TICKS, GameConfig

ROOT = Path(__file__).resolve().parents[2]
SHORT_GAME = {"max_ticks": 40, "idle_ticks": 40, "goal_cap": 40}  # 2 s at the UI's speed
RESTARTS = 2
WAIT_S = 300.0  # serve's sessions on a shared, busy machine


def load(path: Path, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # its dataclasses look their module up while it loads
    spec.loader.exec_module(module)
    return module


sys.path.insert(0, str(ROOT / "benchmarks"))  # classroom.py imports its sibling results.py
classroom = load(ROOT / "benchmarks" / "classroom.py", "classroom_benchmark")


def test_class_link_plays_the_demo_in_games_that_outlast_the_lesson():
    link = decode_link(classroom.class_link())
    game = link.game_config(GameConfig())
    assert (link.seed, link.speed, link.tick, link.paused) == (style.DEFAULT_SEED, style.DEFAULT_SPEED, 0, False)
    # only the tick limit ends a game, at its largest: over 8 minutes at the UI's 20 ticks a second
    assert game.max_ticks == MAX_TICKS and game.idle_ticks >= game.max_ticks and game.goal_cap >= game.max_ticks
    assert game.max_ticks / (style.DEFAULT_SPEED / game.world.tick_seconds) > 8 * 60


async def one_pupil(served) -> object:
    """One student joins and opens the class's link in a protocol tab; its pupil presses the next start after
    each game's end, until RESTARTS games have been restarted and the next one plays."""
    ending = asyncio.Event()
    connections: list = []
    async with httpx.AsyncClient(base_url=served.url, timeout=120) as client:
        joined = await client.post("/api/class/join", json={"code": classroom.CODE, "name": "Pupil"})
        assert joined.is_success, joined.text
        tab = classroom.Tab("protocol", "Pupil")
        tasks = [asyncio.create_task(classroom.protocol_tab(tab, served, classroom.cookie_header(client),
                                                            classroom.class_link(), connections, ending)),
                 asyncio.create_task(classroom.press_next_games([tab], ending))]
        def playing_again() -> bool:
            return tab.next_games >= RESTARTS and tab.ticks[-1][1] > 0 and not tab.ticks[-1][2]

        await classroom.wait_until(lambda: playing_again() or tab.closed is not None, WAIT_S)
        ending.set()
        for connection in connections:
            await connection.close()
        await asyncio.gather(*tasks, return_exceptions=True)
    return tab


def test_ended_game_is_restarted_by_its_pupil(tmp_path, monkeypatch):
    if lan_address().startswith("127."):
        pytest.skip("this machine has no network address besides 127.0.0.1 (classroom mode serves a local network)")
    monkeypatch.setattr(classroom, "LONG_GAME", SHORT_GAME)
    served = classroom.Served(tmp_path, lan_address())
    try:
        tab = asyncio.run(one_pupil(served))
    finally:
        served.stop()
    assert tab.closed is None and not tab.link_refused
    assert tab.next_games >= RESTARTS
    assert classroom.games_ended(tab, 0.0, math.inf) >= RESTARTS
    ended_at = [index for index, (_, _, done) in enumerate(tab.ticks) if done]
    # every end came at the link's tick limit (the link's game, not the demo's), and a new game followed it
    assert all(tab.ticks[index][1] == SHORT_GAME["max_ticks"] for index in ended_at)
    assert all(index + 1 < len(tab.ticks) and not tab.ticks[index + 1][2] for index in ended_at[:RESTARTS])
    # the pupil read each end READ_THE_END_S before pressing: the next game's first tick came no sooner
    for index in ended_at[:RESTARTS]:
        assert tab.ticks[index + 1][0] - tab.ticks[index][0] >= classroom.READ_THE_END_S
