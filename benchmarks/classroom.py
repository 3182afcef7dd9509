"""A class on this machine: every student's session open and playing while the teacher's round plays. Does
every session keep playing (the ticks per second each tab receives), does the round's table appear within
10 s, does any request fail?

A real `soccer-lab serve --class` is started (its own process; the machine's network address, as a class
meets it; a fixed join code; an empty data folder) and its printed teacher token read. STUDENTS students
join (POST /api/class/join, each its own cookies and name). All of them join from this one machine's
address, whose join attempts the class's rate limit counts ten requests each (app/web/api/guard.py: about one a
second): the joins are paced to stay within it, so none is refused. Then every student opens one tab of
the UI at the pitch link the teacher gives the class (`/ui/?pitch=TOKEN`, app/web/pitch_link.py: the UI's demo
player from the UI's first seed at the UI's speed, 2x real time, 20 ticks a second, in games that neither an
idle spell nor the goal cap ends, only GameConfig's largest tick limit, 10,000 ticks: over 8 minutes), each
its own viser session playing its own game. A game that ends stays ended until its pupil starts the next
(app/web/ui/session.py), so when one does (in the queue's long scenario) its pupil reads the end for 2 s and
presses "New random start", as a pupil would:

- BROWSER_TABS tabs are real headless Chromium (the flags of benchmarks/ui_browser.py, software WebGL, one
  window each), the student's cookies set on the browser context; a script in the page records each new
  value of the Play tab's tick counter (`.game-status[data-tick]`, watched by a MutationObserver) and the
  moment the round's table (`.class-table[data-round]`, the Class tab's) enters the page; it is read
  every second. Once playing, each page shows its Class tab and then its Play tab again: viser puts a
  tab's panel in the page when it is first shown (and keeps it), so the table enters the page when the
  server sends it;
- the rest are protocol-level clients: a `websockets` connection to the UI's port with the student's
  cookies, the app's own Origin and viser's subprotocol, which sends the camera message a browser sends on
  connecting (viser builds a session only then) and reads every message. viser's messages are zstd-
  compressed msgpack (8 bytes of size, 8 of compressed size, the zstd frame): each is decompressed and
  the tick counter's HTML (`data-tick="N" ... data-done=...`) and the round's table (`class-table"
  data-round="N"`) found in its UTF-8 text; "New random start" is pressed with the message a browser sends
  for the click (viser's GuiUpdateMessage to the button group the Play tab's creation named). A protocol
  client draws nothing: it costs the server what a browser costs it, and this machine far less than a
  Chromium tab.

One protocol session is first measured alone (the reference: what one tab receives on an idle server).
Once all are playing, every student submits an entry (POST /api/class/entries: the examples of
soccer/data/examples/ with their rules in a different order, most with a rule of another example added),
one after another. The sessions are measured for SECONDS (before the round); then the teacher starts a
round (POST /api/class/rounds, STARTS starts): measured are the seconds from that request to the round's
table in GET /api/class/rounds (one student polls it four times a second) and in every session (pushed by
the server), and each session's ticks while the round plays (from the request to the table in the API) and
in the SECONDS after the request.

Then the queue (issue 35): every student presses Start in the same second (POST /api/runs, each with their own
cookies) with the UI's default pupil run (the Evolve tab's defaults: the chapter's 200 x 25, one game per
evaluation, games of at most 1,000 ticks; a pupil's run plays in one process). No Start may be refused: the
runs the cores cannot take yet are queued and start in turn. The teacher polls GET /api/runs four times a
second: each pupil's wait (Start to running), run time (running to finished) and the time until the last
run finishes, against the target 1.3 x (the sum of the run times / the runs that play at once, as serve
prints them); each session's ticks per second while the queue plays; the estimate each pupil was given at
Start against their real wait.

Ticks per second: the game's progress each tab saw (the counter's advance; a new game counts from 0),
over the window, the 2 s a pupil reads a game's end included; the games that ended in each window are
counted (the lesson's windows are shorter than a game), so a session alone receives the UI's speed, 20. A
stall: the longest time a session received no new tick while its game was on (not while its ended game
waited for the next start). Failed requests: every HTTP request this script made (joins, entries, the
round, the polling), every response with status 400 or more and every failed request of the browser pages,
every websocket that closed before the end, every tab that did not open the class's link (target: none).
CPU: cores busy in each window, of `serve`, of Chromium (and Playwright's driver), of this script, and of
the whole machine (2 cores: more than 2 means waiting for a core).

    python benchmarks/classroom.py [--students 30] [--browser-tabs 3] [--starts 20] [--seconds 20] [--no-queue]
        [--record]
"""

from __future__ import annotations

import argparse
import asyncio
import math
import queue
import random
import re
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import httpx
import psutil
import viser
import websockets
import zstandard

