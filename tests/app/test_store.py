"""The SQLite store: schema version, CRUD, transactions, threads, restarts."""

from __future__ import annotations

import sqlite3
import threading

import numpy as np
import pytest

from soccer_lab.app.store import SCHEMA_VERSION, NotFound, RunStatus, Store, StoreError


@pytest.fixture
def store(tmp_path):
    opened = Store(tmp_path / "db.sqlite3")
    yield opened
    opened.close()


def stats(generation: int, best: float) -> dict:
    return {"generation": generation, "best": best, "mean": best + 0.2}


def test_new_database_has_current_schema_version_and_wal(tmp_path):
    store = Store(tmp_path / "nested" / "db.sqlite3")
    assert store.schema_version == SCHEMA_VERSION >= 1
    store.close()
    connection = sqlite3.connect(tmp_path / "nested" / "db.sqlite3")
    assert connection.execute("PRAGMA user_version").fetchone()[0] == SCHEMA_VERSION
    assert connection.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    connection.close()


def test_database_from_a_newer_version_is_refused_untouched(tmp_path):
    path = tmp_path / "db.sqlite3"
    Store(path).close()
    connection = sqlite3.connect(path)
    connection.execute(f"PRAGMA user_version = {SCHEMA_VERSION + 1}")
    connection.close()
    with pytest.raises(StoreError, match="newer"):
        Store(path)


def test_rulebase_crud(store):
    created = store.create_rulebase("  demo ", "if Ball is At then Kick Straight High\n")
    assert created.name == "demo" and created.created == created.updated
    assert store.get_rulebase(created.id) == created
    renamed = store.update_rulebase(created.id, name="better")
    assert renamed.text == created.text and renamed.name == "better"
    assert renamed.updated >= created.updated
    other = store.create_rulebase("other", "")
    assert [r.id for r in store.list_rulebases()] == [other.id, created.id]  # newest first
    store.delete_rulebase(created.id)
    with pytest.raises(NotFound, match=f"no rulebase with id {created.id}"):
        store.get_rulebase(created.id)
    with pytest.raises(NotFound):
        store.delete_rulebase(created.id)
    with pytest.raises(NotFound):
        store.update_rulebase(created.id, name="x")
    assert [r.id for r in store.list_rulebases()] == [other.id]


@pytest.mark.parametrize("name", ["", "   ", None, 3, "x" * 201])
def test_bad_names_are_refused_and_nothing_changes(store, name):
    saved = store.create_rulebase("kept", "text")
    with pytest.raises(StoreError):
        store.create_rulebase(name, "text")
    if name is not None:  # None in an update means "keep the name"
        with pytest.raises(StoreError):
            store.update_rulebase(saved.id, name=name)
    assert store.list_rulebases() == [saved]


def test_bad_ids_are_not_found_or_refused(store):
    with pytest.raises(NotFound):
        store.get_run(12345)
    with pytest.raises(StoreError):
        store.get_rulebase("1")  # type: ignore[arg-type]


def test_run_lifecycle_generations_and_best(store, tmp_path):
    run = store.create_run("tiny", {"ga": {"population_size": 4}}, tmp_path / "runs" / "{id}")
    assert run.status is RunStatus.RUNNING and run.folder.endswith(f"runs/{run.id}")
    store.record_generation(run.id, stats(0, 0.9), "if Ball is At then Dash High", "(B,A,A) (D,n,H)", 0.9)
    store.record_generation(run.id, {**stats(1, 0.5), "std": np.float64(0.1), "n": np.int64(3)}, "r1", "c1", 0.5)
    store.record_generation(run.id, stats(2, 0.5), "r2", "c2", 0.5)
    assert [s["generation"] for s in store.statistics(run.id)] == [0, 1, 2]
    assert store.statistics(run.id)[1]["n"] == 3
    best = store.best_individual(run.id)
    assert (best.generation, best.rules, best.fitness) == (2, "r2", 0.5)  # ties go to the latest
    store.record_generation(run.id, stats(1, 0.4), "r1 again", "c1", 0.4)  # replayed after a resume
    assert [b.rules for b in store.best_individuals(run.id)] == ["if Ball is At then Dash High", "r1 again", "r2"]
    finished = store.set_run_status(run.id, RunStatus.FINISHED)
    assert finished.status is RunStatus.FINISHED and finished.finished is not None
    store.delete_run(run.id)
    with pytest.raises(NotFound):
        store.statistics(run.id)


