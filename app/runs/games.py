"""Where classroom mode's runs play their games: in worker processes of this machine (`ProcessGames`), or
as Ray tasks on a lab's machines (`RayGames`: `serve --class --executor ray --ray-address ...`, as
experiments do: app/experiment/executors.py).

A pupil's run is one worker, and its GA (breeding, checkpoints, the store, the UI's live view) is a thread of
the app. Played in that thread, its games would hold Python's lock (the game kernels do not release it):
two runs would share one core, and the tabs' games would wait on them. So every chunk of games goes to a
worker process, one per run playing at once, and the run's thread waits without the lock.

On Ray each run keeps its GA (breeding, checkpoints, the store, the UI's live view) in the app's process and
sends every chunk of games to the cluster as one task of one CPU: a game depends only on its rulebase and
seed, so a run plays bit for bit the same on Ray as here. The queue then runs as many runs at once as the
cluster has CPUs. rcssserver runs stay on this machine (their servers are its own).
"""

from __future__ import annotations

import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor
from typing import Any, Sequence

from soccer_lab.app.experiment.executors import RayExecutor
from soccer_lab.ga.evaluation import start_worker


def _play(evaluate: Any, rulebases: Sequence[Any], seeds: Sequence[int]) -> Any:
    """A chunk of games, on a Ray worker."""
    return evaluate(rulebases, seeds)


class RemoteGames:
    """`evaluate` with every call played as a Ray task (its chunk size kept: the GA's chunks are the tasks)."""

    def __init__(self, evaluate: Any, task: Any, ray: Any):
        self.evaluate = evaluate
        self._task = task
        self._ray = ray

    @property
    def chunk_size(self) -> int | None:
        return getattr(self.evaluate, "chunk_size", None)

    def __call__(self, rulebases: Sequence[Any], seeds: Sequence[int]) -> Any:
        return self._ray.get(self._task.remote(self.evaluate, list(rulebases), list(seeds)))


class PooledGames:
    """`evaluate` with every call played in one of the app's game processes."""

    def __init__(self, evaluate: Any, pool: ProcessPoolExecutor):
        self.evaluate = evaluate
        self._pool = pool

    @property
    def chunk_size(self) -> int | None:
        return getattr(self.evaluate, "chunk_size", None)

    def __call__(self, rulebases: Sequence[Any], seeds: Sequence[int]) -> Any:
        return self._pool.submit(_play, self.evaluate, list(rulebases), list(seeds)).result()


def _ready() -> None:
    """A game process's first task: the game's kernels loaded before a run needs them."""
    import soccer_lab.soccer.engine  # noqa: F401


class ProcessGames:
    """`workers` game processes of this machine shared by the runs (spawned: safe beside the app's threads).
    A context manager, entered by the thread that lives as long as the app: a worker dies with the thread
    that started it (soccer_lab.ga.evaluation.start_worker), and a pool starts its processes on demand, so they are
    all started here, at once, never from a run's thread (which ends with its run)."""

    def __init__(self, workers: int):
        self.workers = workers
        self._pool: ProcessPoolExecutor | None = None

    def __enter__(self) -> "ProcessGames":
        self._pool = ProcessPoolExecutor(self.workers, mp_context=multiprocessing.get_context("spawn"),
                                         initializer=start_worker, initargs=(os.getpid(),))
        for _ in range(self.workers):  # no worker is idle yet, so each task starts one more (not awaited)
            self._pool.submit(_ready)
        return self

    def __exit__(self, *exc_info: object) -> None:
        if self._pool is None:
            return
        pool, self._pool = self._pool, None
        # serve leaves with os._exit (app/cli/serve.py): the pool must be gone before, or its queues' semaphores
        # stay registered and Python's resource tracker warns of "leaked semaphore objects" after "stopped". A
        # chunk still playing is an interrupted run's: its process is ended, not waited for.
        for process in list((pool._processes or {}).values()):
            process.terminate()
        pool.shutdown(wait=True, cancel_futures=True)

    def cores(self) -> int:
        return self.workers

    def __call__(self, evaluate: Any) -> PooledGames:
        if self._pool is None:
            raise RuntimeError("ProcessGames is used inside its with block")
        return PooledGames(evaluate, self._pool)


class RayGames:
    """The served runs' games on the Ray cluster at `address` (None: a local Ray of `workers` CPUs started
    here). A context manager, open as long as the app serves; ExecutorError (one line) when Ray is missing
    or the cluster cannot be reached."""

    def __init__(self, address: str | None = None, workers: int | None = None):
        self._executor = RayExecutor(address, workers)
        self._task: Any = None

    def __enter__(self) -> "RayGames":
        self._executor.__enter__()
        self._task = self._executor.ray.remote(num_cpus=1)(_play)
        return self

    def __exit__(self, *exc_info: object) -> None:
        self._executor.__exit__(*exc_info)

    def cores(self) -> int:
        """The cluster's CPUs: how many runs play at once."""
        return max(1, int(self._executor.ray.cluster_resources().get("CPU", 1)))

    def __call__(self, evaluate: Any) -> RemoteGames:
        return RemoteGames(evaluate, self._task, self._executor.ray)
