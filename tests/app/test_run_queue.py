"""Classroom mode's run queue (issue 35, "Every Start is honoured") and fresh run seeds ("Thirty different
players"): real runs in a real RunManager and store, in process. The HTTP side (places in the API, who may
cancel what) is in test_classroom_api.py; the queue on Ray in test_run_games_ray.py."""

from __future__ import annotations

import time

import pytest

from soccer_lab.app.paths import DATABASE_FILE
from soccer_lab.app.runs.run import RunSettings
from soccer_lab.app.runs.queue import QueuedRun, RunPace, RunQueue
from soccer_lab.app.runs.manager import RunManager, RunStateError
from soccer_lab.app.store import RunRecord, RunStatus, Store

TINY = {"population_size": 4, "max_generations": 2, "workers": 1}
SHORT_GAMES = {"max_ticks": 60, "games_per_evaluation": 1}
LONG = {"population_size": 50, "max_generations": 100, "workers": 1}  # minutes: stopped by the test
PUPILS = (11, 12, 13)  # account ids


@pytest.fixture
def store(tmp_path):
    store = Store(tmp_path / DATABASE_FILE)
    yield store
    store.close()


@pytest.fixture
def classroom(store, tmp_path):
    runs = RunManager(store, tmp_path, max_concurrent_runs=2, queue_runs=True)
    yield runs
    for record in store.list_runs():  # stopped, not cut off: no run thread writes to the store once it closes
        if runs.is_pending(record.id):
            runs.stop(record.id)
    runs.shutdown()


def comparable(statistics: list[dict]) -> list[dict]:
    """A run's statistics without wall_time, the one figure a seed does not fix."""
    return [{key: value for key, value in row.items() if key != "wall_time"} for row in statistics]


def test_third_pupil_start_is_queued_not_refused(classroom, store):
    first, second = (classroom.start(ga=LONG, game=SHORT_GAMES, owner=pupil) for pupil in PUPILS[:2])
    third = classroom.start(ga=TINY, game=SHORT_GAMES, owner=PUPILS[2])
    assert third.status is RunStatus.QUEUED and store.get_run(third.id).status is RunStatus.QUEUED
    place = classroom.queue_place(third.id)
    assert (place.position, place.queued) == (1, 1) and place.wait_seconds >= 0 and place.run_seconds > 0
    classroom.stop(first.id)  # a core comes free: the queued run starts on it and plays to its end
    assert classroom.wait(third.id, timeout=120).status is RunStatus.FINISHED
    assert len(store.statistics(third.id)) == 2
    classroom.stop(second.id)


def test_queued_runs_start_in_turn_one_core_each_and_all_finish(store, tmp_path):
    runs = RunManager(store, tmp_path, max_concurrent_runs=1, queue_runs=True)
    started: list[int] = []
    runs.add_listener(lambda event: started.append(event.run_id) if event.status is RunStatus.RUNNING
                      and event.stats is None and event.progress is None else None)
    try:
        records = [runs.start(ga=TINY, game=SHORT_GAMES, owner=pupil) for pupil in PUPILS]
        assert [r.status for r in records] == [RunStatus.RUNNING, RunStatus.QUEUED, RunStatus.QUEUED]
        assert [runs.wait(r.id, timeout=120).status for r in records] == [RunStatus.FINISHED] * 3
        assert started == [r.id for r in records]  # the order they pressed Start in
    finally:
        runs.shutdown()


def test_the_queue_turns_round_robin_across_owners():
    """The teacher (owner None) with two runs waiting does not hold two cores before the pupils' one each."""
    queue = RunQueue()
    settings = RunSettings.build({"population_size": 4, "max_generations": 2}, SHORT_GAMES)
    entries = [(1, None), (2, None), (3, 11), (4, 12)]
    for run_id, owner in entries:
        queue.push(QueuedRun(RunRecord(run_id, "r", {}, RunStatus.QUEUED, "", None, "", None, owner), settings, False))
    assert [queued.record.id for queued in queue] == [1, 3, 4, 2]  # the order they will start in
    assert queue.remove(3) is not None and [q.record.id for q in queue] == [1, 4, 2]
    assert [queue.pop().record.id for _ in range(3)] == [1, 4, 2] and queue.pop() is None
    # the estimate: two cores busy for 10 s and 20 s; each waiting run plays pace x its budget
    for run_id, owner in entries:
        queue.push(QueuedRun(RunRecord(run_id, "r", {}, RunStatus.QUEUED, "", None, "", None, owner), settings, False))
    pace = RunPace(seconds_per_tick=0.5 / (4 * 2 * 60))  # 0.5 s + the runs' start and end, 0.5 s: 1 s each
    places = queue.places([10.0, 20.0], 2, pace)
    assert [(places[i].position, places[i].wait_seconds) for i in (1, 3, 4, 2)] == [(1, 10.0), (2, 11.0), (3, 12.0),
                                                                                      (4, 13.0)]


