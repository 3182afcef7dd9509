"""The projector view and the lesson's minutes 5-6 in headless Chromium, at a classroom projector's 1280 x 800
and at 1920 x 1080: the pitch fills the window (measured on the screenshot), the score, tick, action and what the
player did in large type (measured in the page), the panels folded; one tick on screen in every animation frame;
a game's end stays, and a skill switch replays the same start. Screenshots go to artifacts/screenshots/."""

from __future__ import annotations

import io
import shutil
import time
from pathlib import Path

import numpy as np
import pytest

from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.pitch import PitchGeometry
from soccer_lab.app.web.ui.projector import PROJECTOR_KEY_SCRIPT
from soccer_lab.soccer.config import GameConfig
from tests.app.test_ui_browser import (CHROMIUM, browser, choose, dismiss_notifications, field,  # noqa: F401
                                       session_of, shot, ui, wait_until)

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(shutil.which(CHROMIUM) is None and not Path(CHROMIUM).exists(),
                       reason=f"Chromium not installed at {CHROMIUM} (scripts/test installs it with apt)"),
]
PROJECTOR_SIZES = ({"width": 1280, "height": 800}, {"width": 1920, "height": 1080})
LARGE_TYPE = 24  # px: the least the projector view's score, tick, action and sentence may be
PITCH_SHARE = 0.75  # of the window's width the grass must span in the projector view
COLOUR_TOLERANCE = 12
FRAMES = 100


def open_tab(ui, browser, viewport):
    """A new tab at `viewport`, with the page's projector key (the app's page, app/web/api/ui_page.py, has it)."""
    page = browser.new_page(viewport=viewport)
    page.set_default_timeout(60_000)
    page.add_init_script(PROJECTOR_KEY_SCRIPT)
    page.goto(ui.url)
    page.locator(".game-status").wait_for()
    wait_until(lambda: session_of(ui).ready.is_set(), timeout=60)
    dismiss_notifications(page)
    return page, session_of(ui)


def grass_box(png: bytes, below: float = 0) -> tuple[int, int, int, int]:
    """(left, top, right, bottom) of the grass's colours in a screenshot, under the row `below` (the band's
    green sentence is the grass's colour)."""
    from PIL import Image

    pixels = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)
    green = np.zeros(pixels.shape[:2], bool)
    for colour in (style.GRASS, style.GRASS_STRIPE):
        green |= (np.abs(pixels - np.array(colour)) <= COLOUR_TOLERANCE).all(axis=2)
    green[: int(np.ceil(below))] = False
    rows, columns = np.nonzero(green)
    return int(columns.min()), int(rows.min()), int(columns.max()) + 1, int(rows.max()) + 1


# Read in one script: the band's HTML is replaced at every tick, a located element may be gone a moment later.
def box(page, selector: str) -> dict:
    return page.evaluate("s => { const r = document.querySelector(s).getBoundingClientRect(); "
                         "return {x: r.x, y: r.y, width: r.width, height: r.height}; }", selector)


def band_tab(page, name: str):
    """The band's tab `name`: the folded right panel has tabs of the same names on its rail, at the right edge."""
    width = page.viewport_size["width"]
    tabs = page.get_by_role("tab", name=name, exact=True)
    return next(tabs.nth(i) for i in range(tabs.count())
                if (b := tabs.nth(i).bounding_box()) and b["x"] + b["width"] < width - 100)


def font_px(page, selector: str) -> float:
    return float(page.evaluate("s => parseFloat(getComputedStyle(document.querySelector(s)).fontSize)", selector))


