"""The panels stand on their own: each gets the data it shows and narrow callbacks, never the session.
Built on a real viser server (no browser); their buttons' work is called directly."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.printer import format_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from tests.app.test_ui_browser import free_port

PANELS = Path(__file__).resolve().parents[2] / "app" / "web" / "ui" / "panels"
VOCABULARY = Vocabulary.default()
DEMO = parse_rulebase("if Ball is At then KickTowardGoal High\nif Ball is not At then GoToBall VeryHigh", VOCABULARY)


@pytest.fixture(scope="module")
def gui():
    import viser

    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    yield server.gui
    server.stop()


@pytest.fixture
def store(tmp_path):
    from soccer_lab.app.store import Store

    store = Store(tmp_path / "db.sqlite3")
    yield store
    store.close()


def test_no_panel_imports_the_session():
    for path in PANELS.glob("*.py"):
        imported = {node.module for node in ast.walk(ast.parse(path.read_text())) if isinstance(node, ast.ImportFrom)}
        assert "soccer_lab.app.web.ui.session" not in imported, f"{path.name} reaches into the session"


def test_editor_applies_undoes_and_saves_through_its_callbacks(gui, store):
    from soccer_lab.app.web.ui.panels.editor import EDITED_NAME, EditorPanel

    applied, saved = [], []
    editor = EditorPanel(gui, VOCABULARY, store, (DEMO, "demo"), on_apply=lambda r, n: applied.append((r, n)),
                         on_example=lambda r, n: None, on_saved=lambda: saved.append(True),
                         simplify=lambda rulebase, games: None)
    editor.text.value = "if Ball is Near then Turn Left"
    editor.apply()
    (rulebase, name), = applied
    assert name == EDITED_NAME and format_rulebase(rulebase, VOCABULARY) == "if Ball is Near then Turn Left"
    editor.show_rulebase(rulebase, name)  # what the session does once it is on the pitch
    editor.undo()
    assert applied[-1] == (DEMO, "demo")
    editor.save_name.value = "turner"
    editor.save()
    assert saved == [True]
    assert [r.name for r in store.list_rulebases()] == ["turner"]
    assert store.list_rulebases()[0].text.strip() == "if Ball is Near then Turn Left"


def test_editor_with_an_error_calls_nothing(gui, store):
    from soccer_lab.app.web.ui.panels.editor import EditorPanel

    applied = []
    editor = EditorPanel(gui, VOCABULARY, store, (DEMO, "demo"), on_apply=lambda r, n: applied.append(n),
                         on_example=lambda r, n: None, on_saved=lambda: None, simplify=lambda rulebase, games: None)
    editor.text.value = "if Ball is Nearish then Turn Left"
    editor.apply()
    assert applied == [] and 'data-error="true"' in editor.message.content


def test_editor_plays_a_picked_example_with_its_sentence(gui, store):
    from soccer_lab.app.web.ui.panels.editor import PICK_EXAMPLE, EditorPanel
    from soccer_lab.soccer.examples import example

    played = []
    editor = EditorPanel(gui, VOCABULARY, store, (DEMO, "demo"), on_apply=lambda r, n: None,
                         on_example=lambda r, n: played.append((r, n)), on_saved=lambda: None,
                         simplify=lambda rulebase, games: None)
    striker = example("striker")
    assert editor.example.value == PICK_EXAMPLE and set(editor.example.options) > {striker.title}
    editor.example.value = striker.title  # as a pick from the browser
    assert played == [(striker.rulebase(VOCABULARY), striker.title)]
    editor.show_rulebase(*played[0])  # the session shows it on the pitch: the note stays
    assert "sighted" in editor.example_note.content and editor.example.value == striker.title


def test_editor_forgets_its_message_when_other_rules_go_on_the_pitch(gui, store):
    """"Applied 2 rules" must not stay on screen after "Load best" put another player on the pitch."""
    from soccer_lab.app.web.ui.panels.editor import EditorPanel

    editor = EditorPanel(gui, VOCABULARY, store, (DEMO, "demo"), on_apply=lambda r, n: None,
                         on_example=lambda r, n: None, on_saved=lambda: None, simplify=lambda rulebase, games: None)
    editor.text.value = "if Ball is Near then Turn Left"
    editor.apply()
    assert "Applied 1 rule;" in editor.message.content
    editor.show_rulebase(DEMO, "run #1 best (gen 3, fitness 0.250)")
    assert editor.message.content == "" and editor.example_note.content == ""


def test_library_opens_a_saved_rulebase_through_on_load(gui, store, tmp_path):
    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.web.ui.panels.library import LibraryPanel

    record = store.create_rulebase("striker", format_rulebase(DEMO, VOCABULARY))
    loaded = []
    library = LibraryPanel(gui, store, RunManager(store, tmp_path), VOCABULARY, None,
                           on_load=lambda r, n, run_id: loaded.append((format_rulebase(r, VOCABULARY), n, run_id)))
    assert library.rulebases.value == f"#{record.id} striker"
    library.open_rulebase()
    assert loaded == [(format_rulebase(DEMO, VOCABULARY), "striker", None)]  # no run: the app's game


def test_library_watches_a_runs_best_naming_the_run(gui, store, tmp_path):
    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.web.ui.panels.library import LibraryPanel
    from tests.app.api_client import SHORT_GAMES, TINY_GA

    runs = RunManager(store, tmp_path)
    record = runs.start("assisted", TINY_GA, {**SHORT_GAMES, "skills": "assisted"})
    runs.wait(record.id, timeout=120)
    loaded = []
    library = LibraryPanel(gui, store, runs, VOCABULARY, None, on_load=lambda r, n, run_id: loaded.append(run_id))
    library.refresh()
    assert library.runs.value.startswith(f"#{record.id} ")
    library.watch_run()
    assert loaded == [record.id]  # the session plays it in the run's game (runs.pitch_game)
    runs.shutdown()


def test_policy_map_redraws_for_a_control_change_and_a_new_rulebase(gui):
    from soccer_lab.app.web.ui.panels.policy_view import PolicyPanel

    redraws = []
    policy = PolicyPanel(gui, VOCABULARY, DEMO, 45.0, on_change=lambda: redraws.append(True))
    inputs = {"ball_distance": 5.0, "ball_direction": 0.0, "goal_distance": 30.0, "goal_direction": 0.0}
    policy.show_current(inputs)
    first = policy.map.content
    assert "GoToBall" in first
    policy.show_rulebase(parse_rulebase("if Ball is not At then Turn Left", VOCABULARY))
    policy.output.value = "direction"  # the user picks another output: the panel asks for a redraw
    assert redraws == [True]
    policy.show_current(inputs)  # the redraw it asked for, however soon it comes
    assert "Turn" in policy.map.content and "GoToBall" not in policy.map.content


def test_library_lists_newest_first_and_selects_what_was_just_made(gui, store, tmp_path):
    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.web.ui.panels.library import LibraryPanel

    first = store.create_rulebase("first", format_rulebase(DEMO, VOCABULARY))
    library = LibraryPanel(gui, store, RunManager(store, tmp_path), VOCABULARY, None, on_load=lambda *_: None)
    assert library.rulebases.value == f"#{first.id} first"
    second = store.create_rulebase("second", format_rulebase(DEMO, VOCABULARY))
    library.refresh()
    assert library.rulebases.options == (f"#{second.id} second", f"#{first.id} first")
    assert library.rulebases.value == f"#{second.id} second"
    library.rulebases.value = f"#{first.id} first"  # the user picks the older one and renames it
    store.update_rulebase(first.id, name="renamed")
    library.refresh()
    assert library.rulebases.value == f"#{first.id} renamed"


def test_policy_map_controls_show_the_goal_inputs_the_map_is_drawn_for(gui):
    """Following the player, the "Goal in view" box and the sliders show the player's goal inputs (and cannot be
    changed): the caption never says "Goal out of view" beside a ticked "Goal in view"."""
    from soccer_lab.app.web.ui.panels.policy_view import PolicyPanel

    policy = PolicyPanel(gui, VOCABULARY, DEMO, 45.0, on_change=lambda: None)
    assert policy.follow.value and policy.goal_visible.disabled and policy.goal_distance.disabled
    unseen = {"ball_distance": 5.0, "ball_direction": 0.0, "goal_distance": None, "goal_direction": None}
    policy.show_current(unseen)
    assert policy.goal_visible.value is False and "Goal out of view" in policy.map.content
    policy._last_render = 0.0  # the map redraws at most every POLICY_REFRESH_SECONDS
    policy.show_current({**unseen, "goal_distance": 29.6, "goal_direction": -10.2})
    assert policy.goal_visible.value is True and (policy.goal_distance.value, policy.goal_direction.value) == (30, -10)
    assert "Goal in view at 30 m, -10°" in policy.map.content


def test_evolve_panel_shows_best_so_far_beside_each_generation_s_best(gui, store, tmp_path):
    """The live "best" jumped 0.25 -> 0.5 -> 0.167 (each generation's best) and the end message's "best
    0.167" contradicted the last point: both are shown and named, in the plot, the status and the end."""
    from soccer_lab.app.runs.environments import default_workers
    from soccer_lab.app.runs.manager import RunEvent, RunManager
    from soccer_lab.app.store import RunStatus
    from soccer_lab.app.web.ui.panels.evolve import RCSSSERVER, SIMPLESOCCER, EvolvePanel
    from soccer_lab.ga.statistics import GenerationStats

    panel = EvolvePanel(gui, RunManager(store, tmp_path), store, on_load=lambda *_: None,
                        on_generation=lambda *_: None, on_run_ended=lambda *_: None, on_runs_changed=lambda: None)
    assert panel.inputs["workers"].value == default_workers()  # as the CLI: every core
    assert not panel.servers.visible  # the rcssservers field is for runs on rcssserver only
    panel.where.value = RCSSSERVER
    assert panel.servers.visible
    panel.where.value = SIMPLESOCCER
    assert not panel.servers.visible
    panel.run_id, panel.total_generations = 7, 4
    for generation, best in enumerate((0.25, 0.5, 0.167, 0.3)):
        stats = {**dict.fromkeys(GenerationStats.field_names(), 0), "generation": generation, "best": best,
                 "mean": 0.8, "evaluations": 10 * (generation + 1)}  # a generation's whole statistics
        panel._on_event(RunEvent(7, RunStatus.RUNNING, stats, best))
    generations, best, best_so_far, mean = (list(series) for series in panel.plot.data)
    assert best == [0.25, 0.5, 0.167, 0.3] and best_so_far == [0.25, 0.25, 0.167, 0.167]
    labels = [series["label"] for series in panel.plot.series]
    assert labels[1:] == ["best of the generation 0.300", "best so far 0.167", "mean 0.800"]
    for plot in (panel.plot, panel.diversity.plot):  # generation ticks are whole numbers (a class saw "0.2")
        steps = plot.axes[0]["incrs"]
        assert steps[0] == 1 and all(float(step).is_integer() for step in steps)
    assert "best so far 0.167; this generation: best 0.300" in panel.status.content
    panel._on_event(RunEvent(7, RunStatus.FINISHED))
    assert ("finished after generation 3 — best so far 0.167 (generation 2); the last generation&#x27;s best 0.300"
            in panel.status.content)


def test_evolve_shows_the_progress_within_a_generation_and_stops_it(gui, store, tmp_path):
    """Beside the generation bar: players evaluated of the population, from the run's own progress; Stop
    is obeyed within the generation (issue 22)."""
    import threading
    import time

    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.store import RunStatus
    from soccer_lab.app.web.ui.panels.evolve import EvolvePanel

    runs = RunManager(store, tmp_path)
    ended = threading.Event()
    panel = EvolvePanel(gui, runs, store, on_load=lambda *a: None, on_generation=lambda *a: None,
                        on_run_ended=lambda run_id, status: ended.set(), on_runs_changed=lambda: None,
                        api_url="http://127.0.0.1:8000")
    panel.inputs["population_size"].value = 3000  # generation 0 lasts seconds: the stop lands inside it
    panel.start()
    try:
        # The run on show links to rerun's viewer, served by the app, opening this run's recording.
        assert (f'href="http://127.0.0.1:8000/viewer/?hide_welcome_screen&amp;url=http://127.0.0.1:8000/api/runs/'
                f'{panel.run_id}/recording.rrd"') in panel.viewer.content
        deadline = time.monotonic() + 120
        while "players evaluated" not in panel.within.content and time.monotonic() < deadline:
            time.sleep(0.05)
        assert "Generation 0:" in panel.within.content and "of 3,000 players evaluated" in panel.within.content
        panel.stop()
        assert ended.wait(30)
        assert store.get_run(panel.run_id).status is RunStatus.STOPPED and not store.statistics(panel.run_id)
        assert panel.within.content == ""
    finally:
        panel.close()
        runs.shutdown()


def test_the_viewer_link_says_why_when_the_app_has_no_viewer():
    """serve starts without rerun's viewer when it cannot set it up (and prints why): the UI then says why
    instead of linking to a page that would answer 404."""
    from soccer_lab.app.web.ui.panels.viewer_link import run_viewer_link

    link = run_viewer_link("http://127.0.0.1:8000", 3)
    assert 'href="http://127.0.0.1:8000/viewer/' in link and "Open run #3" in link
    problem = run_viewer_link("http://127.0.0.1:8000", 3, "no <rerun> CLI found")
    assert "<a " not in problem and "not available here: no &lt;rerun&gt; CLI found" in problem
    assert run_viewer_link(None, 3) == ""