from results import Figure, add_record_option, load_average, record, this_command

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
CODE = "BENCH7"
CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]
VIEWPORT = {"width": 1600, "height": 900}
START_TIMEOUT_S = 900.0  # serve's start on a busy machine (the tests wait as long)
PLAYING_TIMEOUT_S = 300.0  # every session playing
TABLE_TIMEOUT_S = 300.0  # the round's table in every session
ALONE_S = 10.0  # the one session measured alone
SETTLE_S = 3.0  # after the entries, before the window before the round
POLL_ROUNDS_S = 0.25  # the polling student: 4 requests a second (the class's rate: 10 each)
READ_PAGES_S = 1.0
JOIN_COST, ADDRESS_RATE, ADDRESS_BURST = 10, 10.0, 60.0  # app/classroom: admission.py, settings.py
TABLE_TARGET_S = 10.0
QUEUE_WINDOW = "while the queue plays"
RECORDED_WINDOWS = ("before the round", "while the round plays", QUEUE_WINDOW)  # with --record (all are printed)
PUPIL_RUN: dict = {}  # the Evolve tab's defaults are the API's: GAConfig's and GameConfig's (workers: one, bounded)
POLL_RUNS_S = 0.25  # the teacher's poll of GET /api/runs while the queue plays
QUEUE_TIMEOUT_S = 3600.0
QUEUE_TARGET = 1.3  # the last finish within 1.3 x (the sum of the runs' own times / the runs at once)
ENDED = {"finished", "failed", "stopped", "interrupted"}
# Every tab opens the teacher's pitch link (app/web/pitch_link.py): the demo player at the UI's speed, in games that
# neither an idle spell nor goals end: only the tick limit, 10,000 ticks (GameConfig's largest), over 8 minutes.
LONG_GAME = {"max_ticks": 10_000, "idle_ticks": 10_000, "goal_cap": 10_000}
# A game that ends stays ended (app/web/ui/session.py): its pupil reads the end, then presses the next start.
NEXT_GAME = "New random start"
READ_THE_END_S = 2.0
TICK = re.compile(rb'data-tick="(\d+)"[^>]*?data-done="(true|false)"')
TABLE = re.compile(rb'class="class-table" data-round="(\d+)"')
# What a browser sends on connecting (viser's CameraControls): a session is built once it arrives.
CAMERA = {"type": "ViewerCameraMessage", "wxyz": [1.0, 0.0, 0.0, 0.0], "position": [0.0, 0.0, -60.0],
          "image_height": 900, "image_width": 1200, "fov": 0.87, "near": 0.01, "far": 1000.0,
          "look_at": [0.0, 0.0, 0.0], "up_direction": [0.0, -1.0, 0.0]}
# In every page: each new value of the tick counter, and when the round's table came (wall-clock ms).
WATCH_PAGE = """
(() => {
  const watch = window.__classWatch = {ticks: [], table: null, last: null};
  const now = () => performance.timeOrigin + performance.now();
  const look = () => {
    const status = document.querySelector(".game-status[data-tick]");
    if (status) {
      const key = status.dataset.tick + "/" + status.dataset.done;
      if (key !== watch.last) {
        watch.last = key;
        watch.ticks.push([now(), Number(status.dataset.tick), status.dataset.done === "true"]);
      }
    }
    if (watch.table === null) {
      const table = document.querySelector(".class-table[data-round]");
      if (table) watch.table = [now(), Number(table.dataset.round)];
    }
  };
  new MutationObserver(look).observe(document, {subtree: true, childList: true, attributes: true,
                                                attributeFilter: ["data-tick", "data-done", "data-round"]});
})();
"""
READ_WATCH = """() => { const w = window.__classWatch;
  return w ? {ticks: w.ticks.splice(0), table: w.table, refused: !!document.querySelector(".link-notice")} : null; }"""


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


class Served:
    """`soccer-lab serve --class` in its own process on the machine's network address; its printed lines."""

    def __init__(self, folder: Path, address: str):
        self.port, self.ui_port = free_port(), free_port()
        command = [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "serve", "--class", "--host", address,
                   "--join-code", CODE, "--data-dir", str(folder), "--port", str(self.port),
                   "--ui-port", str(self.ui_port)]
        self.process = subprocess.Popen(command, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                        text=True)
        self.lines: queue.Queue[str] = queue.Queue()
        self.printed: list[str] = []
        threading.Thread(target=self._read, daemon=True).start()
        self.teacher_token = self._wait_for(r"teacher token\s+(\S+)").group(1)
        self._wait_for(r"  data ")
        self.runs_at_once = int(self._wait_for(r"  runs\s+(\d+) at once").group(1))
        self.url = f"http://{address}:{self.port}"
        self.ws_url = f"ws://{address}:{self.ui_port}"

    def _read(self) -> None:
        for line in self.process.stdout:
            self.lines.put(line)

    def _wait_for(self, pattern: str) -> re.Match:
        deadline = time.monotonic() + START_TIMEOUT_S
        while time.monotonic() < deadline:
            try:
                line = self.lines.get(timeout=0.5)
            except queue.Empty:
                if self.process.poll() is not None:
                    raise RuntimeError("serve --class ended at start:\n" + "".join(self.printed))
                continue
            self.printed.append(line)
            if match := re.search(pattern, line):
                return match
        raise RuntimeError(f"serve --class never printed {pattern!r}:\n" + "".join(self.printed))

    def later_lines(self) -> list[str]:
        """What serve printed since it started (its warnings and errors)."""
        lines = []
        while True:
            try:
                lines.append(self.lines.get_nowait())
            except queue.Empty:
                return lines

    def stop(self) -> None:
        self.process.send_signal(signal.SIGINT)
        try:
            self.process.wait(30)
        except subprocess.TimeoutExpired:
            self.process.kill()


