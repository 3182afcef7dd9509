"""The classroom queue's runs on Ray (`serve --class --executor ray`, app/runs/games.py), with a local Ray:
the same seed gives the same run on Ray as locally, the queue runs one run per CPU of the cluster, and
the options are checked with one line."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from soccer_lab.app.cli import app
from soccer_lab.app.paths import DATABASE_FILE
from soccer_lab.app.runs.manager import RunManager
from soccer_lab.app.store import RunStatus, Store
from tests.app.test_run_queue import SHORT_GAMES, comparable

ray = pytest.importorskip("ray")

RUN = {"population_size": 6, "max_generations": 2, "workers": 2, "seed": 31}


@pytest.fixture(scope="module")
def ray_games():
    """A local Ray of 2 CPUs started by RayGames itself, as serve starts it without --ray-address (a busy
    machine may need a second try)."""
    from soccer_lab.app.experiment.executors import ExecutorError
    from soccer_lab.app.runs.games import RayGames

    for attempt in range(2):
        games = RayGames(None, workers=2)
        try:
            games.__enter__()
            break
        except ExecutorError:
            if attempt:
                raise
    yield games
    games.__exit__(None, None, None)


def played(runs: RunManager, store: Store, owner: int | None = None) -> list[dict]:
    record = runs.start(ga=RUN, game=SHORT_GAMES, owner=owner)
    assert runs.wait(record.id, timeout=300).status is RunStatus.FINISHED, store.get_run(record.id).error
    return [record.id, comparable(store.statistics(record.id)), store.best_individual(record.id).rules]


def test_a_queued_run_on_ray_plays_as_it_does_locally(ray_games, tmp_path):
    store = Store(tmp_path / DATABASE_FILE)
    local = RunManager(store, tmp_path / "local")
    on_ray = RunManager(store, tmp_path / "ray", queue_runs=True, max_concurrent_runs=ray_games.cores())
    on_ray.remote_games = ray_games
    try:
        assert on_ray.max_concurrent_runs == 2  # one run per CPU of the cluster
        here = played(local, store)
        there = played(on_ray, store, owner=7)
        assert there[1:] == here[1:] and len(there[1]) == 2
        assert store.get_run(there[0]).config["ga"]["workers"] == 1  # one CPU per run: its chunks are the tasks
    finally:
        local.shutdown()
        on_ray.shutdown()
        store.close()


@pytest.mark.parametrize("arguments, message", [
    (["--executor", "ray"], "--executor places classroom mode's queue of runs: add --class"),
    (["--class", "--executor", "spark"], "--executor: unknown executor 'spark'; choose one of local, ray"),
    (["--class", "--ray-address", "10.0.0.5:6379"], "--ray-address needs --executor ray"),
])
def test_serve_s_ray_options_are_checked_in_one_line(arguments, message, tmp_path):
    result = CliRunner().invoke(app, ["serve", *arguments, "--data-dir", str(tmp_path)])
    assert result.exit_code == 2 and result.output.strip() == f"error: {message}", result.output
