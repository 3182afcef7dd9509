"""The viser UI driven in headless Chromium: what a teacher does in the first minutes.

The browser clicks and types; assertions read the page and, where the page cannot say it (did the
player move?), the tab's own session in this process. Screenshots of each view go to
artifacts/screenshots/ (git-ignored).
"""

from __future__ import annotations

import shutil
import socket
import time
from pathlib import Path

import pytest

CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]
SCREENSHOTS = Path(__file__).resolve().parents[2] / "artifacts" / "screenshots"
VIEWPORT = {"width": 1600, "height": 900}
TIMEOUT_MS = 60_000  # patience on a shared, busy machine (speed is measured in benchmarks/ui_browser.py)

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(shutil.which(CHROMIUM) is None and not Path(CHROMIUM).exists(),
                       reason=f"Chromium not installed at {CHROMIUM} (scripts/test installs it with apt)"),
]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def ui(tmp_path_factory):
    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.store import Store
    from soccer_lab.app.web.ui import start_ui

    data = tmp_path_factory.mktemp("ui-data")
    store = Store(data / "db.sqlite3")
    runs = RunManager(store, data)
    handle = start_ui(store, runs, port=free_port())
    yield handle
    handle.stop()
    runs.shutdown(wait=10)
    store.close()


@pytest.fixture(scope="module")
def browser():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        launched = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield launched
        launched.close()


@pytest.fixture(scope="module")
def page(ui, browser):
    page = browser.new_page(viewport=VIEWPORT)
    page.set_default_timeout(TIMEOUT_MS)
    page.goto(ui.url)
    page.locator(".game-status").wait_for()
    dismiss_notifications(page)
    yield page
    page.close()


def dismiss_notifications(page) -> None:
    """Headless Chromium renders WebGL in software and viser says so in a toast; close it for screenshots."""
    close = page.locator(".mantine-Notification-closeButton")
    try:
        close.first.wait_for(timeout=3000)
        for i in range(close.count()):
            close.nth(i).click()
    except Exception:  # no toast: nothing to close
        pass


def offline(page) -> list[str]:
    """Refuse every request that leaves this machine, as a school network without internet would; the list
    of what was asked for fills as the page loads."""
    asked = []

    def route(request_route):
        url = request_route.request.url
        if url.startswith(("http://127.0.0.1", "ws://127.0.0.1", "data:", "blob:")):
            request_route.continue_()
        else:
            asked.append(url)
            request_route.abort()

    page.route("**/*", route)
    return asked


def shot(page, name: str) -> None:
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SCREENSHOTS / f"{name}.png"))


def session_of(ui):
    """The session of the most recent tab."""
    with ui.lock:
        return list(ui.sessions.values())[-1]


def field(page, label: str, kind: str):
    """A viser input by its label (viser's labels are not linked to their inputs for get_by_label)."""
    return page.locator(
        f"xpath=//label[normalize-space(text())={xpath_literal(label)}]"
        f"/ancestor::div[contains(@class,'mantine-Flex-root')][1]//{kind}"
    ).first


def xpath_literal(text: str) -> str:
    """`text` as an XPath string literal: a label may hold an apostrophe ("Parents' generation")."""
    if "'" not in text:
        return f"'{text}'"
    if '"' not in text:
        return f'"{text}"'
    return "concat(" + ", \"'\", ".join(f"'{part}'" for part in text.split("'")) + ")"


def choose(page, label: str, option: str, *, exact: bool = False, attempts: int = 5) -> None:
    """Pick `option` in the viser dropdown labelled `label`, as a user does: open it, click the option.

    On a slow CI machine the option list once stayed mounted but never visible for 60 s (the input had just
    come into view in a folder still expanding). So this waits for the input to be wholly in view before
    clicking it and, where the list still does not show, closes it and clicks again, as a user would."""
    from playwright.sync_api import TimeoutError as PlaywrightTimeout
    from playwright.sync_api import expect

    select = field(page, label, "input")
    target = page.get_by_role("option", name=option, exact=exact)
    for _ in range(attempts):
        select.scroll_into_view_if_needed()
        try:  # a folder still expanding above it can move it out of view again: scroll once more
            expect(select).to_be_in_viewport(ratio=1.0)
        except AssertionError:
            continue
        select.click()
        try:
            target.click(timeout=10_000)
            return
        except PlaywrightTimeout:
            page.keyboard.press("Escape")  # close the hidden dropdown; the next click opens it afresh
    raise AssertionError(f"option {option!r} of {label!r} never became clickable")


