"""docs/teaching/index.md walked minute by minute in headless Chromium at a projector's 1280 x 800, each claim
the page makes asserted as a teacher would check it. Minutes 7-10 (an evolution, the population grid, rule
usage) are walked by tests/app/test_ui_browser.py (test_a_small_evolution_..., test_stepping_...) and
test_ui_usage.py; the projector view by test_ui_projector_browser.py. Screenshots go to artifacts/screenshots/."""

from __future__ import annotations

import shutil
import time
from pathlib import Path

import pytest

from soccer_lab.app.web.ui import style
from tests.app.test_ui_browser import (CHROMIUM, browser, choose, field, session_of, shot,  # noqa: F401 (fixtures)
                                       tick, ui, wait_until)
from tests.app.test_ui_projector_browser import open_tab, seed_start

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(shutil.which(CHROMIUM) is None and not Path(CHROMIUM).exists(),
                       reason=f"Chromium not installed at {CHROMIUM} (scripts/test installs it with apt)"),
]
GUIDE = Path(__file__).resolve().parents[2] / "docs" / "teaching" / "index.md"
PROJECTOR = {"width": 1280, "height": 800}


def test_the_lesson_plan_works_as_written(ui, browser):
    guide = GUIDE.read_text()
    page, session = open_tab(ui, browser, PROJECTOR)
    try:
        # Minute 0-1: "Press **Pause** (Play tab, left)": the game stops.
        assert "Press **Pause** (Play tab, left)" in guide
        page.get_by_role("tab", name="Play").click()
        page.get_by_role("button", name="Pause").click()
        wait_until(lambda: not session.playing)
        paused = tick(page)
        time.sleep(1.0)
        assert tick(page) == paused == session.game.state.tick

        # Minute 1-3: the Inference tab shows the four inputs; **Step one tick** moves the player and the degrees.
        assert "scroll to the four inputs" in guide and "Press **Step one\ntick**" in guide
        page.get_by_role("tab", name="Inference").click()
        inputs = page.locator(".membership-input")
        wait_until(lambda: inputs.count() == 4)
        page.get_by_role("tab", name="Play").click()
        page.get_by_role("button", name="New random start").click()
        wait_until(lambda: session.game.state.tick == 0)
        before = inputs.first.inner_html()
        player = session.game.state.player
        for clicks in range(1, 4):
            page.get_by_role("button", name="Step one tick").click()
            wait_until(lambda: tick(page) == clicks)
        assert inputs.first.inner_html() != before and session.game.state.player != player

        # Minute 3-4: every rule shows its strength; "Only rules that fired" keeps only those above 0.
        assert "Tick **Only rules that fired**" in guide
        rules = page.locator(".rule")
        wait_until(lambda: rules.count() == len(session.game.rulebase))
        field(page, "Only rules that fired", "input").check()
        fired = sum(1 for strength in session.game.state.strengths if strength > 0)
        wait_until(lambda: rules.count() == fired)
        assert page.locator('.rule[data-fired="false"]').count() == 0
        shot(page, "lesson-3-only-fired")
        field(page, "Only rules that fired", "input").uncheck()

        # Minute 4-5: the chosen action's output sets with the mean of maximum marked.
        assert "**mean of maximum**" in guide
        page.get_by_text("mean of max").first.wait_for()

        # Minute 5-6: the decision, then "Then in the world:"; the striker under sighted skills stands at the ball,
        # says why, counts idle ticks, ends with its reason and stays ended; strict replays the same start, scores.
        assert "The game stays over, with its reason, until you start the next one" in guide
        assert "the same rules replay the same start" in guide
        page.locator(".decision").wait_for()
        page.locator(".outcome", has_text="Then in the world:").wait_for()
        page.get_by_role("tab", name="Play").click()
        choose(page, "Skills", "sighted", exact=True)
        page.get_by_role("tab", name="Rules").click()
        choose(page, "Example", "Two-rule striker")
        wait_until(lambda: session.game.name == "Two-rule striker")
        page.get_by_role("tab", name="Play").click()
        page.get_by_role("button", name="Play").click()
        page.locator('.outcome[data-refused="true"]', has_text="no kick, the goal is not in view").wait_for()
        page.locator(".idle").wait_for()
        with session.lock:
            session.controls.speed.value = 20.0  # the end sooner
        over = page.locator('.game-over[data-reason="idle"]')
        over.wait_for()
        seed = session.game.seed
        time.sleep(4.0)
        assert over.is_visible() and session.game.done and session.game.seed == seed
        page.get_by_role("button", name="Pause").click()
        wait_until(lambda: not session.playing)
        start = seed_start(session)
        choose(page, "Skills", "strict", exact=True)
        wait_until(lambda: session.game.config.skills == "strict")
        with session.lock:
            assert session.game.seed == seed and session.game.state.tick == 0
            assert (tuple(session.game.state.player), tuple(session.game.state.ball)) == tuple(map(tuple, start))
        page.get_by_role("button", name="Play").click()
        wait_until(lambda: session.game.state.goals >= 1, timeout=120)
        shot(page, "lesson-5-strict-scores")
        with session.lock:
            session.controls.speed.value = style.DEFAULT_SPEED
        choose(page, "Skills", "sighted", exact=True)

        # Minute 6-7: a rule typed and applied changes the behaviour; a mistake is named by line and column and
        # applies nothing; **Undo** brings the previous rules back; the Chromosome box shows the genes.
        assert "the editor names the line and column" in guide and "**Undo** brings" in guide
        page.get_by_role("tab", name="Rules").click()
        editor = field(page, "Rules", "textarea")
        editor.fill("if Ball is not VeryFar then Turn Right")
        page.get_by_role("button", name="Apply").click()
        wait_until(lambda: session.game.name == "edited")
        turning = session.game.rulebase
        editor.fill("if Ball is Nearish then Turn Left")
        page.get_by_role("button", name="Apply").click()
        message = page.locator('.editor-message[data-error="true"]')
        message.wait_for()
        assert "line 1, column 12" in message.inner_text() and session.game.rulebase is turning
        page.get_by_role("button", name="Undo").click()
        wait_until(lambda: session.game.name == "Two-rule striker")
        page.get_by_text("Chromosome (compact notation)").click()
        genes = field(page, "Genes", "textarea")
        wait_until(lambda: genes.input_value().strip() != "")
        shot(page, "lesson-6-undo")
    finally:
        page.close()