@pytest.mark.parametrize("viewport", PROJECTOR_SIZES, ids=lambda v: f"{v['width']}x{v['height']}")
def test_projector_view_fills_the_window_with_large_type(ui, browser, viewport):
    """At 1280 x 800 the pitch was ~380 x 250 px between two panels and its labels ~11 px: the projector view
    (key P) gives the grass at least 75% of the width, the band's type at least 24 px, above the pitch's lines."""
    page, session = open_tab(ui, browser, viewport)
    try:
        page.keyboard.press("p")
        page.locator(".projector-status").wait_for()
        wait_until(lambda: not page.locator(".game-status").is_visible())  # the panels are folded
        assert not page.locator(".inference-decision").is_visible()
        width = viewport["width"]
        band = box(page, ".projector-status")
        under = band["y"] + band["height"]

        def grass_width() -> int:
            left, _, right, _ = grass_box(page.screenshot(), below=under)
            return right - left

        wait_until(lambda: grass_width() >= PITCH_SHARE * width, timeout=30)
        time.sleep(0.5)  # the camera's last move drawn
        left, top, right, bottom = grass_box(page.screenshot(), below=under)
        shot(page, f"projector-{width}x{viewport['height']}")
        print(f"grass {right - left} px of {width} ({(right - left) / width:.3f}), from y {top} to {bottom}")
        assert right - left >= PITCH_SHARE * width, (left, right)
        assert top - under < style.PITCH_MARGIN * (bottom - top) / 78, "a gap between the band and the pitch"
        for part in (".projector-score", ".projector-tick", ".projector-action", ".projector-world"):
            assert font_px(page, part) >= LARGE_TYPE, part
        # The band ends above the pitch's lines, at most over the grass's margin: where the grass's top would be
        # (from its width and shape, in metres), the lines begin PITCH_MARGIN lower.
        x0, x1, y0, y1 = PitchGeometry.from_world(GameConfig().world).grass
        pixels_per_metre = (right - left) / (x1 - x0)
        lines_top = bottom - (y1 - y0 - style.PITCH_MARGIN) * pixels_per_metre
        assert under <= lines_top, f"the band (to y {under}) covers the pitch's lines (from y {lines_top:.0f})"
        assert band["x"] + band["width"] <= width

        page.keyboard.press("p")  # and back: the panels return
        page.locator(".game-status").wait_for(state="visible")
        assert not page.locator(".projector-status").is_visible()
        assert session.projector.on is False
    finally:
        page.close()


def test_projector_button_shows_the_population_grid_larger(ui, browser):
    """The population grid's players were dots: in the projector view's folded panel it is drawn larger."""
    page, session = open_tab(ui, browser, PROJECTOR_SIZES[0])
    try:
        page.get_by_role("tab", name="Play").click()
        page.get_by_role("button", name="Projector view (P)").click()
        page.locator(".projector-status").wait_for()
        band_tab(page, "Population").click()
        grid = page.locator(".projector-population")
        grid.wait_for()
        assert session.projector.on
        shot(page, "projector-population-1280x800")
        page.get_by_role("tab", name="View").click()
        page.get_by_role("button", name="Leave projector view (P)").click()
        wait_until(lambda: not session.projector.on)
    finally:
        page.close()


@pytest.mark.parametrize("speed", (1.0, 4.0))
def test_pitch_panel_and_status_show_one_tick_in_every_frame(ui, browser, speed):
    """While playing, the pitch's label said "dash 100" and the Inference panel "Dribble: kick 8": the status
    line and the decision carry the tick they show, read together in one animation frame, FRAMES frames in a
    row. (The pitch's drawing, which the page cannot read, goes in the same message: app/web/ui/session.py _render.)"""
    page, session = open_tab(ui, browser, PROJECTOR_SIZES[0])
    try:
        with session.lock:
            session.controls.speed.value = speed
            session.new_start(3)
            session.set_playing(True)
        page.locator(".inference-decision").wait_for()
        frames = page.evaluate("""(count) => new Promise((done) => {
            const seen = [];
            const read = () => {
              const ticks = [".game-status", ".inference-decision"].map(
                (s) => { const e = document.querySelector(s); return e ? Number(e.dataset.tick) : null; });
              seen.push(ticks);
              if (seen.length < count) requestAnimationFrame(read); else done(seen);
            };
            requestAnimationFrame(read);
          })""", FRAMES)
        assert len(frames) == FRAMES
        moving = {f[0] for f in frames}
        assert len(moving) > 5, "the game did not play"
        for status, decision in frames:
            assert status == decision, (status, decision)
    finally:
        page.close()