@dataclass
class Tab:
    """One student's tab: every new tick value it received (wall-clock time, tick, game over), and when the
    round's table came."""

    kind: str  # "browser" or "protocol"
    student: str
    ticks: list[tuple[float, int, bool]] = field(default_factory=list)
    table: float | None = None
    opened: float = 0.0
    closed: str | None = None  # why it closed before the end
    link_refused: bool = False  # the session played the demo instead of the link's pitch
    messages: int = 0
    received: int = 0  # bytes
    next_games: int = 0  # the times its pupil pressed NEXT_GAME
    answered_end: float | None = None  # the game over last answered with NEXT_GAME
    connection: object = None  # a protocol tab's websocket
    next_game_button: str | None = None  # a protocol tab's: the uuid of the Play tab's "Start" buttons

    def saw(self, when: float, tick: int, done: bool) -> None:
        if not self.ticks or self.ticks[-1][1:] != (tick, done):
            self.ticks.append((when, tick, done))

    def next_game_due(self, now: float) -> bool:
        """Whether its game ended READ_THE_END_S ago and its pupil has not pressed NEXT_GAME for it yet (and now
        does: counted)."""
        if not self.ticks or not self.ticks[-1][2]:
            return False
        ended = self.ticks[-1][0]
        if ended == self.answered_end or now - ended < READ_THE_END_S:
            return False
        self.answered_end = ended
        self.next_games += 1
        return True

    def playing_since(self) -> float | None:
        return next((when for when, tick, _ in self.ticks if tick > 0), None)


@dataclass
class Ledger:
    """Every request made and every failure seen."""

    requests: int = 0
    failures: list[str] = field(default_factory=list)

    async def call(self, client: httpx.AsyncClient, method: str, path: str, what: str,
                   **kwargs) -> httpx.Response | None:
        self.requests += 1
        try:
            response = await client.request(method, path, **kwargs)
        except Exception as exc:  # noqa: BLE001 - every failure is counted and shown
            self.failures.append(f"{what}: {type(exc).__name__}: {exc}")
            return None
        if not response.is_success:
            self.failures.append(f"{what}: HTTP {response.status_code} {response.text[:160]}")
        return response


class AddressBucket:
    """This script's copy of the class's rate limit for its one address, so joins wait rather than fail."""

    def __init__(self) -> None:
        self.tokens, self.when = ADDRESS_BURST, time.monotonic()

    async def take(self, cost: float) -> None:
        rate = ADDRESS_RATE * 0.9  # a margin: the server's clock and ours differ a little
        while True:
            now = time.monotonic()
            self.tokens, self.when = min(ADDRESS_BURST, self.tokens + (now - self.when) * rate), now
            if self.tokens >= cost:
                self.tokens -= cost
                return
            await asyncio.sleep((cost - self.tokens) / rate)


def entry_texts(count: int) -> list[str]:
    """`count` valid rulebases: the examples' rules in another order, most with another example's rule."""
    examples = sorted((ROOT / "soccer" / "data" / "examples").glob("*.rules"))
    rules = [[line for line in path.read_text().splitlines() if line.startswith("if ")] for path in examples]
    texts = []
    for index in range(count):
        chosen = random.Random(index)
        own = list(rules[index % len(rules)])
        if index >= len(rules):
            other = [rule for rule in chosen.choice(rules) if rule not in own]
            own += chosen.sample(other, min(1, len(other)))
        chosen.shuffle(own)
        texts.append(f"# student {index + 1}'s player\n" + "\n".join(own) + "\n")
    return texts


def cookie_header(client: httpx.AsyncClient) -> str:
    return "; ".join(f"{name}={value}" for name, value in client.cookies.items())


def class_link() -> str:
    """The token of the pitch link the teacher gives the class: the demo from the UI's first seed, at the UI's
    speed, in LONG_GAME's games."""
    from soccer_lab.app.web.pitch_link import PitchLink
    from soccer_lab.app.web.ui import style
    from soccer_lab.app.web.ui.context import DEMO_NAME
    from soccer_lab.soccer.demo import demo_rules_text

    return PitchLink(demo_rules_text(), DEMO_NAME, style.DEFAULT_SEED, speed=style.DEFAULT_SPEED,
                     game=LONG_GAME).token()


def next_game_button(text: bytes) -> str | None:
    """The uuid of the Play tab's Start button group, when this (decompressed) viser message creates it."""
    import msgspec

    if NEXT_GAME.encode() not in text:
        return None
    for message in msgspec.msgpack.decode(text).get("messages", ()):
        if message.get("type") == "GuiButtonGroupMessage" and NEXT_GAME in message["props"]["options"]:
            return message["uuid"]
    return None


# ---- the sessions ---------------------------------------------------------------------------------
async def protocol_tab(tab: Tab, served: Served, cookies: str, link: str, connections: list,
                       ending: asyncio.Event) -> None:
    import msgspec

    decompressor = zstandard.ZstdDecompressor()
    tab.opened = time.time()
    try:
        # the page at /ui/?pitch=TOKEN opens viser's websocket with the link in its query (app/web/api/ui_page.py)
        async with websockets.connect(f"{served.ws_url}/?pitch={link}", origin=served.url,
                                      additional_headers={"Cookie": cookies},
                                      subprotocols=[f"viser-v{viser.__version__}"], open_timeout=120,
                                      max_size=None) as connection:
            connections.append(connection)
            tab.connection = connection
            await connection.send(msgspec.msgpack.encode(CAMERA))
            async for message in connection:
                now = time.time()
                tab.messages += 1
                tab.received += len(message)
                compressed = int.from_bytes(message[8:16], "little")
                text = decompressor.decompress(message[16:16 + compressed])
                for tick, done in TICK.findall(text):
                    tab.saw(now, int(tick), done == b"true")
                if tab.table is None and TABLE.search(text):
                    tab.table = now
                tab.next_game_button = tab.next_game_button or next_game_button(text)
                tab.link_refused = tab.link_refused or b'class="link-notice"' in text
            if not ending.is_set():
                tab.closed = f"closed by the server ({connection.close_code} {connection.close_reason})"
    except Exception as exc:  # noqa: BLE001 - a session that ends early is a failure, shown
        if not ending.is_set():
            tab.closed = f"{type(exc).__name__}: {exc}"


