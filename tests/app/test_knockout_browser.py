"""The class knockout in the real `soccer-lab serve --class`, in headless Chromium at 1280 x 800 (issue 39): the
teacher starts a knockout of three entries (short games) from the Class tab; the bracket fills in on the
teacher's and a pupil's screen and in the projector view's Knockout tab; a name typed as HTML stays text and a
long one is cut with "..." inside its box; "Watch this match" plays a match on the pupil's pitch to its stored
score. Screenshots go to artifacts/screenshots/knockout-*.png (the teaching
guide's docs/images/teaching/knockout-*.png are copies of them)."""

from __future__ import annotations

import time

import pytest

from soccer_lab.app.web.ui.projector import LEAVE_LABEL, TOGGLE_LABEL
from soccer_lab.app.web.ui.style import PROJECTOR_CONTROL_FONT_SIZE
from soccer_lab.app.web.ui.panels.knockout import PROJECTOR_BRACKET_FONT_SIZE
from tests.app.test_classroom_serve import (INJECTED, SCREENSHOTS, TIMEOUT_MS, browser, join, join_in_browser,  # noqa: F401
                                            new_page, open_class_tab, served, teacher)
from tests.app.test_ui_browser import field
from tests.app.test_ui_projector_browser import band_tab

pytestmark = pytest.mark.browser
KICKER = "if Ball is At then Kick Straight High\nif Ball is not At then GoToBall VeryHigh"
CHASER = "if Ball is not At then GoToBall VeryHigh\nif Ball is At then Kick Left High"
LONG_NAME = "Bartholomew Featherstonehaugh-Cholmondeley's striker, evolved all weekend"


def shot(page, name: str) -> None:
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SCREENSHOTS / f"{name}.png"))


def fill(page, label: str, value: object) -> None:
    field(page, label, "input").fill(str(value))
    field(page, label, "input").press("Tab")


def open_band_tab(page, name: str, timeout: float = 60.0) -> None:
    """The projector band's tab `name`, once the band has drawn its tabs (a busy machine takes a moment)."""
    deadline = time.monotonic() + timeout
    while True:
        try:
            band_tab(page, name).click()
            return
        except StopIteration:
            if time.monotonic() > deadline:
                shot(page, "knockout-no-band-tab")
                raise AssertionError(f"the projector band has no tab {name!r} after {timeout} s") from None
            time.sleep(0.2)


