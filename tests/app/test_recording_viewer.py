"""A run's recording opened in rerun's own web viewer, as `serve` serves it (the app's /viewer/, the recording
from the API), in headless Chromium with every request leaving the machine refused: the blueprint's views are
drawn (the replay on its grass, the fitness curves, and beside them, not over them, the legend naming each
series in its colour), not rerun's automatic grid, and the viewer asks the internet for nothing. The screenshot
goes to artifacts/screenshots/recording-viewer.png (git-ignored).

The viewer draws on a canvas, so the test reads the screenshot's pixels: each view shows up as the
colours only it uses."""

from __future__ import annotations

import threading
import time
from pathlib import Path

import numpy as np
import pytest

from soccer_lab.app.runs.recording import FITNESS_SERIES, GOAL_COLOUR, GRASS_COLOUR, LEGEND_SHARE, PLAYER_COLOUR
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
PLAYER_SHADING = 24  # per channel: the viewer shades a point's disc like a sphere
POLL_SECONDS = 5.0  # longer than a frame: two equal screenshots in a row mean the viewer rests
LEGEND_TEXT_TOLERANCE = 24  # a name's letters are thin: few of their pixels are its colour exactly
LEGEND_TEXT_PIXELS = 10


@pytest.fixture(scope="module")
def recorded_run(tmp_path_factory) -> tuple[Path, dict]:
    """A finished run's folder and its settings."""
    from soccer_lab.app.runs.run import Run, RunSettings

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

    from soccer_lab.app.web.api import create_app
    from soccer_lab.app.web.rerun_viewer import viewer_files
    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.store import RunStatus, Store

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


def fitness_plot_end(image: np.ndarray) -> int:
    """Where the fitness plot ends: the right half's first row, the plot taking 1 share of its width and its
    legend LEGEND_SHARE."""
    width = image.shape[1]
    return width // 2 + int(width / 2 / (1 + LEGEND_SHARE))