async def press_next_games(tabs: list[Tab], ending: asyncio.Event) -> None:
    """The protocol clients' pupils: a game that ended READ_THE_END_S ago gets NEXT_GAME pressed (the message a
    browser sends when the button is clicked)."""
    import msgspec

    while not ending.is_set():
        now = time.time()
        for tab in tabs:
            if tab.kind == "protocol" and tab.next_game_button and tab.closed is None and tab.next_game_due(now):
                press = {"type": "GuiUpdateMessage", "uuid": tab.next_game_button, "updates": {"value": NEXT_GAME}}
                try:
                    await tab.connection.send(msgspec.msgpack.encode(press))
                except Exception as exc:  # noqa: BLE001 - a session that cannot be used is a failure, shown
                    tab.closed = f"{NEXT_GAME} could not be pressed: {type(exc).__name__}: {exc}"
        await asyncio.sleep(0.5)


class Browser:
    """The Chromium tabs: one window (context) each, the student's cookies set on it."""

    def __init__(self, playwright, ledger: Ledger, ending: asyncio.Event):
        self.playwright = playwright
        self.ledger = ledger
        self.ending = ending
        self.browser = None
        self.pages: list[tuple[Tab, object]] = []

    async def launch(self) -> None:
        self.browser = await self.playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)

    async def open(self, tab: Tab, served: Served, client: httpx.AsyncClient, link: str) -> None:
        context = await self.browser.new_context(viewport=VIEWPORT)
        await context.add_cookies([{"name": name, "value": value, "url": served.url, "httpOnly": True,
                                    "sameSite": "Strict"} for name, value in client.cookies.items()])
        await context.add_init_script(WATCH_PAGE)
        page = await context.new_page()
        page.set_default_timeout(PLAYING_TIMEOUT_S * 1000)

        def on_response(response) -> None:
            if response.status >= 400:
                self.ledger.failures.append(f"{tab.student}'s page: HTTP {response.status} {response.url}")

        def on_failed(request) -> None:
            if not self.ending.is_set():
                self.ledger.failures.append(f"{tab.student}'s page: {request.url} failed ({request.failure})")

        def on_socket(socket) -> None:
            def closed(_) -> None:
                if not self.ending.is_set():
                    tab.closed = f"the page's websocket closed ({socket.url})"
            socket.on("close", closed)

        page.on("response", on_response)
        page.on("requestfailed", on_failed)
        page.on("websocket", on_socket)
        tab.opened = time.time()
        await page.goto(f"{served.url}/ui/?pitch={link}", wait_until="commit")
        self.pages.append((tab, page))

    async def mount_class_tabs(self) -> None:
        """Visit each page's Class tab once and come back to Play: viser mounts a tab's panel when it is first
        shown (and keeps it), so the round's table then enters the page when the server sends it."""
        for tab, page in self.pages:
            try:
                close = page.locator(".mantine-Notification-closeButton")
                for index in reversed(range(await close.count())):
                    await close.nth(index).click()
                await page.get_by_role("tab", name="Class").click()
                await page.locator(".class-you").wait_for()
                await page.get_by_role("tab", name="Play").click()
                await page.locator(".game-status").wait_for()
            except Exception as exc:  # noqa: BLE001 - counted and shown; the tab's ticks are still measured
                self.ledger.failures.append(f"{tab.student}'s page: its Class tab could not be shown: {exc}")

    async def read(self) -> None:
        for tab, page in self.pages:
            try:
                watch = await page.evaluate(READ_WATCH)
            except Exception as exc:  # noqa: BLE001 - a page that cannot be read is a failure, shown
                if not self.ending.is_set() and tab.closed is None:
                    tab.closed = f"the page could not be read: {exc}"
                continue
            if watch is None:
                continue
            for when, tick, done in watch["ticks"]:
                tab.saw(when / 1000, int(tick), bool(done))
            tab.link_refused = tab.link_refused or watch["refused"]
            if tab.table is None and watch["table"] is not None:
                tab.table = watch["table"][0] / 1000
            if tab.next_game_due(time.time()):
                await self.press_next_game(tab, page)

    async def press_next_game(self, tab: Tab, page) -> None:
        try:
            await page.get_by_role("button", name=NEXT_GAME).click(timeout=30_000)
        except Exception as exc:  # noqa: BLE001 - counted and shown; the tab's ticks are still measured
            self.ledger.failures.append(f"{tab.student}'s page: {NEXT_GAME} could not be pressed: {exc}")

    async def watch(self, ending: asyncio.Event) -> None:
        while not ending.is_set():
            await self.read()
            await asyncio.sleep(READ_PAGES_S)

    async def close(self) -> None:
        if self.browser is not None:
            await self.browser.close()


# ---- the figures --------------------------------------------------------------------------------------
def tick_rate(tab: Tab, start: float, end: float) -> float:
    """Ticks per second the tab saw in [start, end]: the counter's advance, a new game counting from 0."""
    before = [tick for when, tick, _ in tab.ticks if when < start]
    previous = before[-1] if before else None
    advanced = 0
    for when, tick, _ in tab.ticks:
        if start <= when <= end:
            if previous is not None:
                advanced += tick - previous if tick >= previous else tick
            previous = tick
    return advanced / (end - start)


def games_ended(tab: Tab, start: float, end: float) -> int:
    """The games that ended in [start, end] on the tab (each then waited for its pupil's next start)."""
    return sum(1 for (_, _, was_done), (when, _, done) in zip(tab.ticks, tab.ticks[1:])
               if done and not was_done and start <= when <= end)