@pytest.mark.parametrize("speed,match", [(1.0, False), (4.0, False), (4.0, True)], ids=["1x", "4x", "match-4x"])
def test_while_playing_the_pitch_changes_only_poses_and_visibility_so_its_label_never_trails_the_panels(
        ui, browser, speed, match):
    """The band said "dash 100" while the pitch's label still said "dash 92": viser's client applies a node's pose
    and visibility in the frame that receives them, but a label's text and a line's points through React, frames
    later. Every message the tab's pitch gets while a game (or a match, its names shown) plays moves, shows or hides
    a node made beforehand; only the trail (history, up to the ball) gets new points."""
    from viser import _messages

    from soccer_lab.app.web.ui.pitch import COMMAND_LABEL_NODE, COMMAND_NODE, NAME_LABEL_NODES, TRAIL_NODE
    from soccer_lab.fuzzy.vocabulary import Vocabulary
    from soccer_lab.soccer.examples import example

    page, session = open_tab(ui, browser, PROJECTOR_SIZES[0])
    connection = session.client.scene._websock_interface
    sent = []
    try:
        with session.lock:
            session.controls.speed.value = speed
            if match:
                striker, dribbler = (example(name).rulebase(Vocabulary.default()) for name in ("striker", "dribbler"))
                session.watch_match(striker, dribbler, ("Striker", "Dribbler"), 3, GameConfig(), Vocabulary.default())
            else:
                session.new_start(3)
            session.set_playing(True)
        page.locator(".inference-decision").wait_for()
        wait_until(lambda: session.game.state.tick >= 2)  # a match's names placed
        start = session.game.state.tick
        queue = connection.queue_message
        connection.queue_message = lambda message: (sent.append(message), queue(message))[1]
        wait_until(lambda: session.game.state.tick >= start + 60, timeout=60)
    finally:
        connection.__dict__.pop("queue_message", None)
        with session.lock:
            session.set_playing(False)
        page.close()
    pitch = [m for m in sent if getattr(m, "name", "").startswith("/pitch")]
    moves = (_messages.SetPositionMessage, _messages.SetOrientationMessage, _messages.SetSceneNodeVisibilityMessage)
    changed = [(type(m).__name__, m.name) for m in pitch if not isinstance(m, moves) and m.name != TRAIL_NODE]
    assert not changed, changed
    assert any(m.name.startswith(f"{COMMAND_NODE}_") for m in pitch), "no mark moved or was shown"
    assert any(m.name.startswith(f"{COMMAND_LABEL_NODE}_") for m in pitch), "no label moved or was shown"
    assert not match or any(m.name in NAME_LABEL_NODES for m in pitch), "the match's names did not move"


def test_a_game_over_stays_until_the_teacher_starts_the_next_and_skills_replay_the_same_start(ui, browser):
    """"game over" disappeared after 2.4 s and the next seed started by itself, so "switch to strict: the same
    start scores" (lesson minutes 5-6) was another start. Now the end stays, with its reason; a skill switch
    replays the seed on screen from its start."""
    page, session = open_tab(ui, browser, PROJECTOR_SIZES[0])
    try:
        page.get_by_role("tab", name="Play").click()
        choose(page, "Skills", "sighted", exact=True)
        page.get_by_role("tab", name="Rules").click()
        choose(page, "Example", "Two-rule striker")
        wait_until(lambda: session.game.name == "Two-rule striker")
        page.get_by_role("tab", name="Play").click()
        with session.lock:
            session.controls.speed.value = 20.0
            session.set_playing(True)
        seed = session.game.seed
        over = page.locator('.game-over[data-reason="idle"]')
        over.wait_for(timeout=120_000)
        time.sleep(4.0)  # past the old 2.4 s
        assert over.is_visible() and "neither moved nor kicked" in over.inner_text()
        assert session.game.done and session.game.seed == seed
        assert page.locator(".next-game").is_visible()
        shot(page, "lesson-game-over-stays")
        with session.lock:
            session.set_playing(False)  # Pause: the switched game stays at its start to be compared
        start = seed_start(session)

        choose(page, "Skills", "strict", exact=True)
        wait_until(lambda: session.game.config.skills == "strict")
        with session.lock:
            assert session.game.seed == seed and session.game.state.tick == 0
            assert np.array_equal(np.array(session.game.state.player), start[0])
            assert np.array_equal(np.array(session.game.state.ball), start[1])
            session.set_playing(True)
        wait_until(lambda: session.game.state.goals >= 1, timeout=120)
        with session.lock:
            session.controls.speed.value = style.DEFAULT_SPEED
        choose(page, "Skills", "sighted", exact=True)
    finally:
        page.close()