def test_a_knockout_started_by_the_teacher_shows_on_every_screen_and_the_projector(served, browser):
    from playwright.sync_api import expect

    # Three entries: a pupil whose name is HTML, the teacher's with a long name, and a pupil in the browser
    assert join(served, INJECTED).post("/api/class/entries", json={"text": CHASER}).status_code == 201
    desk_api = teacher(served)
    assert desk_api.post("/api/class/entries", json={"text": KICKER, "name": LONG_NAME}).status_code == 201
    pupil = new_page(browser, 1280, 800)
    join_in_browser(pupil, served, "Grace")
    pupil.wait_for_url(f"{served.url}/")
    pupil.goto(f"{served.url}/ui/")
    open_class_tab(pupil)
    pupil.get_by_role("button", name="Enter the rules on my pitch").click()
    expect(pupil.locator(".class-entries")).to_contain_text("3 entries")
    expect(pupil.locator(".knockout")).to_contain_text("No knockout yet")
    expect(pupil.get_by_role("button", name="Watch this match")).to_have_count(0)  # nothing to watch: not shown

    desk = new_page(browser, 1280, 800)
    desk.goto(f"{served.url}/join.html#teacher={served.teacher_token}")
    desk.wait_for_url(f"{served.url}/")
    desk.goto(f"{served.url}/ui/")
    open_class_tab(desk)
    fill(desk, "Ticks a half", 100)
    fill(desk, "Knockout seed", 7)
    desk.get_by_role("button", name="Start a knockout").scroll_into_view_if_needed()
    shot(desk, "knockout-start")
    desk.get_by_role("button", name="Start a knockout").click()

    # The bracket fills in on both screens: the bye, the semi-final, the final, and its winner
    for page in (desk, pupil):
        expect(page.locator('.knockout[data-status="finished"]').first).to_be_attached(timeout=TIMEOUT_MS)
        expect(page.locator('.knockout-tie[data-state="played"]')).to_have_count(3)
        expect(page.locator(".knockout-message").first).to_contain_text("Knockout 1 finished")
        expect(page.locator(".knockout").first).to_contain_text("seed 7")
        expect(page.locator(".knockout").first).to_contain_text(INJECTED)  # as text
        champion = desk_api.get("/api/class/knockouts/1").json()["champion"]
        expect(page.locator(".knockout-champion").first).to_have_text(f"Winner: {champion}")
        assert page.locator(".knockout img").count() == 0 and page.evaluate("window.pwned") is None
    # A long name stays on its line inside its box, cut with "..." (its whole text on hover)
    long_name = pupil.locator(f'.knockout-player span[title$="{LONG_NAME}"]').first
    assert long_name.evaluate("e => e.scrollWidth > e.clientWidth")
    name_box, tie_box = long_name.bounding_box(), pupil.locator(".knockout-tie").first.bounding_box()
    assert name_box["x"] + name_box["width"] <= tie_box["x"] + tie_box["width"] + 1
    assert not pupil.locator(".knockout-message[data-error=true]").count()
    pupil.locator(".knockout").first.scroll_into_view_if_needed()
    shot(pupil, "knockout-pupil")

    # Any played match watched on the pupil's pitch (the latest chosen: the final's last): the same match, to its
    # score, the names as text
    knockout = desk_api.get("/api/class/knockouts/1").json()
    final = knockout["ties"][-1]
    names = {place["draw"]: place["name"] for place in knockout["draw"]}
    pupil.get_by_role("button", name="Watch this match").click()
    expect(pupil.locator(".knockout-message").first).to_contain_text(
        f"Watching {names[final['a']]} against {names[final['b']]} (Final, tie 1, match 3)")
    status = pupil.locator(".match-status")
    expect(status).to_have_attribute("data-done", "true", timeout=TIMEOUT_MS)
    goals = final["matches"][-1]["goals"]
    expect(status).to_have_attribute("data-goals", f"{goals[0]}-{goals[1]}")
    expect(pupil.locator(".match-name").first).to_contain_text(names[final["a"]])
    assert pupil.locator(".match-status img").count() == 0 and pupil.evaluate("window.pwned") is None
    shot(pupil, "knockout-watch")
    desk.locator(".knockout").first.scroll_into_view_if_needed()
    shot(desk, "knockout-teacher")

    # On the projector: the band's Knockout tab, in large type, every tie in view
    desk.get_by_role("tab", name="Play", exact=True).first.click()  # its button, as the P key clicks it
    desk.get_by_role("button", name=TOGGLE_LABEL).click()
    desk.locator(".projector-status").wait_for()
    open_band_tab(desk, "Knockout")
    projected = desk.locator(f'.knockout[style*="font-size:{PROJECTOR_BRACKET_FONT_SIZE}px"]')
    expect(projected).to_be_visible()
    expect(projected.locator('.knockout-tie[data-state="played"]')).to_have_count(3)
    assert all(projected.locator(".knockout-round").nth(i).is_visible() for i in range(2))
    final = projected.locator(".knockout-round").nth(1).bounding_box()
    assert final["x"] + final["width"] <= 1280 and final["y"] + final["height"] <= 800
    # The match chosen and its button read from the back of the room (viser's 12-13 px before); the way back,
    # the teacher's at the laptop, keeps viser's type
    band_sizes = desk.evaluate("""() => [...document.querySelectorAll('[data-dock-group]:has(.projector-controls) '
        + ':is(.mantine-Button-label, input, select)')].filter((e) => e.offsetParent)
        .map((e) => parseFloat(getComputedStyle(e).fontSize))""")
    assert len(band_sizes) >= 2 and min(band_sizes) >= PROJECTOR_CONTROL_FONT_SIZE, band_sizes
    way_back = desk.get_by_role("button", name=LEAVE_LABEL)
    assert way_back.evaluate("(e) => parseFloat(getComputedStyle(e).fontSize)") < PROJECTOR_CONTROL_FONT_SIZE
    shot(desk, "knockout-projector")
