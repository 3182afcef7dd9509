"""The screenshots of docs/teaching/lineage.md, made the way a teacher would see them: the app started on a
fresh data folder, a class-sized evolution started from the Evolve tab, then the Lineage and Breeding tabs
driven in headless Chromium (the browser tests' helpers, tests/app/test_ui_lineage.py), each picture of
the right-hand panel or the whole page written to docs/images/teaching/.

    .venv/bin/python scripts/lineage_screenshots.py [--population 60] [--generations 10]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from tests.app.test_ui_browser import CHROMIUM, CHROMIUM_ARGS, dismiss_notifications, free_port, pause  # noqa: E402
from tests.app.test_ui_lineage import evolve_in_page, fill, session_of, show_tree  # noqa: E402

IMAGES = ROOT / "docs" / "images" / "teaching"
VIEWPORT = {"width": 1600, "height": 1200}  # tall enough for a 10-generation tree with the player at its foot


def panel(page, path: Path) -> None:
    """The right-hand panel (the tab shown) as it is scrolled."""
    box = page.locator(".lineage:visible, .breeding-step:visible").first.bounding_box()
    page.screenshot(path=str(path), clip={"x": box["x"] - 8, "y": 0, "width": VIEWPORT["width"] - box["x"] + 8,
                                          "height": VIEWPORT["height"]})


def element(page, selector: str, path: Path, attempts: int = 10) -> None:
    """A picture of an element the server replaces as it changes (the small pitches, several times a second)."""
    from playwright.sync_api import Error

    for _ in range(attempts):
        try:
            page.locator(selector).screenshot(path=str(path), timeout=5000)
            return
        except Error:  # replaced while being taken: find it again
            page.wait_for_timeout(200)
    raise RuntimeError(f"{selector} never stayed long enough for a picture")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--population", type=int, default=60)
    parser.add_argument("--generations", type=int, default=10)
    parser.add_argument("--behaviour-seeds", type=int, default=2)
    args = parser.parse_args()
    from playwright.sync_api import sync_playwright

    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.store import Store
    from soccer_lab.app.web.ui import start_ui

    IMAGES.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as data:
        store = Store(Path(data) / "db.sqlite3")
        store.create_rulebase("kick when very near", "if Ball is VeryNear then KickTowardGoal High\n"
                                                     "if Ball is not VeryNear then GoToBall VeryHigh")
        runs = RunManager(store, data)
        handle = start_ui(store, runs, port=free_port())
        try:
            with sync_playwright() as playwright:
                browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
                page = browser.new_page(viewport=VIEWPORT)
                page.set_default_timeout(120_000)
                page.goto(handle.url)
                page.locator(".game-status").wait_for()
                dismiss_notifications(page)
                session = session_of(handle)
                run = evolve_in_page(page, session, args.population, args.generations, args.behaviour_seeds)
                page.get_by_text("GA parameters (chapter's Table 2)").click()  # folded again, the plots in view
                page.wait_for_timeout(1500)  # the folder's closing animation over
                page.screenshot(path=str(IMAGES / "lineage-evolve-diversity.png"), clip={
                    "x": 0, "y": 0, "width": 400, "height": VIEWPORT["height"]})
                last = args.generations - 1
                show_tree(page, "Best of a generation", Generation=last)
                page.locator(f".lineage[data-generation='{last}']").wait_for()
                panel(page, IMAGES / "lineage-family-tree.png")
                page.locator(".lineage-rule").first.evaluate("rule => rule.scrollIntoView({block: 'start'})")
                panel(page, IMAGES / "lineage-rules.png")
                page.get_by_role("tab", name="Breeding").click()
                fill(page, "Parents' generation", last)
                fill(page, "Parent B: individual #", 4)
                fill(page, "Seed (the same seed gives the same cuts)", 3)
                page.get_by_role("button", name="Breed").click()
                page.locator(".breeding-step[data-step='1']").wait_for()
                page.get_by_text("Parents, crossover and seed").click()  # the settings fold away
                page.wait_for_timeout(1500)
                page.get_by_role("button", name="Next step").click()
                page.locator(".breeding-step[data-step='2']").wait_for()
                panel(page, IMAGES / "lineage-breeding-cuts.png")
                for step in (3, 4):
                    page.get_by_role("button", name="Next step").click()
                    page.locator(f".breeding-step[data-step='{step}']").wait_for()
                panel(page, IMAGES / "lineage-breeding-mutation.png")
                page.get_by_role("button", name="Next step").click()
                page.locator(".breeding-games .mini-pitch").first.wait_for()
                page.wait_for_timeout(4000)  # the four games under way
                pause(page)  # the small pitches advance with the main one: paused, they hold still for the picture
                page.wait_for_timeout(1000)
                element(page, ".breeding-games", IMAGES / "lineage-breeding-play.png")
                print(f"run #{run}: screenshots in {IMAGES.relative_to(ROOT)}")
                browser.close()
        finally:
            handle.stop()
            runs.shutdown(wait=10)
            store.close()


if __name__ == "__main__":
    main()