def longest_stall(tab: Tab, start: float, end: float) -> float:
    """The longest time in [start, end] without a new tick while a game was on."""
    before = [(when, done) for when, _, done in tab.ticks if when < start]
    points = [(start, before[-1][1] if before else False)]
    points += [(when, done) for when, _, done in tab.ticks if start <= when <= end]
    points.append((end, False))
    return max((later - earlier for (earlier, done), (later, _) in zip(points, points[1:]) if not done), default=0.0)


class CpuMeter:
    """CPU seconds so far: serve's (with its game processes), this script's, its other children's (Chromium,
    Playwright's driver), the machine's."""

    def __init__(self, serve_pid: int):
        self.serve = psutil.Process(serve_pid)
        self.me = psutil.Process()

    def sample(self) -> dict[str, object]:
        def used(process: psutil.Process) -> float:
            times = process.cpu_times()
            return times.user + times.system

        def used_all(processes: list[psutil.Process]) -> dict[int, float]:
            seconds = {}
            for process in processes:
                try:
                    seconds[process.pid] = used(process)
                except psutil.Error:  # ended meanwhile
                    pass
            return seconds

        serves = [self.serve, *self.serve.children(recursive=True)]
        children = used_all([child for child in self.me.children(recursive=True)
                             if child.pid not in {process.pid for process in serves}])
        machine = psutil.cpu_times()
        busy = sum(machine) - machine.idle - getattr(machine, "iowait", 0.0)
        return {"when": time.monotonic(), "serve": used_all(serves), "script": used(self.me), "children": children,
                "machine": busy}

    @staticmethod
    def cores(first: dict, last: dict) -> dict[str, float]:
        seconds = last["when"] - first["when"]
        grown = lambda kind: sum(value - first[kind].get(pid, 0.0) for pid, value in last[kind].items())  # noqa: E731
        return {"serve": grown("serve") / seconds, "Chromium": grown("children") / seconds,
                "this script": (last["script"] - first["script"]) / seconds,
                "machine": (last["machine"] - first["machine"]) / seconds}


def spread(values: list[float]) -> tuple[float, float, float]:
    return min(values), statistics.median(values), max(values)


