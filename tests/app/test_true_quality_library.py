"""Rules saved from a run's best keep both its figures (the one-game fitness the GA saw, its true quality on
the common fresh starts) in the library, the API's rulebase listing and class entries; other rules and
rules edited after saving carry none."""

from __future__ import annotations

import html

import pytest

from soccer_lab.app.runs.outputs import RunFolder, best_of_run, best_of_text, best_record
from soccer_lab.app.runs.true_quality import TRUE_QUALITY_STARTS, simple_soccer_replayer
from soccer_lab.app.store import Store
from soccer_lab.fuzzy.printer import format_rulebase
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.individual import Individual
from soccer_lab.ga.statistics import GenerationStats
from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig
from soccer_lab.soccer.demo import demo_rulebase, demo_rules_text
from tests.app.api_client import SHORT_GAMES, TINY_GA, api_client, wait_for
from tests.app.test_classroom_api import SMALL_RUN, room  # noqa: F401  (the class fixture)

REPLAYED = f"(re-played on {TRUE_QUALITY_STARTS} fresh starts: "
OTHER_RULES = "if Ball is not At then GoToBall VeryHigh"


def finished_run(client) -> tuple[int, dict]:
    run = client.post("/api/runs", json={"name": "tiny", "ga": TINY_GA, "game": SHORT_GAMES}).json()
    wait_for(lambda: client.get(f"/api/runs/{run['id']}").json()["status"] != "running", what="the run to finish")
    return run["id"], client.get(f"/api/runs/{run['id']}/best").json()


def test_a_rulebase_saved_from_a_runs_best_lists_both_its_figures_in_the_api(tmp_path):
    with api_client(tmp_path) as client:
        run_id, best = finished_run(client)
        saved = client.post("/api/rulebases", json={"name": "GA best", "text": best["rules"], "run_id": run_id})
        assert saved.status_code == 201, saved.text
        listed = client.get("/api/rulebases").json()
        assert listed[0]["best_of"] == {"run_id": run_id, "generation": best["generation"],
                                        "fitness_seen": best["fitness"], "true_quality": best["true_quality"]}
        assert best["true_quality"]["starts"] == TRUE_QUALITY_STARTS
        # Other rules claimed to be the run's best are refused, nothing saved; an unknown run is a 404
        refused = client.post("/api/rulebases", json={"name": "not it", "text": OTHER_RULES, "run_id": run_id})
        assert refused.status_code == 422 and f"not run {run_id}'s best" in refused.text
        assert client.post("/api/rulebases", json={"name": "x", "text": OTHER_RULES, "run_id": 999}).status_code == 404
        assert client.post("/api/rulebases", json={"name": "x", "text": OTHER_RULES,
                                                   "run_id": 2 ** 70}).status_code == 422
        assert len(client.get("/api/rulebases").json()) == 1
        plain = client.post("/api/rulebases", json={"name": "mine", "text": OTHER_RULES}).json()
        assert plain["best_of"] is None
        # A rename keeps the figures; new rules are no longer that best's
        record_id = saved.json()["id"]
        assert client.put(f"/api/rulebases/{record_id}", json={"name": "renamed"}).json()["best_of"] is not None
        changed = client.put(f"/api/rulebases/{record_id}", json={"text": OTHER_RULES}).json()
        assert changed["best_of"] is None and client.get(f"/api/rulebases/{record_id}").json()["best_of"] is None


def test_a_damaged_best_of_record_lists_the_rules_without_figures(tmp_path):
    store = Store(tmp_path / "db.sqlite3")
    record = store.create_rulebase("kept", demo_rules_text())
    with store._transaction() as cursor:
        cursor.execute("UPDATE rulebases SET best_of = ? WHERE id = ?", ("{not json", record.id))
    assert store.get_rulebase(record.id).best_of is None and store.get_rulebase(record.id).text == record.text
    assert best_of_text({"run_id": 1}) == ""
    store.close()