def tick(page) -> int:
    return int(page.locator(".game-status").get_attribute("data-tick"))


def wait_until(condition, timeout: float = 20.0, interval: float = 0.1):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(interval)
    raise AssertionError("condition not met in time")


def pause(page) -> None:
    page.get_by_role("tab", name="Play").click()
    page.get_by_role("button", name="Pause").click()


def test_pitch_renders_and_the_demo_player_plays(ui, page):
    canvas = page.locator("canvas").first
    first_tick = tick(page)
    before = canvas.screenshot()
    wait_until(lambda: tick(page) >= first_tick + 10)
    after = canvas.screenshot()
    assert before != after  # player and ball moved on the pitch
    player = session_of(ui).game.state.player
    assert player != (0.0, 0.0)
    assert page.locator(".decision").count() == 1
    shot(page, "1-pitch-and-inference")


PITCH_ON_SCREEN = """() => {
  // The pitch as the page draws it: the field and player and ball pictures decoded, inside the view.
  const m = window.__viserMutable;
  if (!m || !m.camera) return null;
  const Vector = m.scene.position.constructor;
  const report = {};
  for (const name of ["/field", "/pitch/player/body", "/pitch/ball"]) {
    const node = m.nodeRefFromName[name];
    let decoded = false;
    if (node) node.traverse((o) => { if (o.material && o.material.map && o.material.map.image) decoded = true; });
    const p = node ? node.getWorldPosition(new Vector()).project(m.camera) : null;
    report[name] = {decoded, inView: p !== null && Math.abs(p.x) <= 1 && Math.abs(p.y) <= 1};
  }
  report.opaque = getComputedStyle(m.canvas).opacity === "1";
  return report;
}"""


def colour_pixels(png: bytes, rgb: tuple[int, int, int], tolerance: int = 12) -> int:
    import io

    import numpy as np
    from matplotlib.image import imread

    pixels = np.rint(imread(io.BytesIO(png), format="png")[..., :3] * 255).astype(int)
    return int((np.abs(pixels - np.array(rgb)).max(axis=-1) <= tolerance).sum())


def test_a_new_tab_paints_the_whole_pitch_with_player_and_ball(ui, browser):
    from soccer_lab.app.web.ui import style

    before = set(ui.sessions)
    fresh = browser.new_page(viewport=VIEWPORT)
    try:
        fresh.set_default_timeout(TIMEOUT_MS)
        fresh.goto(ui.url)
        fresh.wait_for_function(f"() => {{ const r = ({PITCH_ON_SCREEN})(); return r && r.opaque && "
                                f"Object.values(r).every((v) => v === true || (v.decoded && v.inView)); }}")
        dismiss_notifications(fresh)
        canvas = fresh.locator("canvas").first.screenshot()
        # What the pictures show is on screen: the player's blue, the ball's yellow, the grass.
        assert colour_pixels(canvas, style.PLAYER) > 20
        assert colour_pixels(canvas, style.BALL) > 5
        assert colour_pixels(canvas, style.GRASS) > 10_000
    finally:
        fresh.close()
        wait_until(lambda: set(ui.sessions) <= before)  # the other tests' tab is the newest again


def test_the_tick_label_follows_the_game(ui, page):
    session = session_of(ui)
    # A fresh game, paused: an ended one stays over (on a busy machine the tab's first game may have ended)
    pause(page)
    page.get_by_role("button", name="New random start").click()
    wait_until(lambda: session.game.state.tick == 0 and tick(page) == 0)
    page.evaluate("""() => {
      window.__ticks = [];
      const record = () => { const s = document.querySelector('.game-status');
        if (s && window.__ticks[window.__ticks.length - 1] !== Number(s.dataset.tick)) window.__ticks.push(Number(s.dataset.tick)); };
      new MutationObserver(record).observe(document.body, {subtree: true, childList: true, attributes: true});
      record();
    }""")
    page.get_by_role("button", name="Play").click()
    start = session.game.state.tick
    wait_until(lambda: session.game.state.tick >= start + 15 or session.game.done)
    pause(page)
    wait_until(lambda: not session.playing)
    final = session.game.state.tick
    wait_until(lambda: tick(page) == final)
    shown = page.evaluate("() => window.__ticks")
    assert shown == sorted(shown) and len(set(shown)) >= 3  # it moved on with the game, never back
    assert shown[-1] == final