def test_a_queued_runs_estimate_follows_the_pace_the_running_run_keeps(store, tmp_path):
    """At Start under a load of 20 the estimates (from a quiet machine's pace) were 11 minutes short: once
    the running run has finished generations, the wait is its own remaining time at its own pace."""
    runs = RunManager(store, tmp_path, max_concurrent_runs=1, queue_runs=True)
    try:
        started = time.monotonic()
        running = runs.start(ga=LONG, game=SHORT_GAMES, owner=PUPILS[0])
        queued = runs.start(ga=TINY, game=SHORT_GAMES, owner=PUPILS[1])
        while (progress := runs.progress(running.id)) is None or progress.generation < 3:
            time.sleep(0.05)
        place = runs.queue_place(queued.id)
        elapsed, done = time.monotonic() - started, runs.progress(running.id).generation
        expected = elapsed * (LONG["max_generations"] - done) / done
        assert 0.6 * expected < place.wait_seconds < 1.6 * expected, (place, expected)
    finally:
        runs.shutdown()


def test_a_second_start_while_queued_is_told_its_place_and_keeps_it(classroom):
    for pupil in PUPILS[:2]:
        classroom.start(ga=LONG, game=SHORT_GAMES, owner=pupil)
    queued = classroom.start(ga=TINY, game=SHORT_GAMES, owner=PUPILS[2])
    with pytest.raises(RunStateError, match=rf"your run #{queued.id} is queued \(1st in line of 1, starts in about "):
        classroom.start(ga=TINY, game=SHORT_GAMES, owner=PUPILS[2])
    with pytest.raises(RunStateError, match=r"your run #\d+ is running: stop it first"):
        classroom.start(ga=TINY, game=SHORT_GAMES, owner=PUPILS[0])
    assert classroom.queue_place(queued.id).position == 1 and len(classroom.store.list_runs()) == 3


def test_a_cancelled_queued_run_never_starts_and_can_be_queued_again(classroom, store):
    for pupil in PUPILS[:2]:
        classroom.start(ga=LONG, game=SHORT_GAMES, owner=pupil)
    queued = classroom.start(ga=TINY, game=SHORT_GAMES, owner=PUPILS[2])
    cancelled = classroom.stop(queued.id)
    assert cancelled.status is RunStatus.STOPPED and not classroom.is_pending(queued.id)
    assert classroom.resume(queued.id).status is RunStatus.QUEUED  # back in the queue, at its end
    assert classroom.queue_place(queued.id).position == 1


def test_a_queued_run_is_interrupted_and_resumable_after_a_restart(store, tmp_path):
    """The app ended with a run waiting: the next app lists it interrupted (as a cut-off running run), and
    resuming it plays it from its start to the same end as an uninterrupted run."""
    runs = RunManager(store, tmp_path, max_concurrent_runs=1, queue_runs=True)
    running = runs.start(ga=LONG, game=SHORT_GAMES, owner=PUPILS[0])
    waiting = runs.start(ga={**TINY, "seed": 5}, game=SHORT_GAMES, owner=PUPILS[1])
    runs.shutdown()
    again = RunManager(store, tmp_path, max_concurrent_runs=1, queue_runs=True)
    try:
        assert store.get_run(waiting.id).status is RunStatus.INTERRUPTED
        assert store.get_run(running.id).status.resumable
        assert again.resume(waiting.id).status is RunStatus.RUNNING
        assert again.wait(waiting.id, timeout=120).status is RunStatus.FINISHED
        alone = again.start(ga={**TINY, "seed": 5}, game=SHORT_GAMES)
        assert again.wait(alone.id, timeout=120).status is RunStatus.FINISHED
        assert comparable(store.statistics(waiting.id)) == comparable(store.statistics(alone.id))
    finally:
        again.shutdown()


