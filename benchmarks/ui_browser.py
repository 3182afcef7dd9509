"""The UI as a teacher meets it, in headless Chromium: open to playing, first paint, every tick drawn, bytes
per tab.

Open to playing (the figure the spec's target is on: at most 3 s): a real `soccer-lab serve` is started
(its own process, an empty data folder, the README's defaults), and a fresh browser opens the UI: the
seconds from the navigation's start to the moment the tick counter has advanced with the whole pitch
drawn; then the page is reloaded and measured again. Five rounds, each with a new `serve`; the median of
each is reported (`--record` writes docs/results/ui_browser.json).

Then the UI is started in this process (an empty data folder), TABS tabs of Debian's Chromium (software
WebGL, the flags of tests/app/test_ui_browser.py) are opened and reported, per number of tabs:

- first paint: seconds to the first frame drawn with the whole pitch on screen (grass, lines, goal,
  player and ball inside the canvas, the canvas fully opaque), counted from the navigation's start
  (the browser's performance.timeOrigin, where web first-paint metrics count from: the page is being
  opened) and, as before, from asking Chromium for a new tab or a reload (a new tab adds its own set-up,
  about 0.4-1 s of software-WebGL start here); both on opening the page and on reloading it;
- ticks drawn: of the ticks the server played in the measuring window, the share whose player and
  ball position the page drew in at least one frame; pitch updates per second (frames that drew a new
  position) against game ticks per second; frames drawn per second; tick label updates per second;
- websocket messages and KiB per second each tab received;
- viser's warnings when the tabs close (there should be none).

The page is watched from inside (the scene's onBeforeRender and the tick label); the server's ticks
by polling each tab's session. Speed is the game's (1 = real time, the target: every tick drawn).

    python benchmarks/ui_browser.py [--tabs 1 4] [--speed 1] [--seconds 15] [--rounds 5] [--record]
"""

from __future__ import annotations

import argparse
import json
import math
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from playwright.sync_api import TimeoutError as PlaywrightTimeout
from playwright.sync_api import sync_playwright
from results import Figure, add_record_option, load_average, record, this_command

CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]
VIEWPORT = {"width": 1600, "height": 900}
PAINT_TIMEOUT_S = 120.0
WARM_UP_S = 2.0
POLL_S = 0.005  # the server's ticks last 33 ms or more at the speeds measured: none is missed
SAME_POSITION = 1e-3  # metres: a drawn position is a tick's when every coordinate agrees this well

# Runs in every page before its own scripts: records each frame the scene is drawn in that shows a new
# player or ball position, the first frame with the whole pitch on screen, and each new tick label.
WATCH_PAGE = """
(() => {
  const watch = window.__watch = {frames: 0, draws: [], ticks: [], complete: null};
  // The field is one picture ("/field"); before it was, grass and lines were nodes of their own.
  const FIELDS = [["/field"], ["/pitch/grass", "/pitch/lines", "/pitch/net"]];
  let hooked = false;
  function drawn(node) {
    // Mounted, and every texture it shows decoded (a picture's quad is blank until then).
    let ready = true;
    node.traverse((o) => {
      if (o.material && o.material.type === "MeshBasicMaterial" && !(o.material.map && o.material.map.image)) ready = false;
    });
    return ready;
  }
  function pitchComplete(m) {
    const nodes = m.nodeRefFromName;
    const parts = ["/pitch/player", "/pitch/ball"];
    const field = FIELDS.find((names) => names.every((name) => nodes[name]));
    return field !== undefined && [...field, ...parts].every((name) => drawn(nodes[name]))
      && m.canvas && getComputedStyle(m.canvas).opacity === "1" && inView(m, parts) && pitchFitted(m);
  }
  function inView(m, names) {
    const camera = m.camera;
    const Vector = m.scene.position.constructor;
    camera.updateMatrixWorld();
    for (const name of names) {
      const node = m.nodeRefFromName[name];
      if (!node) return false;
      for (let o = node; o; o = o.parent) if (!o.visible) return false;
      const p = node.getWorldPosition(new Vector()).project(camera);
      if (!(Math.abs(p.x) <= 1 && Math.abs(p.y) <= 1)) return false;
    }
    return true;
  }
  function pitchFitted(m) {
    // The pitch's end lines project near the canvas edges once the camera is fitted to it.
    const pitch = m.nodeRefFromName["/pitch"];
    if (!pitch) return false;
    const Vector = m.scene.position.constructor;
    const left = pitch.localToWorld(new Vector(-50, 0, 0)).project(m.camera);
    const right = pitch.localToWorld(new Vector(50, 0, 0)).project(m.camera);
    return Math.abs(left.x) <= 1 && Math.abs(right.x) <= 1 && right.x - left.x > 1.0;
  }
  function hook() {
    const m = window.__viserMutable;
    if (m && m.scene && m.camera && !hooked) {
      hooked = true;
      let last = null;
      m.scene.onBeforeRender = () => {
        const now = performance.now();
        watch.frames += 1;
        const nodes = m.nodeRefFromName, player = nodes["/pitch/player"], ball = nodes["/pitch/ball"];
        if (watch.complete === null && pitchComplete(m)) watch.complete = now;
        if (player && ball) {
          const key = [player.position.x, player.position.y, ball.position.x, ball.position.y];
          if (last === null || key.some((v, i) => v !== last[i])) {
            watch.draws.push([now, ...key]);
            last = key;
          }
        }
      };
    }
    const status = document.querySelector(".game-status");
    if (status) {
      const tick = Number(status.dataset.tick), ticks = watch.ticks;
      if (!ticks.length || ticks[ticks.length - 1][1] !== tick) ticks.push([performance.now(), tick]);
    }
    requestAnimationFrame(hook);
  }
  requestAnimationFrame(hook);
})();
"""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@dataclass
class Tab:
    page: object
    session: object = None
    frames: list[tuple[float, int]] = field(default_factory=list)  # (perf_counter, bytes) per websocket message
    ticks: list[tuple[float, int, float, float, float, float]] = field(default_factory=list)  # server's
    first_paint: dict[str, float] = field(default_factory=dict)

    def listen(self) -> None:
        def on_socket(socket) -> None:
            socket.on("framereceived", lambda payload: self.frames.append((time.perf_counter(), len(payload))))

        self.page.on("websocket", on_socket)