def test_stepping_changes_membership_and_rule_panels(ui, page):
    session = session_of(ui)
    pause(page)
    wait_until(lambda: not session.playing)
    # From a fresh start, so the five steps stay in one game (at a game's end a step starts the next).
    page.get_by_role("button", name="New random start").click()
    wait_until(lambda: session.game.state.tick == 0)
    start = 0
    wait_until(lambda: tick(page) == start)  # the page has the paused tick, not one still on its way
    membership = page.locator(".membership-input").first.inner_html()
    step = page.get_by_role("button", name="Step one tick")
    for clicks in range(1, 6):
        step.click()
        wait_until(lambda: tick(page) == start + clicks)
    assert session.game.state.tick == start + 5 and not session.playing
    assert page.locator(".membership-input").first.inner_html() != membership
    # Strengths or the deciding rule change as the ball gets nearer; at least the HTML differs.
    shown = [float(s) for s in page.locator(".rule").evaluate_all("rows => rows.map(r => r.dataset.strength)")]
    assert shown == pytest.approx(list(session.game.state.strengths), abs=5e-5)
    fired = sum(1 for s in session.game.state.strengths if s > 0)
    field(page, "Only rules that fired", "input").check()
    wait_until(lambda: page.locator(".rule").count() == fired)
    assert page.locator('.rule[data-fired="false"]').count() == 0
    shot(page, "2-stepping")


def test_a_rule_with_an_error_shows_line_and_column(ui, page):
    page.get_by_role("tab", name="Rules").click()
    rulebase_before = session_of(ui).game.rulebase
    field(page, "Rules", "textarea").fill("if Ball is Near then Kick Left High\nif Ball is Nearish then Turn Left")
    page.get_by_role("button", name="Apply").click()
    message = page.locator('.editor-message[data-error="true"]')
    message.wait_for()
    assert "line 2, column 12" in message.inner_text()
    assert session_of(ui).game.rulebase is rulebase_before  # nothing applied
    shot(page, "3-editor-error")


def test_applying_a_valid_rule_changes_the_behaviour(ui, page):
    page.get_by_role("tab", name="Rules").click()
    field(page, "Rules", "textarea").fill("if Ball is not VeryFar then Turn Right")
    page.get_by_role("button", name="Apply").click()
    page.locator('.editor-message[data-error="false"]').wait_for()
    session = session_of(ui)
    wait_until(lambda: session.game.name == "edited")
    page.get_by_role("tab", name="Play").click()
    page.get_by_role("button", name="New random start").click()
    wait_until(lambda: session.game.state.tick == 0)
    start_player = session.game.state.player
    for _ in range(15):
        page.get_by_role("button", name="Step one tick").click()
    wait_until(lambda: session.game.state.tick == 15)
    # Turning (and hunting, which also only turns) never moves the player; the demo's GoToBall did.
    assert session.game.state.player == pytest.approx(start_player, abs=1e-9)
    assert session.game.state.kicks == 0
    assert page.locator(".decision").get_attribute("data-action") in ("TURN", "HUNT")
    shot(page, "4-edited-rule")