def test_a_run_left_queued_by_a_killed_app_is_interrupted_at_the_next_start(store, tmp_path):
    """Killed (no shutdown): its row still says queued; the next app does not leave it waiting forever."""
    left = store.create_run("left", RunSettings.build(TINY, SHORT_GAMES).to_dict(), tmp_path / "runs" / "{id}",
                            owner=PUPILS[0], status=RunStatus.QUEUED)
    runs = RunManager(store, tmp_path, queue_runs=True)
    try:
        assert runs.interrupted_at_start == [left.id]
        assert store.get_run(left.id).status is RunStatus.INTERRUPTED and not runs.is_pending(left.id)
    finally:
        runs.shutdown()


def test_the_desk_user_is_still_told_at_once_when_every_run_slot_is_busy(store, tmp_path):
    """Outside classroom mode the one user can stop one of their own runs: a queue would only hide it."""
    runs = RunManager(store, tmp_path, max_concurrent_runs=1)
    try:
        runs.start(ga=LONG, game=SHORT_GAMES)
        with pytest.raises(RunStateError, match="the limit is 1"):
            runs.start(ga=TINY, game=SHORT_GAMES)
    finally:
        runs.shutdown()


def test_a_run_ending_frees_its_core_for_the_next_even_when_it_fails(classroom, store, monkeypatch):
    """A crashed run must not keep its core: the queue moves on."""
    import soccer_lab.app.runs.manager

    real = soccer_lab.app.runs.manager.RunManager._evolve
    calls = []

    def failing_first(self, record, *args):
        calls.append(record.id)
        if len(calls) == 1:
            raise RuntimeError("boom")
        return real(self, record, *args)

    monkeypatch.setattr(soccer_lab.app.runs.manager.RunManager, "_evolve", failing_first)
    classroom.max_concurrent_runs = 1
    first = classroom.start(ga=TINY, game=SHORT_GAMES, owner=PUPILS[0])
    second = classroom.start(ga=TINY, game=SHORT_GAMES, owner=PUPILS[1])
    assert classroom.wait(first.id, timeout=60).status is RunStatus.FAILED
    assert classroom.wait(second.id, timeout=120).status is RunStatus.FINISHED


class ProcessId:
    """An evaluator answering with the process that played it."""

    def __call__(self, rulebases, seeds):
        import os

        return [os.getpid()] * len(rulebases)


def test_class_runs_play_their_games_in_game_processes_as_they_would_here(store, tmp_path):
    """Played in the app's threads, two runs' games share one core (the kernels hold Python's lock): a class's
    runs play theirs in game processes, bit for bit as here."""
    import os

    from soccer_lab.app.runs.games import ProcessGames

    with ProcessGames(2) as games:
        assert set(games(ProcessId())([None, None], [1, 2])) - {os.getpid()}  # another process played them
        runs = RunManager(store, tmp_path, max_concurrent_runs=2, queue_runs=True)
        runs.remote_games = games
        here = RunManager(store, tmp_path / "here")
        try:
            records = [manager.start(ga={**TINY, "seed": 9, "workers": 2}, game=SHORT_GAMES)
                       for manager in (runs, here)]
            for manager, record in zip((runs, here), records):
                assert manager.wait(record.id, timeout=120).status is RunStatus.FINISHED
            pooled, local = (comparable(store.statistics(record.id)) for record in records)
            assert pooled == local and len(pooled) == 2
            assert store.get_run(records[0].id).config["ga"]["workers"] == 1  # one game process per run
        finally:
            runs.shutdown()
            here.shutdown()


def test_game_processes_outlive_the_runs_that_use_them(store, tmp_path):
    """A worker dies with the thread that started it: started from a run's thread, the class's game processes
    died with the first run, and every later run failed (BrokenProcessPool)."""
    import threading

    from soccer_lab.app.runs.games import ProcessGames

    with ProcessGames(2) as games:
        runs = RunManager(store, tmp_path, max_concurrent_runs=2, queue_runs=True)
        runs.remote_games = games
        try:
            for seed in (1, 2, 3):  # one after another: each run's thread has ended before the next
                record = runs.start(ga={**TINY, "seed": seed}, game=SHORT_GAMES, owner=seed)
                assert runs.wait(record.id, timeout=120).status is RunStatus.FINISHED, store.get_run(record.id).error
            worker = threading.Thread(target=lambda: games(ProcessId())([None], [1]))
            worker.start()
            worker.join()
            assert runs.wait(runs.start(ga=TINY, game=SHORT_GAMES).id, timeout=120).status is RunStatus.FINISHED
        finally:
            runs.shutdown()


