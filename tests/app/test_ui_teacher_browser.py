"""What a teacher meets in the first ten minutes, in headless Chromium: a frozen player explained in words
and on the pitch, the skill set switched where it is explained, nothing drawn off the grass, number fields
that show what the server uses, output-set labels apart. Screenshots go to artifacts/screenshots/."""

from __future__ import annotations

import io
import random
import shutil
from pathlib import Path

import numpy as np
import pytest

from soccer_lab.app.web.ui import style
from tests.app.test_ui_browser import (CHROMIUM, VIEWPORT, browser, choose, field,  # noqa: F401 (fixtures)
                                       page, pause, session_of, shot, ui, wait_until)

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(shutil.which(CHROMIUM) is None and not Path(CHROMIUM).exists(),
                       reason=f"Chromium not installed at {CHROMIUM} (scripts/test installs it with apt)"),
]
COLOUR_TOLERANCE = 10  # per channel: the canvas is drawn in software, edges blend


def test_the_two_rule_striker_says_why_it_stands_still_and_strict_skills_let_it_shoot(ui, page):
    """The obvious player froze with "KickTowardGoal 1.00" on screen and no word why. Now the decision is
    followed by what the skill did, the idle countdown runs, and the game says why it ended."""
    session = session_of(ui)
    page.get_by_role("tab", name="Play").click()
    choose(page, "Skills", "sighted", exact=True)
    wait_until(lambda: session.game.config.skills == "sighted")
    page.get_by_role("button", name="Play").click()
    page.get_by_role("tab", name="Rules").click()
    choose(page, "Example", "Two-rule striker")
    page.locator(".example-note", has_text="knows where the goal is only while it sees it").wait_for()
    wait_until(lambda: session.game.name == "Two-rule striker")
    page.get_by_role("tab", name="Play").click()
    refused = page.locator('.outcome[data-refused="true"]', has_text="no kick, the goal is not in view")
    refused.wait_for()
    page.locator(".idle").wait_for()
    shot(page, "teacher-1-striker-frozen-explained")
    over = page.locator('.game-over[data-reason="idle"]')
    over.wait_for()
    assert "neither moved nor kicked for 100 ticks" in over.inner_text()
    assert "goal is not in view" in over.inner_text()  # what it last tried
    shot(page, "teacher-2-striker-game-over")

    choose(page, "Skills", "strict", exact=True)
    page.locator('.skills-note[data-skills="strict"]').wait_for()
    wait_until(lambda: session.game.config.skills == "strict" and session.game.name == "Two-rule striker")
    wait_until(lambda: session.game.state.goals >= 1, timeout=120)
    assert session.game.rulebase == session.game.rulebase  # the same rules, only the skills changed
    shot(page, "teacher-3-striker-scores-with-strict-skills")
    choose(page, "Skills", "sighted", exact=True)  # the next tests expect the app's default
    wait_until(lambda: session.game.config.skills == "sighted")


def test_nothing_is_drawn_off_the_grass(ui, page):
    """The view cone reached past the pitch onto the page. Around the grass every pixel is the stadium's
    colour, while the player turns at every place of several starts (the cone sweeps every way)."""
    session = session_of(ui)
    page.get_by_role("tab", name="Rules").click()
    choose(page, "Example", "Does nothing useful")  # it only hunts: turns in place, the cone sweeps
    wait_until(lambda: session.game.name == "Does nothing useful")
    page.get_by_role("tab", name="Play").click()
    page.get_by_role("button", name="Play").click()
    canvas = page.locator("canvas").first
    checked = 0
    for start in range(4):
        page.get_by_role("button", name="New random start").click()
        for _ in range(3):
            before = session.game.state.tick
            wait_until(lambda: session.game.state.tick >= before + 4 or session.game.done)
            image = _pixels(canvas.screenshot())
            off = _drawn_off_the_grass(image)
            assert off == 0, f"{off} pixels drawn beyond the grass (start {start})"
            checked += 1
    shot(page, "teacher-4-nothing-off-the-grass")
    assert checked == 12


def _pixels(png: bytes) -> np.ndarray:
    from matplotlib.image import imread

    return np.rint(imread(io.BytesIO(png), format="png")[..., :3] * 255).astype(int)


def _near(image: np.ndarray, colour: tuple[int, int, int]) -> np.ndarray:
    return (np.abs(image - np.array(colour)).max(axis=-1) <= COLOUR_TOLERANCE)