def test_a_small_evolution_shows_progress_and_its_best_player_can_be_loaded(ui, page):
    older = ui.context.store.create_run("an older run", {}, ui.context.runs.runs_dir / "{id}")
    ui.context.store.set_run_status(older.id, "stopped")
    page.get_by_role("tab", name="Evolve").click()
    page.get_by_text("GA parameters (chapter's Table 2)").click()
    field(page, "Population size", "input").fill("12")
    field(page, "Generations (max)", "input").fill("2")
    field(page, "Generations (max)", "input").press("Tab")
    session = session_of(ui)
    wait_until(lambda: session.evolve.config()["population_size"] == 12 and session.evolve.config()["max_generations"] == 2)
    # The skill set and counting touches are Game choices of the panel: the defaults are GameConfig's, and a
    # pick reaches the run.
    from soccer_lab.soccer.config import GameConfig

    defaults = GameConfig()
    assert session.evolve.game_config() == {"skills": defaults.skills, "noise": defaults.noise,
                                            "count_touches": defaults.count_touches}
    page.get_by_text("Game options", exact=True).click()
    choose(page, "Skills (strict: kicks only within reach; sighted: and sees the goal)", "assisted")
    field(page, "Body pushes count as kicks", "input").check()
    wait_until(lambda: session.evolve.game_config()["skills"] == "assisted"
               and session.evolve.game_config()["count_touches"] is True)
    page.get_by_role("button", name="Start").click()
    status = page.locator(".evolve-status")
    wait_until(lambda: "generation 0 of 0–1" in status.inner_text() or "finished" in status.inner_text(), timeout=60)
    load = page.get_by_role("button", name="Load best so far onto the pitch")
    wait_until(lambda: load.is_enabled())
    load.click()
    wait_until(lambda: session.game.name.startswith("run #"))
    # The run's best plays in the game it was evaluated in, and the Play tab says which: the Skills control
    # its skill set, the status line the choices beyond it.
    assert session.game.config.skills == "assisted" and session.game.config.count_touches is True
    page.locator('.skills-note[data-skills="assisted"]').wait_for(state="attached")
    page.locator(".game-rules", has_text="body pushes count as kicks").wait_for(state="attached")
    assert "skills" not in page.locator(".game-rules").inner_text()  # named once, by the Skills control
    wait_until(lambda: "finished" in status.inner_text(), timeout=60)
    assert len(session.evolve.best) == 2  # generation 0 (the initial population) and generation 1
    game = session.evolve.store.get_run(session.evolve.run_id).config["game"]
    assert game["skills"] == "assisted" and game["count_touches"] is True
    assert all(0.0 <= b <= m <= 1.0 for b, m in zip(session.evolve.best, session.evolve.mean))
    shot(page, "5-evolve")
    page.get_by_role("tab", name="Population").click()
    page.get_by_role("tab", name="Play").click()
    page.get_by_role("button", name="Play").click()
    # The last generation's best players, played live in the grid.
    caption = page.locator(".population-caption")
    wait_until(lambda: caption.count() and caption.get_attribute("data-generation") == "1")
    shown = len(session.population.labels)
    assert 0 < shown <= 12
    wait_until(lambda: page.locator(".mini-pitch").count() == shown)
    # Under each small pitch its true quality: re-played on the common starts within the view's share of the
    # time, best first (the run's one-game fitness alone once stood there)
    wait_until(lambda: caption.get_attribute("data-replaying") == "false", timeout=60)
    assert "re-played on the same 20 fresh starts as every run's best" in caption.inner_text()
    wait_until(lambda: page.locator(".mini-pitch .replayed").count() == shown)
    lines = page.locator(".mini-pitch .replayed").all_inner_texts()
    assert all(line.startswith("re-played ") or not line.strip() for line in lines)  # unknown: said once, above
    page.get_by_role("tab", name="Library").click()
    shot(page, "6-library-and-population")
    # Newest first: the run just made is selected, not the older one.
    assert session.library.runs.value.startswith(f"#{session.evolve.run_id} ")


def test_after_a_run_every_view_numbers_its_generations_alike_and_says_it_ended(ui, page):
    session = session_of(ui)  # the run of the test above has finished
    run_id = session.evolve.run_id
    last = ui.context.store.statistics(run_id)[-1]
    assert last["generation"] == 1  # generations 0 and 1
    page.get_by_role("tab", name="Evolve").click()
    status = page.locator(".evolve-status").inner_text()
    assert f"Run #{run_id} finished after generation 1" in status
    legend = page.locator(".u-legend").first
    assert "after generation 1" in page.locator(".u-title").first.inner_text()
    assert (f"best of the generation {last['best']:.3f}" in legend.inner_text()
            and f"mean {last['mean']:.3f}" in legend.inner_text())
    assert "--" not in legend.inner_text()
    page.get_by_role("tab", name="Population").click()
    caption = page.locator(".population-caption")
    wait_until(lambda: caption.get_attribute("data-ended") == "true")
    assert caption.get_attribute("data-generation") == "1"
    assert "evaluated" not in caption.inner_text() and "finished after this generation" in caption.inner_text()
    assert "assisted skills · body pushes count as kicks" in caption.inner_text()  # the run's game


