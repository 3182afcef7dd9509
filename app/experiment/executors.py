"""Where trials run: local worker processes (default) or Ray tasks. Both hand results back as each
trial finishes, in whatever order; a trial's result depends only on its spec, so the executor never
changes the outcome. Trials on rcssserver (the robocup preset) run on RcssExecutor instead: one after
another in this process, each GA's evaluations spread over the servers."""

from __future__ import annotations

import multiprocessing
import os
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from typing import TYPE_CHECKING, Any, Callable, Iterable, Iterator, Sequence

from soccer_lab.ga.evaluation import start_worker

if TYPE_CHECKING:
    from soccer_lab.soccer.rcss.evaluate import RcssEvaluator
    from soccer_lab.soccer.rcss.trial import TrialConfig

LOCAL, RAY = "local", "ray"
EXECUTOR_NAMES = (LOCAL, RAY)
RAY_MISSING = "Ray is not installed; install the optional extra: pip install 'soccer-lab[ray]'"


class ExecutorError(RuntimeError):
    """An executor that cannot start (Ray missing, cluster unreachable): one line for the user."""


def default_workers() -> int:
    return os.cpu_count() or 1


class LocalExecutor:
    """Trials on `workers` spawned processes; with one worker, in this process (no start-up cost)."""

    def __init__(self, workers: int | None = None):
        self.workers = workers or default_workers()
        self._pool: ProcessPoolExecutor | None = None

    def __enter__(self) -> "LocalExecutor":
        if self.workers > 1:
            # start_worker: it dies with this process, and freezes what it imported for the garbage collector
            self._pool = ProcessPoolExecutor(self.workers, mp_context=multiprocessing.get_context("spawn"),
                                             initializer=start_worker, initargs=(os.getpid(),))
        return self

    def __exit__(self, *exc_info: object) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None

    def map_unordered(self, function: Callable[[Any], Any], items: Iterable[Any]) -> Iterator[tuple[Any, Any]]:
        if self._pool is None:
            for item in items:
                yield item, function(item)
            return
        pending = {self._pool.submit(function, item): item for item in items}
        while pending:
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:
                yield pending.pop(future), future.result()


class RayExecutor:
    """Trials as Ray tasks (one CPU each) on the cluster at `address`, or on a local Ray started here
    with `workers` CPUs. The cluster's workers need soccer-lab installed."""

    def __init__(self, address: str | None = None, workers: int | None = None):
        try:
            import ray
        except ImportError:
            raise ExecutorError(RAY_MISSING) from None
        self.ray = ray
        self.address = address
        self.workers = workers
        self._started_here = False

    def __enter__(self) -> "RayExecutor":
        if not self.ray.is_initialized():
            try:
                if self.address is None:
                    self.ray.init(num_cpus=self.workers or default_workers(), include_dashboard=False,
                                  log_to_driver=False)
                else:
                    self.ray.init(address=self.address, log_to_driver=False)
            except Exception as exc:  # noqa: BLE001 - Ray raises a bare Exception when its node does not start in time
                where = f" at {self.address}" if self.address else ""
                raise ExecutorError(f"cannot start Ray{where}: {str(exc).splitlines()[0] if str(exc) else exc!r}") \
                    from None
            self._started_here = True
        return self

    def __exit__(self, *exc_info: object) -> None:
        if self._started_here:
            self.ray.shutdown()
            self._started_here = False

    def map_unordered(self, function: Callable[[Any], Any], items: Iterable[Any]) -> Iterator[tuple[Any, Any]]:
        task = self.ray.remote(num_cpus=1)(function)
        pending = {task.remote(item): item for item in items}
        try:
            while pending:
                done, _ = self.ray.wait(list(pending), num_returns=1)
                for ref in done:
                    yield pending.pop(ref), self.ray.get(ref)
        finally:
            for ref in pending:  # interrupted: do not leave the cluster busy with our trials
                self.ray.cancel(ref, force=True)


class RcssExecutor:
    """Trials on the rcssservers at `servers` (HOST:PORT), one trial at a time, its evaluations in parallel
    over the servers. Each server keeps one player and trainer for the whole experiment (a server takes
    only 11 players of a team in its lifetime)."""

    def __init__(self, servers: Sequence[str]):
        self.servers = list(servers)
        self._trial: TrialConfig | None = None
        self._evaluate: RcssEvaluator | None = None

    def __enter__(self) -> "RcssExecutor":
        return self

    def __exit__(self, *exc_info: object) -> None:
        self._close()

    def evaluator(self, trial: TrialConfig) -> RcssEvaluator:
        """The evaluator playing `trial` rules, connected to every server on first use."""
        if self._evaluate is None or trial != self._trial:
            self._close()
            self._evaluate, self._trial = self._new_evaluator(trial), trial
            self._evaluate.connect()
        return self._evaluate

    def _new_evaluator(self, trial: TrialConfig) -> RcssEvaluator:
        from soccer_lab.soccer.rcss.evaluate import RcssEvaluator

        return RcssEvaluator(self.servers, trial)

    def map_unordered(self, function: Callable[..., Any], items: Iterable[Any]) -> Iterator[tuple[Any, Any]]:
        """`function(item, evaluator)` for each item (a TrialSpec of rcssserver trials), in order."""
        for item in items:
            if item.setting.trial is None:
                raise ExecutorError("SimpleSoccer trials run on the local or ray executor, not on rcssservers")
            yield item, function(item, self.evaluator(item.setting.trial))

    def _close(self) -> None:
        if self._evaluate is not None:
            self._evaluate.close()
        self._evaluate = self._trial = None


def make_executor(name: str, *, workers: int | None = None, address: str | None = None) -> LocalExecutor | RayExecutor:
    if name == LOCAL:
        if address is not None:
            raise ExecutorError("--address needs --executor ray")
        return LocalExecutor(workers)
    if name == RAY:
        return RayExecutor(address, workers)
    raise ExecutorError(f"unknown executor {name!r}; choose one of {', '.join(EXECUTOR_NAMES)}")