# ---- the class -------------------------------------------------------------------------------------------
async def lesson(served: Served, args: argparse.Namespace) -> dict[str, object]:
    from playwright.async_api import async_playwright

    ledger, ending, bucket = Ledger(), asyncio.Event(), AddressBucket()
    cpu = CpuMeter(served.process.pid)
    result: dict[str, object] = {"ledger": ledger}
    limits = httpx.Limits(max_connections=4)
    clients = [httpx.AsyncClient(base_url=served.url, timeout=120, limits=limits) for _ in range(args.students)]
    teacher = httpx.AsyncClient(base_url=served.url, timeout=120)
    connections: list = []
    tasks: list[asyncio.Task] = []
    playwright = await async_playwright().start()
    browser = Browser(playwright, ledger, ending)
    try:
        # Joining: the teacher, then each student (paced: one address for all)
        started = time.monotonic()
        await bucket.take(JOIN_COST)
        await ledger.call(teacher, "POST", "/api/class/teacher", "teacher sign-in",
                          json={"token": served.teacher_token})
        names = [f"Student {index + 1:02d}" for index in range(args.students)]
        for name, client in zip(names, clients):
            await bucket.take(JOIN_COST)
            await ledger.call(client, "POST", "/api/class/join", f"{name} joins", json={"code": CODE, "name": name})
        result["joined s"] = time.monotonic() - started

        # One protocol session alone: the reference. Every tab opens the teacher's link; the pupils press
        # NEXT_GAME when a game ends
        link = class_link()
        tabs = [Tab("protocol", names[-1])]
        tasks.append(asyncio.create_task(protocol_tab(tabs[0], served, cookie_header(clients[-1]), link,
                                                      connections, ending)))
        tasks.append(asyncio.create_task(press_next_games(tabs, ending)))
        await wait_until(lambda: tabs[0].playing_since() is not None or tabs[0].closed, PLAYING_TIMEOUT_S)
        await asyncio.sleep(2.0)  # its panels built (app/web/ui/session.py: PANELS_AFTER)
        alone_start = time.time()
        await asyncio.sleep(ALONE_S)
        result["alone ticks/s"] = tick_rate(tabs[0], alone_start, time.time())

        # Every other student's tab: Chromium first, then protocol clients
        opening = time.time()
        if args.browser_tabs:
            await browser.launch()
        for index in range(args.students - 1):
            kind = "browser" if index < args.browser_tabs else "protocol"
            tab = Tab(kind, names[index])
            tabs.append(tab)
            if kind == "browser":
                await browser.open(tab, served, clients[index], link)
            else:
                tasks.append(asyncio.create_task(protocol_tab(tab, served, cookie_header(clients[index]), link,
                                                              connections, ending)))
        tasks.append(asyncio.create_task(browser.watch(ending)))
        await wait_until(lambda: all(t.playing_since() is not None or t.closed for t in tabs[1:]), PLAYING_TIMEOUT_S)
        result["all playing s"] = max((t.playing_since() or math.inf) for t in tabs[1:]) - opening
        result["open to playing s"] = {kind: [(t.playing_since() or math.inf) - t.opened for t in tabs[1:]
                                              if t.kind == kind] for kind in ("browser", "protocol")}
        await browser.mount_class_tabs()

        # Every student enters, one after another
        started = time.monotonic()
        for name, client, text in zip(names, clients, entry_texts(args.students)):
            await ledger.call(client, "POST", "/api/class/entries", f"{name}'s entry", json={"text": text})
        result["entries s"] = time.monotonic() - started
        await asyncio.sleep(SETTLE_S)

        # Before the round
        first = cpu.sample()
        before_start = time.time()
        await asyncio.sleep(args.seconds)
        before_end = time.time()
        middle = cpu.sample()

        # The round: the teacher starts it, a student polls for its table, every session is pushed it
        known = await ledger.call(clients[-1], "GET", "/api/class/rounds", "rounds before")
        known_ids = {r["id"] for r in known.json()} if known is not None and known.is_success else set()
        round_start = time.time()
        answer = await ledger.call(teacher, "POST", "/api/class/rounds", "start the round",
                                   json={"starts": args.starts})
        result["round answered s"] = time.time() - round_start
        result["round"] = answer.json() if answer is not None and answer.is_success else None
        api_table = None
        while api_table is None and time.time() - round_start < TABLE_TIMEOUT_S:
            response = await ledger.call(clients[-1], "GET", "/api/class/rounds", "poll the rounds")
            if response is not None and response.is_success and {r["id"] for r in response.json()} - known_ids:
                api_table = time.time()
            else:
                await asyncio.sleep(POLL_ROUNDS_S)
        round_cpu = cpu.sample()
        await wait_until(lambda: all(t.table is not None or t.closed for t in tabs), TABLE_TIMEOUT_S,
                         at_least=round_start + args.seconds - time.time())
        await browser.read()
        after_end = time.time()
        last = cpu.sample()
        result["cpu"] = {"before the round": CpuMeter.cores(first, middle),
                         "while the round plays": CpuMeter.cores(middle, round_cpu),
                         f"{args.seconds:g} s from the round's start": CpuMeter.cores(middle, last)}
        result["api table s"] = api_table - round_start if api_table is not None else math.inf
        result["session table s"] = {kind: [(t.table - round_start) if t.table is not None else math.inf
                                            for t in tabs if t.kind == kind] for kind in ("browser", "protocol")}
        round_end = api_table if api_table is not None else after_end
        windows = {"alone": None,
                   "before the round": (before_start, before_end),
                   "while the round plays": (round_start, round_end),
                   f"{args.seconds:g} s from the round's start": (round_start, round_start + args.seconds)}
        result["windows"] = {name: span for name, span in windows.items() if span is not None}
        result["rates"] = {name: {kind: [tick_rate(t, *span) for t in tabs if t.kind == kind]
                                  for kind in ("browser", "protocol")} for name, span in result["windows"].items()}
        result["stalls"] = {name: {kind: [longest_stall(t, *span) for t in tabs if t.kind == kind]
                                   for kind in ("browser", "protocol")} for name, span in result["windows"].items()}
        result["received KiB/s"] = [t.received / 1024 / (after_end - t.opened) for t in tabs if t.kind == "protocol"]
        result["tabs"] = tabs
        if args.queue:
            result["queue"] = await press_start_together(served, clients, names, teacher, ledger, cpu)
            span = result["queue"]["window"]
            result["windows"][QUEUE_WINDOW] = span
            result["rates"][QUEUE_WINDOW] = {kind: [tick_rate(t, *span) for t in tabs if t.kind == kind]
                                             for kind in ("browser", "protocol")}
            result["stalls"][QUEUE_WINDOW] = {kind: [longest_stall(t, *span) for t in tabs if t.kind == kind]
                                              for kind in ("browser", "protocol")}
            await browser.read()
    finally:
        ending.set()
        for connection in connections:
            await connection.close()
        await asyncio.gather(*tasks, return_exceptions=True)
        await browser.close()
        await playwright.stop()
        for client in [*clients, teacher]:
            await client.aclose()
    result["closed early"] = [f"{t.student} ({t.kind}): {t.closed}" for t in result.get("tabs", []) if t.closed]
    ledger.failures += [f"{t.student} ({t.kind}): the class's pitch link was not opened (the demo played instead)"
                        for t in result.get("tabs", []) if t.link_refused]
    return result


async def press_start_together(served: Served, clients: list, names: list[str], teacher: httpx.AsyncClient,
                               ledger: Ledger, cpu: CpuMeter) -> dict[str, object]:
    """Every student presses Start at once; each run's moments (Start, running, ended) as the teacher's poll
    of GET /api/runs sees them."""
    first = cpu.sample()
    pressed = time.time()
    answers = await asyncio.gather(*(ledger.call(client, "POST", "/api/runs", f"{name} presses Start",
                                                 json=PUPIL_RUN) for name, client in zip(names, clients)))
    answered = time.time()
    runs = {answer.json()["id"]: name for name, answer in zip(names, answers)
            if answer is not None and answer.status_code == 201}
    refused = [name for name, answer in zip(names, answers) if answer is None or answer.status_code != 201]
    estimates = {answer.json()["id"]: answer.json()["queue"]["wait_seconds"] if answer.json()["queue"] else 0.0
                 for answer in answers if answer is not None and answer.status_code == 201}
    started: dict[int, float] = {}
    ended: dict[int, tuple[float, str]] = {}
    while len(ended) < len(runs) and time.time() - pressed < QUEUE_TIMEOUT_S:
        response = await ledger.call(teacher, "GET", "/api/runs", "the teacher polls the runs")
        now = time.time()
        for run in response.json() if response is not None and response.is_success else []:
            if run["id"] not in runs:
                continue
            if run["status"] != "queued":
                started.setdefault(run["id"], now)
            if run["status"] in ENDED:
                ended.setdefault(run["id"], (now, run["status"]))
        await asyncio.sleep(POLL_RUNS_S)
    last = cpu.sample()
    end = max((when for when, _ in ended.values()), default=time.time())
    return {"pressed": pressed, "answered s": answered - pressed, "refused": refused, "runs": len(runs),
            "wait s": {runs[i]: started[i] - pressed for i in started},
            "run s": {runs[i]: ended[i][0] - started[i] for i in ended},
            "estimate error s": [estimates[i] - (started[i] - pressed) for i in started],
            "not finished": [f"{runs[i]}: {ended[i][1]}" for i in ended if ended[i][1] != "finished"]
                            + [runs[i] for i in runs if i not in ended],
            "last finish s": end - pressed, "at once": served.runs_at_once, "window": (pressed, end),
            "cpu": CpuMeter.cores(first, last)}