def test_a_runs_best_saved_to_the_library_keeps_both_its_figures(ui, page):
    """Saved from the pitch, a run's best once kept its rules only: the library now shows the fitness the GA
    saw beside its true quality."""
    from soccer_lab.app.runs.outputs import best_of_run

    session, store = session_of(ui), ui.context.store
    run_id = session.evolve.run_id  # the finished run of the tests above
    page.get_by_role("tab", name="Evolve").click()
    page.get_by_role("button", name="Load best so far onto the pitch").click()
    wait_until(lambda: session.pitch_run == run_id and session.game.name.startswith(f"run #{run_id} best"))
    page.get_by_role("tab", name="Rules").click()
    field(page, "Name", "input").fill("GA best kept")
    page.get_by_role("button", name="Save").click()
    page.locator(".editor-message", has_text="GA best kept").wait_for()
    saved = next(r for r in store.list_rulebases() if r.name == "GA best kept")
    assert saved.best_of == best_of_run(store, run_id) and saved.best_of["true_quality"]["starts"] == 20
    page.get_by_role("tab", name="Library").click()
    figures = page.locator(".rulebase-figures", has_text=f"Saved from run #{run_id}'s best")
    figures.wait_for()
    assert "as the GA saw it (re-played on 20 fresh starts: " in figures.inner_text()


def test_save_to_library_then_open_it_again(ui, page):
    session = session_of(ui)
    page.get_by_role("tab", name="Rules").click()
    field(page, "Rules", "textarea").fill("if Ball is At then KickTowardGoal VeryHigh\nif Ball is not At then GoToBall High")
    page.get_by_role("button", name="Apply").click()
    wait_until(lambda: len(session.game.rulebase) == 2 and session.game.name == "edited")
    assert session.game.config.skills == "assisted"  # edited rules stay in the game on the pitch (the run's)
    field(page, "Name", "input").fill("my striker")
    page.get_by_role("button", name="Save").click()
    page.locator(".editor-message", has_text="my striker").wait_for()
    saved = [r for r in ui.context.store.list_rulebases() if r.name == "my striker"]
    assert len(saved) == 1 and "GoToBall High" in saved[0].text
    page.get_by_role("button", name="Undo").click()  # back to the previous rulebase
    wait_until(lambda: session.game.name != "edited")
    page.get_by_role("tab", name="Library").click()
    wait_until(lambda: session.library.rulebases.value.endswith("my striker"))
    page.get_by_role("button", name="Open").click()
    wait_until(lambda: session.game.name == "my striker")
    assert "GoToBall High" in "\n".join(session.game.rule_texts)
    assert session.game.config == ui.context.game  # a saved rulebase plays in the app's game
    page.locator(f'.skills-note[data-skills="{ui.context.game.skills}"]').wait_for(state="attached")
    assert page.locator(".game-rules").count() == 0  # the app's game changes nothing beyond its skill set


def test_the_rule_editor_shows_a_whole_rulebase(ui, page):
    from soccer_lab.fuzzy.random_rulebase import random_rulebase
    from soccer_lab.fuzzy.rule import Rulebase
    import numpy as np

    vocabulary = ui.context.vocabulary
    rulebase = random_rulebase(np.random.default_rng(3), vocabulary, rules=12)  # an evolved player's size
    session = session_of(ui)
    session.load_rulebase(rulebase, "twelve rules")
    page.get_by_role("tab", name="Rules").click()
    editor = field(page, "Rules", "textarea")
    wait_until(lambda: editor.input_value().count("\n") >= 11)
    shot(page, "9-rule-editor")
    height, content = editor.evaluate("t => [t.clientHeight, t.scrollHeight]")
    assert content <= height + 1  # every rule in view, no scrolling
    # in the panel's text size (viser's inputs are 12 px, too small on a projector)
    from soccer_lab.app.web.ui import style

    assert editor.evaluate("t => parseFloat(getComputedStyle(t).fontSize)") == style.FONT_SIZE - 1
    # two rules: the box fits them with room to type, and Apply stays in view below it
    session.load_rulebase(Rulebase(rulebase.rules[:2]), "two rules")
    wait_until(lambda: editor.input_value().count("\n") == 1)
    wait_until(lambda: editor.evaluate("t => t.clientHeight") < height / 2)
    apply = page.get_by_role("button", name="Apply")
    assert apply.bounding_box()["y"] + apply.bounding_box()["height"] <= VIEWPORT["height"]


