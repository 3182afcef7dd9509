"""The population view's true quality in headless Chromium at a classroom projector's 1280 x 800: said once in
a small caption, re-played for the whole grid by its button (in the panel, and in the projector view above its
larger grid), shown under every pitch in both views. Screenshots go to artifacts/screenshots/."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from soccer_lab.app.runs.true_quality import TRUE_QUALITY_STARTS, simple_soccer_batch_replayer
from soccer_lab.app.web.ui import style
from tests.app.test_ui_browser import CHROMIUM, browser, field, shot, ui, wait_until  # noqa: F401
from tests.app.test_ui_projector_browser import PROJECTOR_SIZES, band_tab, open_tab

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(shutil.which(CHROMIUM) is None and not Path(CHROMIUM).exists(),
                       reason=f"Chromium not installed at {CHROMIUM} (scripts/test installs it with apt)"),
]
GRID = style.POPULATION_GRID[0] * style.POPULATION_GRID[1]


def replayed_lines(page, grid: str) -> list[str]:
    """The line under each small pitch of `grid`, read in one script (the grid is redrawn at 10 Hz)."""
    return page.evaluate("s => [...document.querySelectorAll(s + ' .mini-pitch')].map("
                         "(cell) => (cell.querySelector('.replayed') || {innerText: ''}).innerText.trim())", grid)


def test_population_grid_says_not_replayed_once_and_its_button_replays_every_pitch(ui, browser, monkeypatch):
    # Re-playing within 5% of the time left every pitch "not re-played" (0 of 12), under each pitch in type as
    # large as a title, in the panel and in the projector view. Now the small caption says it once, the empty
    # pitches say nothing, and "Measure these 12 on 20 fresh starts" gives every pitch its true quality.
    page, session = open_tab(ui, browser, PROJECTOR_SIZES[0])
    # No background share: the grid's figures beyond the first (which measures the cost) are the button's.
    monkeypatch.setattr(ui.context.player_qualities, "share", 0.0)
    try:
        page.get_by_role("tab", name="Evolve").click()
        page.get_by_text("GA parameters (chapter's Table 2)").click()
        field(page, "Population size", "input").fill("30")
        field(page, "Generations (max)", "input").fill("2")
        # A fixed seed: a fresh one's best 12 sometimes hold a chromosome that decodes to no rule, and the grid
        # shows only players (the lesson plan says so); seed 0's are 12 playable players, a full grid.
        field(page, "Run seed (empty: a new one each run)", "input").fill("0")
        field(page, "Run seed (empty: a new one each run)", "input").press("Tab")
        wait_until(lambda: session.evolve.config()["population_size"] == 30
                   and session.evolve.config()["max_generations"] == 2
                   and session.evolve.config().get("seed") == 0)
        page.get_by_role("button", name="Start").click()
        wait_until(lambda: "finished" in page.locator(".evolve-status").first.inner_text(), timeout=300)
        page.get_by_role("tab", name="Population").click()
        caption = page.locator(".population-caption")
        wait_until(lambda: caption.count() and caption.get_attribute("data-ended") == "true"
                   and caption.get_attribute("data-replaying") == "false", timeout=120)
        run_id, _, players = session.population.shown_players()
        assert len(players) == GRID
        wait_until(lambda: len(replayed_lines(page, ".population")) == GRID)
        before = replayed_lines(page, ".population")
        shot(page, "population-before-replay-1280x800")
        assert sum(line.startswith("re-played ") for line in before) <= 1, before
        assert not any(line and not line.startswith("re-played ") for line in before), before  # the rest: silent
        body = page.locator("body").inner_text()
        assert "not re-played" not in body
        assert re.search(rf"[01] of {GRID} so far; the button measures the rest \(\d+ games, about",
                         caption.inner_text())
        assert float(page.evaluate("() => parseFloat(getComputedStyle("
                                   "document.querySelector('.population-caption')).fontSize)")) <= style.FONT_SIZE - 2

        label = f"Measure these {GRID} on {TRUE_QUALITY_STARTS} fresh starts"
        button = page.get_by_role("button", name=label)
        assert button.is_enabled()

        # The projector view: the larger pitches silent too, and the same button above them (the teacher
        # measures without leaving the view).
        page.keyboard.press("p")
        page.locator(".projector-status").wait_for()
        band_tab(page, "Population").click()
        wait_until(lambda: len(replayed_lines(page, ".projector-population")) == GRID, timeout=60)
        assert not any(line and not line.startswith("re-played ")
                       for line in replayed_lines(page, ".projector-population"))
        shot(page, "projector-population-before-replay-1280x800")
        visible = [b for b in page.get_by_role("button", name=label).all() if b.is_visible()]
        assert len(visible) == 1  # the projector's: the panel's is folded away
        visible[0].click()
        wait_until(lambda: all(line.startswith("re-played ")
                               for line in replayed_lines(page, ".projector-population")), timeout=180)
        wait_until(lambda: not any(b.is_visible() for b in page.get_by_role("button", name=label).all()))
        cells = page.evaluate("() => [...document.querySelectorAll('.projector-population .mini-pitch')]"
                              ".map((cell) => cell.getBoundingClientRect().bottom)")
        assert max(cells) <= PROJECTOR_SIZES[0]["height"], "a small pitch below the window"
        shot(page, "projector-population-replayed-1280x800")
        page.keyboard.press("p")
        wait_until(lambda: not session.projector.on)

        # Back in the panel: every pitch shows its true quality, the button is gone (nothing left to re-play).
        wait_until(lambda: all(line.startswith("re-played ") for line in replayed_lines(page, ".population")),
                   timeout=60)
        assert not button.is_visible()
        assert caption.get_attribute("data-replayed") == str(GRID) and "so far" not in caption.inner_text()
        shot(page, "population-after-replay-1280x800")
        # Each figure is the player's own: re-played on the common starts, as every run's best is.
        expected = simple_soccer_batch_replayer(session.population.game, ui.context.vocabulary)(
            [p.rulebase for p in players])
        shown = page.evaluate("() => [...document.querySelectorAll('.population .replayed')].map("
                              "(line) => parseFloat(line.dataset.replayed))")
        assert shown == pytest.approx([q.fitness for q in expected], abs=1e-6)
        assert session.population.shown_players()[0] == run_id
    finally:
        session.evolve.stop()
        page.close()