def queue_figures(queue: dict[str, object]) -> list[Figure]:
    """The queue's report, printed, and its figures."""
    waits, times = list(queue["wait s"].values()), list(queue["run s"].values())
    bound = QUEUE_TARGET * sum(times) / queue["at once"] if times else math.inf
    print(f"\n  the queue: {queue['runs']} students pressed Start in the same second (all answered in "
          f"{queue['answered s']:.2f} s); {len(queue['refused'])} refused (target 0)")
    for name in sorted(queue["wait s"]):
        print(f"    {name}: waited {queue['wait s'][name]:6.1f} s, ran {queue['run s'].get(name, math.nan):5.1f} s")
    print(f"    the last run finished {queue['last finish s']:.1f} s after the Starts; the runs' own times add up to "
          f"{sum(times):.1f} s on {queue['at once']} cores: target ≤ {QUEUE_TARGET:g} x {sum(times) / queue['at once']:.1f}"
          f" = {bound:.1f} s")
    errors = [abs(error) for error in queue["estimate error s"]]
    if queue["not finished"]:
        print(f"    not finished: {', '.join(queue['not finished'])}")
    cores = queue["cpu"]
    print(f"    CPU while the queue plays, cores: serve {cores['serve']:.2f}, machine {cores['machine']:.2f}")
    low, middle, high = spread(waits) if waits else (math.nan,) * 3
    run_low, run_middle, run_high = spread(times) if times else (math.nan,) * 3
    return [
        Figure("queue: Starts refused", len(queue["refused"]), target="0",
               note=f"{queue['runs']} Starts in the same second, the UI's default pupil run; "
                    f"{len(queue['not finished'])} runs did not finish"),
        Figure("queue: the last run's finish, from the Starts", round(queue["last finish s"], 1), "s",
               target=f"≤ {QUEUE_TARGET:g} x (runs' own times / cores)",
               note=f"bound {bound:.1f} s: runs' own times add up to {sum(times):.1f} s, {queue['at once']} at once; "
                    f"{queue['last finish s'] / (bound / QUEUE_TARGET):.2f} x"),
        Figure("queue: a pupil's wait for their run to start", round(middle, 1), "s",
               note=f"median of {len(waits)}; min {low:.1f}, max {high:.1f}; the estimate given at Start was off by "
                    f"{statistics.median(errors) if errors else math.nan:.1f} s (median)"),
        Figure("queue: a pupil's run time", round(run_middle, 1), "s",
               note=f"median of {len(times)}; min {run_low:.1f}, max {run_high:.1f}; serve's CPU "
                    f"{cores['serve']:.2f} cores, the machine's {cores['machine']:.2f}"),
    ]


async def wait_until(done, timeout: float, at_least: float = 0.0) -> None:
    started = time.monotonic()
    while time.monotonic() - started < at_least or (not done() and time.monotonic() - started < timeout):
        await asyncio.sleep(0.2)