def fitness_plot(image: np.ndarray) -> np.ndarray:
    return image[: image.shape[0] // 4, image.shape[1] // 2: fitness_plot_end(image) - 4]


def fitness_legend(image: np.ndarray) -> np.ndarray:
    """The fitness plot's legend view, right of the plot, where none of its lines can be drawn."""
    return image[: image.shape[0] // 4, fitness_plot_end(image) + 4:]


def pixels_near(image: np.ndarray, colour: tuple[int, ...], tolerance: int = COLOUR_TOLERANCE) -> int:
    return int((np.abs(image[..., :3].astype(int) - np.array(colour[:3])) <= tolerance).all(axis=-1).sum())


def test_the_recording_opens_in_the_viewer_as_its_blueprint_lays_it_out(app_url):
    from PIL import Image
    from playwright.sync_api import sync_playwright

    from soccer_lab.app.web.rerun_viewer import recording_link

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
                    # the curves (this run's may all lie on one line, fitness 1: a colour each is not asked)
                    "fitness curves": fitness_pixels(fitness_plot(image)),
                }
                named = {name: pixels_near(fitness_legend(image), colour, LEGEND_TEXT_TOLERANCE)
                         for name, (_, colour) in FITNESS_SERIES.items()}
                if settled and all(count >= ENOUGH_PIXELS for count in drawn.values()) and all(
                        count >= LEGEND_TEXT_PIXELS for count in named.values()):
                    break
                if time.monotonic() > deadline:
                    break
                time.sleep(POLL_SECONDS)
        finally:
            browser.close()
    # Left: the latest generation's replay (grass, the goal, the player); right: the fitness curves.
    assert settled and all(count >= ENOUGH_PIXELS for count in drawn.values()), drawn
    # Beside the fitness plot, not over its lines: its legend's view names each series in its colour. Before,
    # rerun drew the legend in a corner inside the plot.
    assert all(count >= LEGEND_TEXT_PIXELS for count in named.values()), named
    assert asked == [], f"the viewer asked the internet for {asked}"


# What the viewer says in a headless, GPU-less, offline Chromium whatever it opens (no GPU, refused telemetry,
# egui commands a browser cannot do): the machine's, not the recording's. Anything else is a finding.
ENVIRONMENT_MESSAGES = ("Software rasterizer", "No available adapters", "GL Driver Message", "Unhandled egui viewport",
                        "serves rerun's viewer offline", "deprecated parameters for the initialization",
                        'values for "notebook" query', 'values for "persist" query')
VIEWER_SETTLES_SECONDS = 45.0


def _ui_recording(folder: Path) -> Path:
    """A run as the UI's Evolve tab runs it (soccer_lab.app.runs.run.Run, as the run manager does), with replays."""
    from soccer_lab.app.runs.run import Run, RunSettings

    settings = RunSettings.build({"population_size": 12, "max_generations": 4, "max_length": 24, "seed": 5},
                                 {"max_ticks": 300})
    run = Run.create(settings, folder / "run")
    with run.evaluator() as evaluate:
        run.play(evaluate)
    return run.folder.recording


def _cli_recording(folder: Path) -> Path:
    import subprocess
    import sys

    out = folder / "cli-run"
    subprocess.run([sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "evolve", "--out", str(out),
                    "--population-size", "12", "--generations", "4", "--max-ticks", "300", "--seed", "5"],
                   check=True, capture_output=True, timeout=600)
    (recording,) = out.glob("*.rrd")
    return recording


def _experiment_recording(folder: Path) -> Path:
    from soccer_lab.app.experiment.executors import LocalExecutor
    from soccer_lab.app.experiment.presets import ExperimentOptions
    from soccer_lab.app.experiment.runner import run_experiment

    run_experiment("crossover", ExperimentOptions(trials=1, population=6, generations=3, max_ticks=60, seed=7),
                   folder / "experiment", LocalExecutor(1))
    return sorted((folder / "experiment").rglob("*.rrd"))[0]


def width_share(image: np.ndarray, colour: tuple[int, ...]) -> float:
    """How much of the picture's width the pixels of `colour` span."""
    columns = np.flatnonzero((np.abs(image[..., :3].astype(int) - np.array(colour[:3])) <= COLOUR_TOLERANCE)
                             .all(axis=-1).any(axis=0))
    return 0.0 if columns.size == 0 else (columns[-1] - columns[0]) / image.shape[1]


def fitness_pixels(image: np.ndarray) -> int:
    return sum(pixels_near(image, colour) for _, colour in FITNESS_SERIES.values())


RECORDINGS = {"ui": _ui_recording, "cli": _cli_recording, "experiment": _experiment_recording}


@pytest.fixture
def file_server(tmp_path):
    """The app with rerun's viewer, and the test's folder served under /files/ for the viewer to open."""
    import uvicorn
    from starlette.routing import Mount
    from starlette.staticfiles import StaticFiles

    from soccer_lab.app.web.api import create_app
    from soccer_lab.app.web.rerun_viewer import viewer_files
    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.store import Store

    served = tmp_path / "served"
    served.mkdir()
    store = Store(tmp_path / "db.sqlite3")
    port = free_port()
    api_url = f"http://127.0.0.1:{port}"
    app = create_app(store, RunManager(store, tmp_path), api_url=api_url, viewer_files=viewer_files(tmp_path / "viewer"))
    app.router.routes.insert(0, Mount("/files", app=StaticFiles(directory=served)))
    server = uvicorn.Server(uvicorn.Config(app, host="127.0.0.1", port=port, log_level="warning"))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    deadline = time.monotonic() + 30
    while not server.started and time.monotonic() < deadline:
        time.sleep(0.05)
    yield api_url, served
    server.should_exit = True
    thread.join(10)
    store.close()


@pytest.mark.parametrize("source", list(RECORDINGS))
def test_a_recording_opens_in_the_viewer_without_a_warning_and_shows_the_player(file_server, tmp_path, source):
    # Before: every UI and CLI run greeted the viewer with "Blueprint ... has broken references: /container/..."
    # (each blueprint sent into one store), and the replayed player was a pixel or two at the default zoom.
    import shutil as files

    from PIL import Image
    from playwright.sync_api import sync_playwright

    from soccer_lab.app.web.rerun_viewer import recording_link

    api_url, served = file_server
    files.copy(RECORDINGS[source](tmp_path), served / "recording.rrd")
    shot = SCREENSHOTS / f"recording-viewer-{source}.png"
    shot.parent.mkdir(parents=True, exist_ok=True)
    messages: list[str] = []
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport=VIEWPORT)
            offline(page)
            page.on("console", lambda m: messages.append(f"{m.type}: {m.text}") if m.type in ("warning", "error")
                    else None)
            page.goto(recording_link(api_url, f"{api_url}/files/recording.rrd"))
            deadline = time.monotonic() + DRAWN_WITHIN_SECONDS
            while True:  # the viewer loads its wasm, then the recording: wait until the curves are drawn
                page.screenshot(path=str(shot), timeout=SCREENSHOT_TIMEOUT_MS)
                image = np.asarray(Image.open(shot).convert("RGB"))
                if fitness_pixels(image) >= ENOUGH_PIXELS or time.monotonic() > deadline:
                    break
                time.sleep(POLL_SECONDS)
            page.wait_for_timeout(VIEWER_SETTLES_SECONDS * 1000)  # warnings come as the blueprint is checked
            page.screenshot(path=str(shot), timeout=SCREENSHOT_TIMEOUT_MS)
        finally:
            browser.close()
    image = np.asarray(Image.open(shot).convert("RGB"))
    assert fitness_pixels(image) >= ENOUGH_PIXELS
    # The blueprint's layout, not rerun's automatic grid (a small view per series): with replays their grass;
    # without, the fitness plot across the whole width, its "worst" line with it.
    if source == "experiment":
        assert width_share(image, FITNESS_SERIES["worst"][1]) > 0.6
    else:
        assert pixels_near(image, GRASS_COLOUR) >= ENOUGH_PIXELS
    findings = [m for m in messages if not any(known in m for known in ENVIRONMENT_MESSAGES)]
    assert findings == []
    if source != "experiment":  # an experiment's trials record statistics only, no replays
        # a shaded disc 20 points across, not the pixel or two of the player's true size (0.3 m on a 105 m pitch)
        assert pixels_near(image[:, : image.shape[1] // 2], PLAYER_COLOUR, PLAYER_SHADING) >= 60
