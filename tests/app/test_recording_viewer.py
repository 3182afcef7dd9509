"""A run's recording opened in rerun's own web viewer, as `serve` serves it (the app's /viewer/, the recording
from the API), in headless Chromium with every request leaving the machine refused: the blueprint's views are
drawn (the replay on its grass, the fitness curves in their colours), not rerun's automatic grid, and the
viewer asks the internet for nothing. The screenshot goes to artifacts/screenshots/recording-viewer.png
(git-ignored).

The viewer draws on a canvas, so the test reads the screenshot's pixels: each view shows up as the
colours only it uses."""

from __future__ import annotations

import threading
import time
from pathlib import Path

import numpy as np
import pytest

from app.recording import FITNESS_SERIES, GOAL_COLOUR, GRASS_COLOUR, PLAYER_COLOUR
from tests.app.test_ui_browser import CHROMIUM, CHROMIUM_ARGS, SCREENSHOTS, free_port, offline

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(not Path(CHROMIUM).exists(), reason=f"Chromium not installed at {CHROMIUM} "
                                                           "(scripts/test installs it with apt)"),
]
VIEWPORT = {"width": 1400, "height": 900}
DRAWN_WITHIN_SECONDS = 180.0
SCREENSHOT_TIMEOUT_MS = 60_000  # the viewer renders in software (no GPU in headless Chromium)
COLOUR_TOLERANCE = 12  # per channel: anti-aliased edges blend, the insides of lines and discs do not
ENOUGH_PIXELS = 20
POLL_SECONDS = 5.0  # longer than a frame: two equal screenshots in a row mean the viewer rests


@pytest.fixture(scope="module")
def recorded_run(tmp_path_factory) -> tuple[Path, dict]:
    """A finished run's folder and its settings."""
    from app.run import Run, RunSettings

    folder = tmp_path_factory.mktemp("viewer") / "run"
    settings = RunSettings.build({"population_size": 12, "max_generations": 3, "max_length": 24, "seed": 3},
                                 {"max_ticks": 300})
    run = Run.create(settings, folder)
    with run.evaluator() as evaluate:
        run.play(evaluate)
    return folder, settings.to_dict()


@pytest.fixture
def app_url(recorded_run, tmp_path):
    """The app as serve runs it, with the run in its store: (its address, the run's id)."""
    import uvicorn

    from app.api import create_app
    from app.rerun_viewer import viewer_files
    from app.runs import RunManager
    from app.store import RunStatus, Store

    folder, settings = recorded_run
    store = Store(tmp_path / "db.sqlite3")
    record = store.create_run("viewed", settings, folder)
    store.set_run_status(record.id, RunStatus.FINISHED)
    port = free_port()
    api_url = f"http://127.0.0.1:{port}"
    app = create_app(store, RunManager(store, tmp_path), api_url=api_url, viewer_files=viewer_files(tmp_path / "viewer"))
    server = uvicorn.Server(uvicorn.Config(app, host="127.0.0.1", port=port, log_level="warning"))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    deadline = time.monotonic() + 30
    while not server.started and time.monotonic() < deadline:
        time.sleep(0.05)
    yield api_url, record.id
    server.should_exit = True
    thread.join(10)
    store.close()


def pixels_near(image: np.ndarray, colour: tuple[int, ...]) -> int:
    return int((np.abs(image[..., :3].astype(int) - np.array(colour[:3])) <= COLOUR_TOLERANCE).all(axis=-1).sum())


def test_the_recording_opens_in_the_viewer_as_its_blueprint_lays_it_out(app_url):
    from PIL import Image
    from playwright.sync_api import sync_playwright

    from app.rerun_viewer import recording_link

    api_url, run_id = app_url
    shot = SCREENSHOTS / "recording-viewer.png"
    shot.parent.mkdir(parents=True, exist_ok=True)
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport=VIEWPORT)
            asked = offline(page)  # a school network without internet: the viewer must not need it
            page.goto(recording_link(api_url, f"{api_url}/api/runs/{run_id}/recording.rrd"))
            deadline = time.monotonic() + DRAWN_WITHIN_SECONDS
            previous = None
            while True:  # the viewer loads its wasm, then the recording, then draws: poll the picture
                page.screenshot(path=str(shot), timeout=SCREENSHOT_TIMEOUT_MS)
                image = np.asarray(Image.open(shot).convert("RGB"))
                settled = previous is not None and np.array_equal(image, previous)  # all loaded: it rests
                previous = image
                left, right = image[:, : image.shape[1] // 2], image[:, image.shape[1] // 2:]
                drawn = {
                    "grass": pixels_near(left, GRASS_COLOUR), "player": pixels_near(left, PLAYER_COLOUR),
                    "goal": pixels_near(left, GOAL_COLOUR),
                    **{name: pixels_near(right, colour) for name, (_, colour) in FITNESS_SERIES.items()},
                }
                if settled and all(count >= ENOUGH_PIXELS for count in drawn.values()):
                    break
                if time.monotonic() > deadline:
                    break
                time.sleep(POLL_SECONDS)
        finally:
            browser.close()
    # Left: the latest generation's replay (grass, the goal, the player); right: the fitness curves.
    assert settled and all(count >= ENOUGH_PIXELS for count in drawn.values()), drawn
    assert asked == [], f"the viewer asked the internet for {asked}"