def test_policy_map_marks_the_current_input(ui, page):
    page.get_by_role("tab", name="Policy map").click()
    page.locator(".policy-map").wait_for()
    assert page.locator(".policy-map svg").count() == 2
    shot(page, "7-policy-map")


def test_library_shows_an_experiment_and_its_figures(ui, page, tmp_path):
    from matplotlib.figure import Figure

    folder = tmp_path / "crossover-seed0"
    (folder / "figures").mkdir(parents=True)
    (folder / "report.html").write_text("<html></html>")
    figure = Figure(figsize=(4, 2))
    figure.subplots().plot([0, 1, 2], [0.9, 0.7, 0.6])
    figure.savefig(folder / "figures" / "crossover-best_fitness.png")
    ui.context.store.record_experiment("crossover", folder, {
        "presets": ["crossover"], "trials": 20, "verdicts": {"agrees": 2},
        "figures": ["figures/crossover-best_fitness.png"], "figure_captions": ["Crossover: best fitness"]})
    page.get_by_role("tab", name="Library").click()
    page.get_by_role("button", name="Refresh", exact=True).click()
    summary = page.locator(".experiment")
    summary.wait_for()
    assert "2 agrees" in summary.inner_text() and "20 trials" in summary.inner_text()
    image = page.locator(".experiment-figure img")
    image.wait_for()
    wait_until(lambda: image.evaluate("img => img.complete && img.naturalWidth") > 0)
    assert "Crossover: best fitness" in page.locator(".experiment-figure").inner_text()
    shot(page, "8-library-experiment")


def drawn_player(page) -> tuple[float, float]:
    return tuple(page.evaluate("() => { const p = window.__viserMutable.nodeRefFromName['/pitch/player'].position;"
                               " return [p.x, p.y]; }"))


def test_each_tab_has_its_own_game(ui, browser, page):
    second = browser.new_page(viewport=VIEWPORT)
    try:
        second.goto(ui.url)
        second.locator(".game-status").wait_for()
        wait_until(lambda: len(ui.sessions) == 2)
        first_session, second_session = list(ui.sessions.values())
        assert first_session.game.env is not second_session.game.env
        wait_until(lambda: first_session.ready.is_set() and second_session.ready.is_set())  # panels come after Play
        assert first_session.editor is not second_session.editor
        pause(page)  # the first tab pauses; the second, just opened, plays the demo on its own pitch
        wait_until(lambda: not first_session.playing)
        first_tick, second_tick = first_session.game.state.tick, second_session.game.state.tick
        wait_until(lambda: second_session.game.state.tick >= second_tick + 5)
        assert first_session.game.state.tick == first_tick
        assert second_session.game.name == ui.context.demo_name
        # The pitch's pictures are the server's, the same for both; the frames they hang from are each
        # tab's own: each page draws its own session's player.
        x, y = first_session.game.state.player
        wait_until(lambda: drawn_player(page) == pytest.approx((x, -y), abs=1e-3))
        wait_until(lambda: drawn_player(second) != drawn_player(page))
        assert second.evaluate("() => !!window.__viserMutable.nodeRefFromName['/pitch/player/body']")
    finally:
        second.close()


def test_a_closed_tab_stops_its_session(ui, browser):
    before = set(ui.sessions)
    other = browser.new_page(viewport=VIEWPORT)
    other.set_default_timeout(TIMEOUT_MS)
    other.goto(ui.url)
    other.locator(".game-status").wait_for()
    session = ui.sessions[max(wait_until(lambda: set(ui.sessions) - before))]
    other.close()
    wait_until(lambda: session not in ui.sessions.values())
    assert session.join(timeout=10)  # its loop has ended: nothing more goes to the closed tab
    tick_after = session.game.state.tick
    time.sleep(0.5)
    assert session.game.state.tick == tick_after