class TickPoller(threading.Thread):
    """Records every tick each tab's session plays: (time, tick, player x, y, ball x, y)."""

    def __init__(self, tabs: list[Tab]):
        super().__init__(daemon=True)
        self.tabs = tabs
        self.running = threading.Event()
        self.done = threading.Event()

    def run(self) -> None:
        last: dict[int, object] = {}
        while not self.done.is_set():
            if self.running.is_set():
                for index, tab in enumerate(self.tabs):
                    state = tab.session.game.state
                    if state is not last.get(index):
                        last[index] = state
                        tab.ticks.append((time.perf_counter(), state.tick, *state.player, *state.ball))
            time.sleep(POLL_S)


def open_tab(ui, browser_context, tab: Tab | None = None) -> Tab:
    """Open (or reload) a tab and wait for its first complete pitch; returns the tab with its session."""
    before = set(ui.sessions)
    opened = time.time()
    if tab is None:
        tab = Tab(browser_context.new_page())
        tab.listen()
        tab.page.goto(ui.url)
        what = "open"
    else:
        tab.page.reload()
        what = "reload"
    try:
        tab.page.wait_for_function("() => window.__watch && window.__watch.complete !== null",
                                   timeout=PAINT_TIMEOUT_S * 1000, polling=100)
        origin, complete = tab.page.evaluate("() => [performance.timeOrigin, window.__watch.complete]")
        tab.first_paint[what] = complete / 1000  # performance.now() counts from the navigation's start
        tab.first_paint[f"{what} asked"] = (origin + complete) / 1000 - opened
    except PlaywrightTimeout:  # reported as longer than the wait, and the tab measured all the same
        tab.first_paint[what] = tab.first_paint[f"{what} asked"] = math.inf
    deadline = time.monotonic() + PAINT_TIMEOUT_S
    while not (new := set(ui.sessions) - before) and time.monotonic() < deadline:
        time.sleep(0.05)
    tab.session = ui.sessions[max(new)]
    return tab


def measure(tabs: list[Tab], seconds: float, speed: float) -> list[dict[str, float]]:
    for tab in tabs:
        tab.session.ready.wait(PAINT_TIMEOUT_S)
        tab.session.controls.speed.value = speed
        tab.session.set_playing(True)
        tab.ticks.clear()
    poller = TickPoller(tabs)
    poller.start()
    tabs[0].page.wait_for_timeout(WARM_UP_S * 1000)
    starts = [tab.page.evaluate("() => performance.now()") for tab in tabs]
    start = time.perf_counter()
    poller.running.set()
    tabs[0].page.wait_for_timeout(seconds * 1000)
    poller.running.clear()
    end = time.perf_counter()
    poller.done.set()
    poller.join()
    rows = []
    for tab, page_start in zip(tabs, starts):
        watch = tab.page.evaluate("() => ({draws: window.__watch.draws, ticks: window.__watch.ticks, "
                                  "frames: window.__watch.frames, now: performance.now()})")
        page_end = page_start + (end - start) * 1000
        draws = np.array([d[1:] for d in watch["draws"] if page_start <= d[0] <= page_end + 1000] or
                         np.zeros((0, 4)))
        played = [t for t in tab.ticks if t[1] > 0]
        drawn = sum(1 for t in played if _was_drawn(t, draws))
        received = [n for when, n in tab.frames if start <= when <= end]
        labels = [t for t in watch["ticks"] if page_start <= t[0] <= page_end]
        rows.append({
            "game ticks/s": len(played) / (end - start),
            "pitch updates/s": sum(1 for d in watch["draws"] if page_start <= d[0] <= page_end) / (end - start),
            "ticks drawn %": 100.0 * drawn / max(1, len(played)),
            "tick label updates/s": len(labels) / (end - start),
            "messages/s": len(received) / (end - start),
            "KiB/s": sum(received) / 1024 / (end - start),
        })
    return rows