def test_best_of_a_run_without_generations_is_not_found(store, tmp_path):
    run = store.create_run("empty", {}, tmp_path)
    with pytest.raises(NotFound, match="best individual"):
        store.best_individual(run.id)


def test_non_finite_statistics_are_stored_as_null(store, tmp_path):
    run = store.create_run("nan", {}, tmp_path)
    store.record_generation(run.id, {"generation": 0, "std": float("nan")}, "r", "c", 1.0)
    assert store.statistics(run.id) == [{"generation": 0, "std": None}]


def test_failed_write_rolls_back_the_whole_generation(store, tmp_path):
    run = store.create_run("r", {}, tmp_path)
    store.record_generation(run.id, stats(0, 0.7), "r0", "c0", 0.7)
    # The statistics row is written first; the best row's bad rule text must undo it.
    with pytest.raises(StoreError):
        store.record_generation(run.id, stats(1, 0.6), None, "c1", 0.6)  # type: ignore[arg-type]
    assert [s["generation"] for s in store.statistics(run.id)] == [0]
    with pytest.raises(StoreError):
        store.record_generation(run.id, {"best": 0.1}, "r", "c", 0.1)
    with pytest.raises(StoreError):
        store.create_run("bad config", {"x": object()}, tmp_path)
    assert [r.id for r in store.list_runs()] == [run.id]


def test_restart_marks_running_runs_interrupted(tmp_path):
    path = tmp_path / "db.sqlite3"
    first = Store(path)
    running = first.create_run("running", {}, tmp_path / "a")
    stopped = first.create_run("stopped", {}, tmp_path / "b")
    first.set_run_status(stopped.id, RunStatus.STOPPED)
    saved = first.create_rulebase("kept", "if Ball is At then DoNothing")
    first.close()
    second = Store(path)
    assert second.mark_interrupted() == [running.id]
    assert second.get_run(running.id).status is RunStatus.INTERRUPTED
    assert second.get_run(running.id).status.resumable
    assert second.get_run(stopped.id).status is RunStatus.STOPPED
    assert second.get_rulebase(saved.id) == saved
    second.close()


def test_concurrent_writers_lose_nothing(store, tmp_path):
    run = store.create_run("threads", {}, tmp_path)
    errors = []

    def write(worker: int) -> None:
        try:
            for i in range(25):
                store.create_rulebase(f"w{worker}-{i}", "")
                store.record_generation(run.id, stats(worker * 100 + i, 1.0), "r", "c", 1.0)
        except Exception as exc:  # collected for the assertion below
            errors.append(exc)

    threads = [threading.Thread(target=write, args=(w,)) for w in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert errors == []
    assert len(store.list_rulebases()) == 100
    assert len(store.statistics(run.id)) == 100


def test_experiments(store):
    record = store.record_experiment("initial", "/tmp/exp", {"trials": 20, "agrees": [True, False]})
    assert store.list_experiments() == [record]
    assert store.get_experiment(record.id).summary == {"trials": 20, "agrees": [True, False]}
    with pytest.raises(NotFound):
        store.get_experiment(record.id + 1)
    # Resumed into the same folder: the entry is updated, not duplicated; another folder is another entry.
    again = store.record_experiment("initial", "/tmp/exp", {"trials": 20, "agrees": [True, True]})
    other = store.record_experiment("initial", "/tmp/exp2", {"trials": 2})
    assert again.id == record.id and again.summary["agrees"] == [True, True]
    assert [e.id for e in store.list_experiments()] == [other.id, record.id]  # newest first