def test_a_class_entry_from_the_gas_best_says_both_figures(room):  # noqa: F811
    teacher = room.teacher()
    # seed 1: this small run's best has rules (an entry needs one)
    run = teacher.post("/api/runs", json={"name": "GA", "ga": {**SMALL_RUN["ga"], "seed": 1}, "game": SMALL_RUN["game"]})
    assert run.status_code == 201, run.text
    run_id = run.json()["id"]
    room.runs.wait(run_id, timeout=120)
    best = teacher.get(f"/api/runs/{run_id}/best").json()
    entry = teacher.post("/api/class/entries", json={"run_id": run_id, "name": "GA best"})
    assert entry.status_code == 201, entry.text
    quality = best["true_quality"]
    both = (f"fitness {best['fitness']:.3f} as the GA saw it {REPLAYED}"
            f"{quality['fitness']:.3f} ± {quality['fitness_std']:.3f})")
    assert both in entry.json()["source"]
    # From the library, saved from that best: the same two figures
    saved = teacher.post("/api/rulebases", json={"name": "kept best", "text": best["rules"], "run_id": run_id}).json()
    from_library = teacher.post("/api/class/entries", json={"rulebase_id": saved["id"], "name": "library best"})
    assert from_library.status_code == 201 and both in from_library.json()["source"]
    assert from_library.json()["source"].startswith("library: kept best, run #")


@pytest.fixture
def stored_run(tmp_path):
    """A store with one run whose best (the demo player, seen at 0.25 in one game) was re-played."""
    store = Store(tmp_path / "db.sqlite3")
    record = store.create_run("tiny", {"ga": {}}, tmp_path / "runs" / "{id}")
    best = Individual(ChromosomeCodec(SOCCER_VOCABULARY).encode(demo_rulebase()), evaluations=1, fitness_sum=0.25,
                      goals=1)
    stats = {**dict.fromkeys(GenerationStats.field_names(), 0), "generation": 0, "best": 0.25, "mean": 0.8}
    store.record_generation(record.id, stats, format_rulebase(demo_rulebase(), SOCCER_VOCABULARY), "(B,N,O)", 0.25)
    quality = simple_soccer_replayer(GameConfig(max_ticks=60), SOCCER_VOCABULARY)(demo_rulebase())
    RunFolder.create(record.folder, {"algorithm": "ga"}).write_best_record(best_record(best, 0, quality))
    yield store, record.id, quality
    store.close()


def test_the_library_and_the_editor_keep_a_runs_best_with_both_figures(stored_run, tmp_path):
    """The library once named a run's best by its one-game fitness alone, and saved rules lost it."""
    import viser

    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.web.ui.panels.editor import EditorPanel
    from soccer_lab.app.web.ui.panels.library import LibraryPanel
    from tests.app.test_ui_browser import free_port

    store, run_id, quality = stored_run
    note = f"{REPLAYED}{quality.fitness:.3f} ± {quality.fitness_std:.3f})"
    loaded = []
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    try:
        library = LibraryPanel(server.gui, store, RunManager(store, tmp_path), SOCCER_VOCABULARY, None,
                               on_load=lambda *a: loaded.append(a))
        editor = EditorPanel(server.gui, SOCCER_VOCABULARY, store, (demo_rulebase(), "run #1 best"),
                             on_apply=lambda *_: None, on_example=lambda *_: None, on_saved=library.refresh,
                             simplify=lambda *_: None,
                             best_of=lambda rulebase: best_of_run(store, run_id) if rulebase == demo_rulebase()
                             else None)
        editor.save_name.value = "GA best"
        editor.save()
        saved = store.list_rulebases()[0]
        assert saved.best_of == best_of_run(store, run_id) and saved.best_of["true_quality"] == quality.to_dict()
        assert f"fitness 0.250 as the GA saw it {note}" in editor.message.content
        shown = html.unescape(library.rulebase_figures.content)
        assert f"Saved from run #{run_id}'s best (gen 0): fitness 0.250 as the GA saw it {note}" in shown
        library.open_rulebase()
        assert loaded[-1][0] == demo_rulebase() and note in loaded[-1][1] and loaded[-1][2] is None
        library.runs.value = library.runs.options[0]
        library.watch_run()
        assert f"fitness 0.250 {note}" in loaded[-1][1] and loaded[-1][2] == run_id
        # Rules that are no run's best are saved without figures, and the library shows none
        editor.on_pitch = (demo_rulebase().__class__(demo_rulebase().rules[:1]), "edited")
        editor.save_name.value = "edited"
        editor.save()
        assert store.list_rulebases()[0].best_of is None and library.rulebase_figures.content == ""
    finally:
        server.stop()
