"""No thread leaks (issue 25): rerun's recording streams (a batcher and a sender thread each) end with their
run, and blueprints sent every generation leave none behind. Counted on the process's own threads (rerun's
are native, not Python's) across 100 generations of runs, played as the app plays them."""

from __future__ import annotations

import os

from soccer_lab.app.paths import DATABASE_FILE
from soccer_lab.app.runs.manager import RunManager
from soccer_lab.app.store import Store
from tests.app.api_client import SHORT_GAMES

RUNS, GENERATIONS = 5, 20


def threads() -> int:
    return len(os.listdir("/proc/self/task"))


def test_threads_stay_flat_across_100_generations_of_runs(tmp_path):
    store = Store(tmp_path / DATABASE_FILE)
    runs = RunManager(store, tmp_path)
    counts = []
    try:
        for i in range(RUNS):
            record = runs.start(f"run {i}", {"population_size": 4, "max_generations": GENERATIONS, "max_length": 16,
                                             "seed": i}, SHORT_GAMES)
            assert str(runs.wait(record.id, timeout=300).status) == "finished"
            assert len(store.statistics(record.id)) == GENERATIONS
            counts.append(threads())
    finally:
        runs.shutdown()
        store.close()
    # The first run starts what lives as long as the process (rerun's runtime, the one blueprint stream); a
    # thread or so comes and goes (rerun's and sqlite's own). A stream left per generation added 2 threads
    # each: 160 over these runs.
    assert max(counts) - min(counts) <= 2, counts


def test_runs_opening_sending_and_closing_recordings_at_once_do_not_deadlock(tmp_path):
    """Runs' threads each opening a recording, sending its blueprints (as every generation's replay does) and
    closing it all finish: unserialised, rerun's bindings deadlocked and two API runs hung for good (a blueprint
    sent while another run closed its recording, too)."""
    import threading

    import rerun as rr
    import rerun.blueprint as rrb

    from soccer_lab.app.runs.recording import close_stream, open_stream, send_blueprint

    finished = []

    def send_many(name: str) -> None:
        for recording in range(15):
            stream = open_stream(tmp_path / f"{name}-{recording}.rrd")
            for generation in range(10):
                stream.set_time("generation", sequence=generation)
                stream.log("/fitness/best", rr.Scalars(1.0 / (generation + 1)))
                send_blueprint(stream, rrb.Blueprint(rrb.TimeSeriesView(origin="/fitness")))
            close_stream(stream)
            del stream
        finished.append(name)

    senders = [threading.Thread(target=send_many, args=(name,), daemon=True) for name in ("a", "b", "c")]
    for sender in senders:
        sender.start()
    for sender in senders:
        sender.join(60)
    assert sorted(finished) == ["a", "b", "c"]
