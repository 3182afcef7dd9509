"""Many tabs share the server's drawing (app/web/ui/frame_share.py): past ALL_TABS_FRAME_RATE frames a second in
all, each tab draws fewer frames and plays several ticks a frame, so its game keeps its speed. The figures
for a class of 30 tabs are benchmarks/classroom.py's."""

from __future__ import annotations

import asyncio
import re
import time

import msgspec
import pytest
import viser
import websockets
import zstandard

from soccer_lab.app.paths import DATABASE_FILE
from soccer_lab.app.runs.manager import RunManager
from soccer_lab.app.store import Store
from soccer_lab.app.web.ui.frame_share import FrameShare
from tests.app.test_security import free_port

TICK = re.compile(rb'data-tick="(\d+)"')
SECONDS = 5.0  # of play watched
TAB_FRAMES = 3.0  # each tab's share of frames a second
# What a browser sends on connecting (viser's camera controls): viser builds a session only then
CAMERA = {"type": "ViewerCameraMessage", "wxyz": [1.0, 0.0, 0.0, 0.0], "position": [0.0, 0.0, -60.0],
          "image_height": 900, "image_width": 1200, "fov": 0.87, "near": 0.01, "far": 1000.0,
          "look_at": [0.0, 0.0, 0.0], "up_direction": [0.0, -1.0, 0.0]}


def message_text(message: bytes) -> bytes:
    """viser's message: 8 bytes of size, 8 of compressed size, then zstd-compressed msgpack."""
    compressed = int.from_bytes(message[8:16], "little")
    return zstandard.ZstdDecompressor().decompress(message[16:16 + compressed])


def test_each_tab_draws_its_share_and_never_more_than_the_frame_rate():
    share = FrameShare(total=100, most=30)
    assert share.rate == 30  # no tab counted yet: one
    share.tabs = 3
    assert share.rate == 30
    share.tabs = 30
    assert share.rate == pytest.approx(100 / 30)


@pytest.fixture
def ui(tmp_path):
    from soccer_lab.app.web.ui import start_ui

    store = Store(tmp_path / DATABASE_FILE)
    runs = RunManager(store, tmp_path)
    page_port = free_port()
    handle = start_ui(store, runs, port=free_port(), page_port=page_port)
    yield handle, page_port
    handle.stop()
    runs.shutdown()
    store.close()


async def ticks_seen(url: str, origin: str, seconds: float, handle) -> tuple[list[int], int]:
    """The tick counter's values one tab received in `seconds` of play, and the tabs the server counted."""
    seen: list[int] = []
    async with websockets.connect(url, origin=origin, subprotocols=[f"viser-v{viser.__version__}"],
                                  open_timeout=60, max_size=None) as connection:
        await connection.send(msgspec.msgpack.encode(CAMERA))
        while len(handle.sessions) < 2 or not all(s.ready.is_set() for s in handle.sessions.values()):
            await connection.recv()
        for session in list(handle.sessions.values()):
            session.controls.speed.value = 1.0  # 10 ticks a second: one a frame at the full frame rate
        counting = time.monotonic() + 1.0  # the new speed has reached the loop
        deadline = counting + seconds
        counted = 0
        while time.monotonic() < deadline:
            try:
                message = await asyncio.wait_for(connection.recv(), max(0.01, deadline - time.monotonic()))
            except asyncio.TimeoutError:
                break
            if time.monotonic() >= counting:
                seen += [int(tick) for tick in TICK.findall(message_text(message))]
            counted = max(counted, handle.context.frames.tabs)
    return seen, counted


def test_a_tab_with_a_small_share_plays_several_ticks_a_frame(ui):
    handle, page_port = ui
    handle.context.frames.total = 2 * TAB_FRAMES  # two tabs, each its share: the game plays 10 ticks a second
    url, origin = f"ws://127.0.0.1:{handle.server.get_port()}", f"http://127.0.0.1:{page_port}"

    async def two_tabs():
        return await asyncio.gather(*(ticks_seen(url, origin, SECONDS, handle) for _ in range(2)))

    for seen, counted in asyncio.run(two_tabs()):
        assert counted == 2
        assert seen and seen[-1] > seen[0], seen  # the game went on
        # At most its share of frames (a busy machine draws fewer still); at the full frame rate the tab
        # would get all 20 ticks a second, one a frame
        frames = len(set(seen))
        assert frames <= 1.5 * TAB_FRAMES * SECONDS + 2, seen
    deadline = time.monotonic() + 30
    while handle.context.frames.tabs and time.monotonic() < deadline:
        time.sleep(0.05)
    assert handle.context.frames.tabs == 0  # closed tabs give their share back