# ---- the report ----------------------------------------------------------------------------------------
def report(result: dict[str, object], args: argparse.Namespace, load_before: list[float],
           serve_said: list[str]) -> list[Figure]:
    from soccer_lab.app.web.ui import style
    from soccer_lab.soccer.config import WorldConfig

    nominal = style.DEFAULT_SPEED / WorldConfig().tick_seconds
    protocol = args.students - args.browser_tabs
    ledger: Ledger = result["ledger"]
    figures: list[Figure] = []

    def shown(values: list[float], digits: int = 1) -> str:
        low, middle, high = spread(values)
        text = lambda v: "never" if math.isinf(v) else f"{v:.{digits}f}"  # noqa: E731
        return f"{text(low):>6} {text(middle):>7} {text(high):>6}"

    print(f"\nclassroom: {args.students} students' sessions ({args.browser_tabs} Chromium tabs, {protocol} protocol "
          f"clients), a round of {args.students} entries x {args.starts} starts; load average before {load_before}")
    print(f"  {args.students} students joined in {result['joined s']:.1f} s (paced: {JOIN_COST} requests of this "
          f"one address's rate each)")
    print(f"  one session alone: {result['alone ticks/s']:.1f} ticks/s (the UI's speed: {nominal:g} ticks/s)")
    opened = result["open to playing s"]
    print(f"  the other {args.students - 1} tabs opened: all playing {result['all playing s']:.1f} s after the first "
          "was asked for")
    for kind in ("browser", "protocol"):
        if opened[kind]:
            print(f"    open to the first tick, {kind:<8} s (min median max) {shown(opened[kind])}")
    print(f"  {args.students} entries submitted one after another in {result['entries s']:.1f} s")
    print(f"\n  ticks/s each session received          min  median    max   longest stall (s, max)")
    figures.append(Figure("one session alone", round(result["alone ticks/s"], 1), "ticks/s",
                          note=f"the UI's speed is {nominal:g} ticks/s; its game does not end while measured"))
    for window, (start, end) in result["windows"].items():
        rates, stalls = result["rates"][window], result["stalls"][window]
        ended = {kind: sum(games_ended(t, start, end) for t in result["tabs"] if t.kind == kind)
                 for kind in ("browser", "protocol")}
        print(f"  {window} ({end - start:.1f} s; games ended: {ended['browser']} in Chromium, "
              f"{ended['protocol']} in protocol tabs)")
        for kind in ("browser", "protocol"):
            if rates[kind]:
                print(f"    {kind:<10} {len(rates[kind]):>3} tabs      {shown(rates[kind])}   {max(stalls[kind]):.1f}")
                if window not in RECORDED_WINDOWS:
                    continue
                low, middle, high = spread(rates[kind])
                figures.append(Figure(f"ticks/s per {kind} tab, {window}", round(middle, 1), "ticks/s",
                                      target="every session keeps playing",
                                      note=f"median of {len(rates[kind])} tabs; min {low:.1f}, max {high:.1f}; "
                                           f"longest stall {max(stalls[kind]):.1f} s; window {end - start:.1f} s; "
                                           f"{ended[kind]} games ended, each restarted by its pupil"))
    print(f"  protocol clients received {shown(result['received KiB/s'])} KiB/s (min median max)")
    print(f"  pupils pressed {NEXT_GAME} {sum(t.next_games for t in result['tabs'])} times (a game had ended)")

    answered, api = result["round answered s"], result["api table s"]
    sessions = [*result["session table s"]["browser"], *result["session table s"]["protocol"]]
    played = (f"{result['round']['entries']} entries x {result['round']['starts']} starts" if result["round"]
              else "not started")
    print(f"\n  the round ({played}): the teacher's POST answered in {answered:.2f} s")
    print(f"    its table in GET /api/class/rounds after {api:.2f} s   (target ≤ {TABLE_TARGET_S:g} s)")
    print(f"    its table in the sessions, s (min median max): {shown(sessions, 2)}"
          + (f"; in Chromium's Class tab {shown(result['session table s']['browser'], 2)}"
             if result["session table s"]["browser"] else ""))
    figures.append(Figure("round's table in the API, from the teacher's request", round(api, 2), "s",
                          target=f"≤ {TABLE_TARGET_S:g} s", note=f"{args.students} entries x {args.starts} starts"))
    figures.append(Figure("round's table in every session, from the teacher's request", round(max(sessions), 2), "s",
                          target=f"≤ {TABLE_TARGET_S:g} s", note=f"the last of {len(sessions)}; median "
                                                                  f"{statistics.median(sessions):.2f} s"))

    failed, closed = ledger.failures, result["closed early"]
    print(f"\n  failed requests: {len(failed)} (this script made {ledger.requests}; the pages' own counted too)   "
          "(target 0)")
    for line in failed[:20]:
        print(f"    {line}")
    print(f"  sessions closed before the end: {len(closed)}")
    for line in closed[:20]:
        print(f"    {line}")
    figures.append(Figure("failed requests", len(failed), target="0",
                          note=f"of {ledger.requests} made by the script, plus the browser pages' own; "
                               f"{len(closed)} sessions closed early"))
    print("\n  CPU, cores busy (this machine has 2)   serve  Chromium  this script  machine")
    for window, cores in result["cpu"].items():
        print(f"    {window:<36} {cores['serve']:>5.2f}  {cores['Chromium']:>8.2f}  {cores['this script']:>11.2f}"
              f"  {cores['machine']:>7.2f}")
    cores = result["cpu"]["before the round"]
    figures.append(Figure("serve's CPU before the round", round(cores["serve"], 2), "cores",
                          note=f"machine {cores['machine']:.2f}, Chromium {cores['Chromium']:.2f}, this script "
                               f"{cores['this script']:.2f}"))
    noisy = [line.rstrip() for line in serve_said if line.strip()]
    print(f"  serve printed {len(noisy)} lines while the class ran" + (":" if noisy else ""))
    for line in noisy[:15]:
        print(f"    {line}")
    if "queue" in result:
        figures += queue_figures(result["queue"])
    print(f"  load average before {load_before}, after {load_average()}")
    return figures


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--students", type=int, default=30)
    parser.add_argument("--browser-tabs", type=int, default=3, help="of the students' tabs, how many are Chromium")
    parser.add_argument("--starts", type=int, default=20, help="the round's starts per entry")
    parser.add_argument("--seconds", type=float, default=20.0, help="each measuring window")
    parser.add_argument("--no-queue", dest="queue", action="store_false",
                        help="skip the queue's scenario (every student pressing Start at once)")
    add_record_option(parser)
    args = parser.parse_args()
    if not 2 <= args.students or not 0 <= args.browser_tabs < args.students:
        parser.error("--students at least 2, --browser-tabs fewer than --students (one protocol tab is measured alone)")
    from soccer_lab.app.web.classroom.address import lan_address

    address = lan_address()
    if address.startswith("127."):
        sys.exit("this machine has no network address besides 127.0.0.1: classroom mode serves a local network")
    load_before = load_average()
    with tempfile.TemporaryDirectory() as folder:
        served = Served(Path(folder), address)
        try:
            result = asyncio.run(lesson(served, args))
            said = served.later_lines()
        finally:
            served.stop()
    figures = report(result, args, load_before, said)
    if args.record:
        record("classroom", figures, command=this_command(), load_before=load_before)


if __name__ == "__main__":
    main()