def _was_drawn(tick: tuple, draws: np.ndarray) -> bool:
    _, _, px, py, bx, by = tick
    scene = np.array([px, -py, bx, -by])  # the pitch stores (x, -y)
    return bool(len(draws)) and bool((np.abs(draws - scene) <= SAME_POSITION).all(axis=1).any())


def frames_drawn(tabs: list[Tab], seconds: float) -> list[float]:
    before = [tab.page.evaluate("() => window.__watch.frames") for tab in tabs]
    tabs[0].page.wait_for_timeout(seconds * 1000)
    return [(tab.page.evaluate("() => window.__watch.frames") - b) / seconds for tab, b in zip(tabs, before)]


def run(tab_count: int, speed: float, seconds: float, playwright) -> dict[str, object]:
    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.store import Store
    from soccer_lab.app.web.ui import start_ui
    from soccer_lab.app.web.ui.game import Game

    with tempfile.TemporaryDirectory() as folder:
        store = Store(Path(folder) / "db.sqlite3")
        runs = RunManager(store, folder)
        ui = start_ui(store, runs, port=free_port())
        Game(ui.context, ui.context.demo_rulebase(), "warm-up", seed=1).step()  # numba's cache, loaded once
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        # One window per tab, as a teacher's and the students' screens would show them: pages sharing a
        # window are background tabs there, and Chromium draws a background tab about once a second.
        contexts = [browser.new_context(viewport=VIEWPORT) for _ in range(tab_count)]
        for context in contexts:
            context.add_init_script(WATCH_PAGE)
        try:
            tabs = [open_tab(ui, context) for context in contexts]
            rows = measure(tabs, seconds, speed)
            fps = frames_drawn(tabs, min(5.0, seconds))
            for tab, context in zip(tabs, contexts):
                open_tab(ui, context, tab)
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                for tab in tabs:
                    tab.page.close()
                deadline = time.monotonic() + 10
                while ui.sessions and time.monotonic() < deadline:
                    time.sleep(0.1)
                time.sleep(1.0)  # a late frame of a closed tab would warn now
            closed_warnings = [str(w.message).split(" (")[0] for w in caught if "closed connection" in str(w.message)]
        finally:
            browser.close()
            ui.stop()
            runs.shutdown(wait=10)
            store.close()
    return {
        "tabs": tab_count,
        **{f"first paint {what} s": [t.first_paint[what] for t in tabs]
           for what in ("open", "open asked", "reload", "reload asked")},
        "rows": rows,
        "frames drawn/s": fps,
        "close warnings": closed_warnings,
    }


def report(result: dict[str, object], speed: float) -> list[Figure]:
    """Prints the tabs' figures; returns the ones the docs show (the share of ticks drawn, ticks played)."""
    def spread(values: list[float], unit: str = "") -> str:
        def shown(value: float) -> str:
            return f"> {PAINT_TIMEOUT_S:.0f}" if math.isinf(value) else f"{value:.1f}"

        if len(values) == 1:
            return f"{shown(values[0])}{unit}"
        return f"{shown(statistics.median(values))}{unit} (min {shown(min(values))}, max {shown(max(values))})"

    rows = result["rows"]
    print(f"\n{result['tabs']} tab(s), speed {speed:g}x")
    print(f"  first paint, open      {spread(result['first paint open s'], ' s')}   (target ≤ 3 s; from the navigation's start)")
    print(f"    from asking a tab    {spread(result['first paint open asked s'], ' s')}")
    print(f"  first paint, reload    {spread(result['first paint reload s'], ' s')}")
    print(f"    from asking reload   {spread(result['first paint reload asked s'], ' s')}")
    for name in ("game ticks/s", "pitch updates/s", "ticks drawn %", "tick label updates/s", "messages/s", "KiB/s"):
        print(f"  {name:<22} {spread([row[name] for row in rows])}")
    print(f"  {'frames drawn/s':<22} {spread(result['frames drawn/s'])}")
    warned = result["close warnings"]
    print(f"  viser closed-connection warnings (unfiltered) on closing the tabs: {len(warned)}{'  (' + '; '.join(sorted(set(warned))) + ')' if warned else ''}")
    drawn = [row["ticks drawn %"] for row in rows]
    played = [row["game ticks/s"] for row in rows]
    tabs = f"{result['tabs']} tab{'s' if result['tabs'] != 1 else ''} at {speed:g}x"
    return [Figure(f"ticks drawn, {tabs} (lowest tab)", round(min(drawn), 1), "%",
                   target="every tick at 1x" if result["tabs"] == 1 else "",
                   note=f"each tab's share: {', '.join(f'{d:.1f}' for d in drawn)}; frames the browser drew a "
                        f"second per tab: {', '.join(f'{f:.1f}' for f in result['frames drawn/s'])}"),
            Figure(f"game ticks played per second, {tabs} (lowest tab)", round(min(played), 1), "ticks/s")]