LEAVE_AS_SERVE_DOES = """
import operator, os, sys
from soccer_lab.app.runs.games import ProcessGames
games = ProcessGames(2).__enter__()
assert games(operator.add)([0], [1]) == [0, 1]  # a chunk played in a game process
games.__exit__(None, None, None)
sys.stdout.flush(); sys.stderr.flush()
os._exit(0)  # as serve ends (app/cli/serve.py _exit_now): no interpreter teardown after this
"""


def test_serve_s_game_processes_leave_no_semaphore_behind_when_serve_stops():
    """serve --class's Ctrl+C ended "stopped" with Python's resource tracker warning "There appear to be 5 leaked
    semaphore objects to clean up at shutdown": the game processes' pool was shut down without waiting, and serve
    leaves with os._exit, so its queues' semaphores were never released."""
    import subprocess
    import sys

    ended = subprocess.run([sys.executable, "-c", LEAVE_AS_SERVE_DOES], capture_output=True, text=True, timeout=120)
    assert ended.returncode == 0, ended.stderr
    assert "leaked" not in ended.stderr and ended.stderr.strip() == "", ended.stderr


# ---- Thirty different players -------------------------------------------------------------------------
def test_two_default_runs_breed_different_players(store, tmp_path):
    runs = RunManager(store, tmp_path)
    try:
        first, second = (runs.start(ga=TINY, game=SHORT_GAMES) for _ in range(2))
        for record in (first, second):
            assert runs.wait(record.id, timeout=120).status is RunStatus.FINISHED
        seeds = [store.get_run(r.id).config["ga"]["seed"] for r in (first, second)]
        assert seeds[0] != seeds[1] and all(0 <= seed < 2**32 for seed in seeds)
        assert f"seed {seeds[0]}" in first.name  # the default name says it too
        assert comparable(store.statistics(first.id)) != comparable(store.statistics(second.id))
    finally:
        runs.shutdown()


def test_the_seed_a_run_drew_replays_it_bit_for_bit(store, tmp_path):
    runs = RunManager(store, tmp_path)
    try:
        drawn = runs.start(ga=TINY, game=SHORT_GAMES)
        runs.wait(drawn.id, timeout=120)
        seed = store.get_run(drawn.id).config["ga"]["seed"]
        again = runs.start(ga={**TINY, "seed": seed}, game=SHORT_GAMES)
        assert runs.wait(again.id, timeout=120).status is RunStatus.FINISHED
        assert comparable(store.statistics(again.id)) == comparable(store.statistics(drawn.id))
        assert store.best_individual(again.id).rules == store.best_individual(drawn.id).rules
        assert (tmp_path / "runs" / str(again.id) / "statistics.csv").read_text().count("\n") == 3
    finally:
        runs.shutdown()


def test_a_seed_given_as_zero_is_kept(store, tmp_path):
    """0 is a seed like any other (the chapter's runs): only a missing seed is drawn."""
    from soccer_lab.ga.config import GAConfig

    runs = RunManager(store, tmp_path, new_seed=lambda: 1234)
    try:
        given = runs.start(ga={**TINY, "seed": 0}, game=SHORT_GAMES)
        model = runs.start(ga=GAConfig(**TINY), game=SHORT_GAMES)  # a GAConfig without a seed given
        for record in (given, model):
            runs.wait(record.id, timeout=120)
        assert [store.get_run(r.id).config["ga"]["seed"] for r in (given, model)] == [0, 1234]
    finally:
        runs.shutdown()


# ---- the Evolve tab ----------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def gui():
    import viser

    from tests.app.test_ui_browser import free_port

    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    yield server.gui
    server.stop()


def evolve_panel(gui, runs, store):
    from soccer_lab.app.web.ui.panels.evolve import EvolvePanel

    panel = EvolvePanel(gui, runs, store, on_load=lambda *_: None, on_generation=lambda *_: None,
                        on_run_ended=lambda *_: None, on_runs_changed=lambda: None)
    for name, value in {**TINY, "population_size": 6}.items():
        panel.inputs[name].value = value
    panel.game_inputs["skills"].value = "sighted"
    return panel