def _drawn_off_the_grass(image: np.ndarray) -> int:
    """Pixels outside the grass's rectangle (the bounding box of the grass colours) not of the stadium's colour."""
    grass = _near(image, style.GRASS) | _near(image, style.GRASS_STRIPE)
    rows, columns = np.flatnonzero(grass.any(axis=1)), np.flatnonzero(grass.any(axis=0))
    assert len(rows) and len(columns), "no grass on the canvas"
    inside = np.zeros(grass.shape, dtype=bool)
    inside[rows[0] - 1: rows[-1] + 2, columns[0] - 1: columns[-1] + 2] = True  # a pixel of blended edge
    stadium = _near(image, style.STADIUM)
    return int((~inside & ~stadium).sum())


def test_number_fields_show_what_the_server_uses(ui, page):
    """A number field showed nothing after "abc" while the server kept 10^9 and used it on Start. Whatever is
    typed, the field shows it and the server either uses exactly that number or names the problem and the limit."""
    session = session_of(ui)
    page.get_by_role("tab", name="Evolve").click()
    page.get_by_text("GA parameters (chapter's Table 2)").click()
    fields = {handle.label: handle for handle in session.evolve.inputs.values() if hasattr(handle, "needs")}
    run_seed = "Run seed (empty: a new one each run)"
    assert {"Population size", "Generations (max)", "Mutation rate (per gene)", run_seed} <= set(fields)
    typed = ["abc", "", "1000000000", "-3", "2.5", "12", "1e3", " 7 "]
    rng = random.Random(5)
    for label in ("Population size", "Generations (max)", "Mutation rate (per gene)", run_seed):
        for text in rng.sample(typed, 5):
            box = field(page, label, "input")
            box.fill(text)
            box.press("Tab")
            server = fields[label]
            wait_until(lambda: server.text.value == text)
            shown = box.input_value()
            assert shown == text  # the field keeps what was typed: nothing silently replaced or blanked
            if label == run_seed and not shown.strip():
                assert server.problem is None and server.value is None  # empty: the run draws a fresh seed
            elif server.problem is None:
                assert float(shown) == server.value  # the server uses exactly the number shown
            else:
                assert label in server.problem and "expected" in server.problem
                problem = page.locator(".field-problem", has_text=label)
                problem.wait_for()
    field(page, "Population size", "input").fill("abc")
    page.get_by_role("button", name="Start").click()
    refusal = page.locator('.evolve-status[data-error="true"]', has_text="Population size")
    refusal.wait_for()
    assert "expected a whole number ≥ 2" in refusal.inner_text()
    shot(page, "teacher-5-a-number-the-server-cannot-use")
    for label, default in (("Population size", "200"), ("Generations (max)", "25"),
                           ("Mutation rate (per gene)", "0.1"), (run_seed, "")):  # the next tests' defaults
        field(page, label, "input").fill(default)
        wait_until(lambda: fields[label].problem is None)


def test_output_set_labels_never_overlap(ui, page):
    """"SlightlyLow 1.00" was drawn over "MediumPower 1.00": neighbouring clipped sets' labels take rows."""
    session = session_of(ui)
    page.get_by_role("tab", name="Rules").click()
    field(page, "Rules", "textarea").fill(
        # One premise, true wherever the player runs (the ball is never 100 m away): all four sets are clipped
        # alike, the case that overlapped.
        "if Ball is not VeryFar then Dash SlightlyLow\nif Ball is not VeryFar then Dash MediumPower\n"
        "if Ball is not VeryFar then Dash SlightlyHigh\nif Ball is not VeryFar then Dash Low")
    page.get_by_role("button", name="Apply").click()
    wait_until(lambda: session.game.name == "edited")
    pause(page)
    page.get_by_role("tab", name="Inference").click()
    labels = page.locator(".set-label")
    wait_until(lambda: labels.count() >= 3)
    boxes = labels.evaluate_all("els => els.map(e => { const r = e.getBoundingClientRect(); "
                                "return [r.left, r.top, r.right, r.bottom]; })")
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            apart = a[2] <= b[0] or b[2] <= a[0] or a[3] <= b[1] or b[3] <= a[1]
            assert apart, f"labels overlap: {a} {b}"
    shot(page, "teacher-6-output-labels-apart")
    page.get_by_role("button", name="Play").click()