# ---- open to playing, against a real `soccer-lab serve` --------------------------------------------------
SERVE_START_TIMEOUT_S = 120.0
OPEN_TO_PLAYING = """() => {
  // Seconds from the navigation's start until the tick counter has advanced with the whole pitch drawn.
  const w = window.__watch;
  if (!w || w.complete === null || w.ticks.length < 2) return null;
  return Math.max(w.complete, w.ticks[1][0]) / 1000;
}"""


def start_serve(folder: Path) -> tuple[subprocess.Popen, str]:
    """`soccer-lab serve` on free ports with its data in `folder`; (the process, the UI's address)."""
    ports = [free_port() for _ in range(2)]
    command = [str(Path(sys.executable).parent / "soccer-lab"), "serve", "--port", str(ports[0]), "--ui-port",
               str(ports[1]), "--data-dir", str(folder)]
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + SERVE_START_TIMEOUT_S
    while time.monotonic() < deadline:
        try:
            with urllib.request.urlopen(f"http://127.0.0.1:{ports[0]}/api/server", timeout=1) as answer:
                return process, json.loads(answer.read())["ui"]
        except OSError:
            if process.poll() is not None:
                raise RuntimeError(f"soccer-lab serve ended at start (exit status {process.returncode})")
            time.sleep(0.1)
    process.kill()
    raise RuntimeError("soccer-lab serve did not answer")


def open_to_playing(playwright, rounds: int) -> dict[str, list[float]]:
    """Per round, a new serve: the first open's and a reload's seconds to playing."""
    measured: dict[str, list[float]] = {"first open": [], "reload": []}
    for _ in range(rounds):
        with tempfile.TemporaryDirectory() as folder:
            process, ui_url = start_serve(Path(folder))
            browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
            try:
                page = browser.new_context(viewport=VIEWPORT).new_page()
                page.add_init_script(WATCH_PAGE)
                page.set_default_navigation_timeout(PAINT_TIMEOUT_S * 1000)
                for what, go in (("first open", lambda: page.goto(ui_url, wait_until="commit")),
                                 ("reload", lambda: page.reload(wait_until="commit"))):
                    go()
                    try:
                        handle = page.wait_for_function(OPEN_TO_PLAYING, timeout=PAINT_TIMEOUT_S * 1000, polling=50)
                        measured[what].append(float(handle.json_value()))
                    except PlaywrightTimeout:
                        measured[what].append(math.inf)
            finally:
                browser.close()
                process.terminate()
                process.wait(30)
    return measured


def report_open_to_playing(measured: dict[str, list[float]], load_before: list[float]) -> list[Figure]:
    print(f"\nopen to playing (navigation start -> tick counter advancing, pitch drawn), {len(measured['first open'])} "
          f"rounds, each a new `soccer-lab serve`; load average before {load_before}, after {load_average()}")
    figures = []
    for what, values in measured.items():
        median = statistics.median(values)
        print(f"  {what:<12} median {median:.2f} s (min {min(values):.2f}, max {max(values):.2f})   target ≤ 3 s")
        figures.append(Figure(f"open to playing, {what} (median of {len(values)})", round(median, 2), "s",
                              target="≤ 3 s", note=f"min {min(values):.2f}, max {max(values):.2f}"))
    return figures


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tabs", type=int, nargs="*", default=[1, 4], help="tab counts to measure (none: skip)")
    parser.add_argument("--speed", type=float, default=1.0)
    parser.add_argument("--seconds", type=float, default=15.0)
    parser.add_argument("--rounds", type=int, default=5, help="open to playing: rounds, each a new serve (0: skip)")
    add_record_option(parser)
    args = parser.parse_args()
    load_before = load_average()
    figures: list[Figure] = []
    with sync_playwright() as playwright:
        if args.rounds:
            figures += report_open_to_playing(open_to_playing(playwright, args.rounds), load_before)
        for tab_count in args.tabs:
            figures += report(run(tab_count, args.speed, args.seconds, playwright), args.speed)
    if args.record:
        record("ui_browser", figures, command=this_command(), load_before=load_before)


if __name__ == "__main__":
    main()