def seed_start(session) -> tuple[np.ndarray, np.ndarray]:
    """The player's and the ball's places at the start of the tab's seed, from a game of its own."""
    from soccer_lab.app.web.ui.game import Game

    replay = Game(session.context, session.game.rulebase, session.game.name, session.game.seed, session.game.config)
    return np.array(replay.state.player), np.array(replay.state.ball)


READABLE_CAPTION = 18  # px: a small pitch's name and goals, read from the back of a class
READABLE_PITCH = 200  # px wide: each small pitch at 1280 x 800


def rendered_sizes(page) -> list[dict]:
    """Each small pitch of the projector's grid as drawn: its width, and its caption's font size times the zoom
    the grid is drawn at (a box's drawn height over its laid-out one)."""
    return page.evaluate("""() => [...document.querySelectorAll('.projector-population .mini-pitch')].map((cell) => {
        const caption = cell.querySelector('div');
        const zoom = caption.getBoundingClientRect().height / caption.offsetHeight;
        return {pitch: cell.querySelector('svg').getBoundingClientRect().width,
                caption: parseFloat(getComputedStyle(caption).fontSize) * zoom,
                bottom: cell.getBoundingClientRect().bottom};
    })""")


def test_projector_population_grid_stays_readable_with_a_run_playing(ui, browser):
    # At 1280 x 800 the grid's players were dots, then its fourth row fell below the window. With a run playing
    # (its latest generation's best players in the grid), every small pitch is at least 200 px wide, its caption
    # at least 18 px, and all in the window, measured in the page.
    page, session = open_tab(ui, browser, PROJECTOR_SIZES[0])
    try:
        page.get_by_role("tab", name="Evolve").click()
        page.get_by_text("GA parameters (chapter's Table 2)").click()
        field(page, "Population size", "input").fill("12")  # a full grid
        field(page, "Generations (max)", "input").fill("3")
        field(page, "Generations (max)", "input").press("Tab")
        wait_until(lambda: session.evolve.config()["population_size"] == 12
                   and session.evolve.config()["max_generations"] == 3)
        page.get_by_role("button", name="Start").click()
        wait_until(lambda: session.population.shown_players() is not None, timeout=120)  # a generation's best
        page.get_by_role("tab", name="Play").click()
        page.get_by_role("button", name="Projector view (P)").click()
        page.locator(".projector-status").wait_for()
        band_tab(page, "Population").click()
        wait_until(lambda: page.locator(".projector-population .mini-pitch").count() > 0, timeout=60)
        sizes = rendered_sizes(page)
        shot(page, "projector-population-run-1280x800")
        print(f"{len(sizes)} small pitches, drawn {sizes[0]}")
        assert all(size["pitch"] >= READABLE_PITCH for size in sizes), sizes
        assert all(size["caption"] >= READABLE_CAPTION for size in sizes), sizes
        assert all(size["bottom"] <= PROJECTOR_SIZES[0]["height"] for size in sizes), "a small pitch below the window"
        page.get_by_role("tab", name="View").click()
        page.get_by_role("button", name="Leave projector view (P)").click()
        wait_until(lambda: not session.projector.on)
    finally:
        session.evolve.stop()  # the next test's tab starts without this run in the machine's queue
        page.close()