def test_the_evolve_tab_shows_the_seed_it_drew_and_replays_it(gui, store, tmp_path):
    runs = RunManager(store, tmp_path)
    panel = evolve_panel(gui, runs, store)
    try:
        assert panel.inputs["seed"].text.value == ""  # empty: no real-looking value every pupil would share
        panel.start()
        first = panel.run_id
        seed = store.get_run(first).config["ga"]["seed"]
        assert f"Run #{first}&#x27;s seed: {seed} (type it in Run seed" in panel.seed_line.content
        runs.wait(first, timeout=120)
        panel.inputs["seed"].text.value = str(seed)
        panel.start()
        assert runs.wait(panel.run_id, timeout=120).status is RunStatus.FINISHED
        assert store.get_run(panel.run_id).config["ga"]["seed"] == seed
        assert comparable(store.statistics(panel.run_id)) == comparable(store.statistics(first))
        panel.inputs["seed"].text.value = "-3"
        panel.start()
        assert "Run seed (empty: a new one each run): expected a whole number ≥ 0" in panel.status.content
    finally:
        panel.close()
        runs.shutdown()


def test_the_evolve_tab_shows_a_queued_runs_place_and_stop_leaves_the_queue(gui, store, tmp_path):
    runs = RunManager(store, tmp_path, max_concurrent_runs=1, queue_runs=True)
    panel = evolve_panel(gui, runs, store)
    panel.api_url = "http://127.0.0.1:8000"  # as serve gives it: the tab links runs to the rerun viewer
    try:
        running = runs.start(ga=LONG, game=SHORT_GAMES, owner=PUPILS[0])
        panel.start()
        assert store.get_run(panel.run_id).status is RunStatus.QUEUED
        assert f"Run #{panel.run_id} is queued: 1st in line of 1, starts in about" in panel.status.content
        assert panel.viewer.content == ""  # its recording does not exist yet: the link opened the viewer on a 404
        panel.stop()
        assert store.get_run(panel.run_id).status is RunStatus.STOPPED
        assert f"Run #{panel.run_id} stopped" in panel.status.content
        panel.start()  # queued again; once the core is free it starts, and the tab says so
        runs.stop(running.id)
        assert runs.wait(panel.run_id, timeout=120).status is RunStatus.FINISHED
        assert f"Run #{panel.run_id} finished" in panel.status.content
        assert f"Open run #{panel.run_id} in the rerun viewer" in panel.viewer.content  # once it started
    finally:
        panel.close()
        runs.shutdown()


def test_the_teacher_cancels_a_pupils_queued_run_from_the_library_and_a_pupil_only_their_own(gui, store, tmp_path):
    from soccer_lab.app.web.access import ScopedRuns, ScopedStore, Visitor
    from soccer_lab.app.web.ui.panels.library import LibraryPanel, _label
    from soccer_lab.fuzzy.vocabulary import Vocabulary

    runs = RunManager(store, tmp_path, max_concurrent_runs=1, queue_runs=True)
    teacher, ada = Visitor(None, "", teacher=True), Visitor(PUPILS[0], "Ada", teacher=False)
    panels = {visitor: LibraryPanel(gui, ScopedStore(store, visitor), ScopedRuns(runs, visitor), Vocabulary.default(),
                                    None, on_load=lambda *_: None) for visitor in (teacher, ada)}
    try:
        running = runs.start(ga=LONG, game=SHORT_GAMES, owner=PUPILS[1])
        adas = runs.start(ga=TINY, game=SHORT_GAMES, owner=PUPILS[0])
        bens = runs.start(ga=TINY, game=SHORT_GAMES, owner=PUPILS[2])
        for panel in panels.values():
            panel.refresh()
        assert _label(bens.id, f"{bens.name} (queued)") not in panels[ada].runs.options  # not hers to see
        panels[ada].runs.value = _label(adas.id, f"{adas.name} (queued)")
        panels[ada].stop_run()
        assert store.get_run(adas.id).status is RunStatus.STOPPED
        assert f"Run #{adas.id} taken out of the queue." in panels[ada].message.content
        panels[teacher].refresh()
        panels[teacher].runs.value = _label(bens.id, f"{bens.name} (queued)")
        panels[teacher].stop_run()
        assert store.get_run(bens.id).status is RunStatus.STOPPED and not runs.is_pending(bens.id)
        panels[teacher].runs.value = _label(running.id, f"{running.name} (running)")
        panels[teacher].stop_run()
        assert runs.wait(running.id, timeout=30).status is RunStatus.STOPPED
    finally:
        runs.shutdown()
