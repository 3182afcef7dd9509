"""Scoring rulebases with the caller's evaluator, in bounded chunks, serially or across worker processes.

The evaluator is any picklable callable `evaluate(rulebases, seeds) -> results`, each result with
`.fitness` and `.goals`, whose result for one (rulebase, seed) does not depend on the rest of the
batch. Then splitting a generation into contiguous chunks gives exactly the unsplit results, whatever
the chunk size and the number of workers. A generation is played a chunk at a time (at most
`evaluate.chunk_size` rulebases, else CHUNK_SIZE): what a chunk's games hold in memory is bounded
whatever the population, the caller hears the progress after each chunk, and a stop asked for is
obeyed between chunks (EvaluationStopped), so within about one chunk's time.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import gc
import math
import multiprocessing
import os
import signal
import threading
from concurrent.futures import ProcessPoolExecutor
from typing import Any, Callable, NamedTuple, Sequence

from soccer_lab.fuzzy.rule import Rulebase

INVALID_FITNESS = 1.0  # a ruleset with no valid rule is never played (docs/research/index.md, "The model")
# Rulebases per chunk for an evaluator that does not say (`chunk_size`): a SimpleSoccer chunk of this many
# 1000-tick games plays in well under a second and holds a few MB (benchmarks/stop_latency.py)
CHUNK_SIZE = 100

PR_SET_PDEATHSIG = 1  # Linux's prctl option: a signal for this process when the thread that started it ends

Evaluator = Callable[[list[Rulebase], list[int]], Sequence[Any]]
Progress = Callable[[int, int], None]  # (rulebases evaluated so far in this generation, the generation's size)


def start_worker(parent: int) -> None:
    """A worker process's first step. It dies with the process that started it (Linux): a worker holds both
    ends of its task queue, so when that process is killed (`kill -9` on serve) it would otherwise wait
    forever. And gc.freeze: what a worker has imported lives as long as it, and every full collection of
    the cyclic garbage collector walked it all again (3% of a trial's CPU time)."""
    libc = ctypes.util.find_library("c")
    prctl = getattr(ctypes.CDLL(libc, use_errno=True), "prctl", None) if libc else None
    if prctl is not None:
        prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        if os.getppid() != parent:  # it died while this one started
            os._exit(1)
    gc.freeze()


class EvaluationError(RuntimeError):
    pass


class EvaluationStopped(Exception):
    """The stop event was set: the generation in progress was abandoned between two chunks."""


class Score(NamedTuple):
    fitness: float
    goals: int


INVALID_SCORE = Score(INVALID_FITNESS, 0)


class Evaluation:
    """Use as a context manager: worker processes (spawned, so safe beside threads) live for one run.
    With `workers` = k, k - 1 processes are spawned and, chunk after chunk, this process plays one chunk
    itself while they play the next k - 1: it would otherwise sit idle, and one process fewer starts.
    `stop` (an Event) abandons a generation between chunks (chunks not started are cancelled);
    `progress(done, total)` is called after every chunk."""

    def __init__(self, evaluate: Evaluator, workers: int = 1, *, stop: threading.Event | None = None,
                 progress: Progress | None = None, chunk_size: int | None = None):
        self.evaluate = evaluate
        self.workers = workers
        self.stop = stop
        self.progress = progress
        self.chunk_size = max(1, int(chunk_size or getattr(evaluate, "chunk_size", None) or CHUNK_SIZE))
        self._pool: ProcessPoolExecutor | None = None

    def use(self, evaluate: Evaluator) -> None:
        """Score with `evaluate` from now on (co-evolution: the generation's opponents), in chunks of its size."""
        self.evaluate = evaluate
        self.chunk_size = max(1, int(getattr(evaluate, "chunk_size", None) or CHUNK_SIZE))

    def __enter__(self) -> "Evaluation":
        # What exists when a run starts (modules, compiled kernels, the app's state) is frozen for the run, so
        # the cyclic garbage collector's full collections skip it (one walked 140,000 objects: 2% of a trial's
        # CPU); thawed when the run ends, so that what the process drops later is still collected
        gc.freeze()
        if self.workers > 1:
            self._pool = ProcessPoolExecutor(self.workers - 1, mp_context=multiprocessing.get_context("spawn"),
                                             initializer=start_worker, initargs=(os.getpid(),))
        return self

    def __exit__(self, *exc_info: object) -> None:
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)
            self._pool = None
        gc.unfreeze()

    def __call__(self, rulebases: Sequence[Rulebase], seeds: Sequence[int], *, report: bool = True) -> list[Score]:
        """One Score per rulebase; empty (invalid) rulebases score INVALID_SCORE without being played.
        `rulebases` may decode each on access: only a chunk's are held at a time. EvaluationStopped when
        the stop event is set before the last chunk is played. `report`: call `progress` (False for games
        that are not the generation's evaluation, such as the behaviour seeds')."""
        start_generation = getattr(self.evaluate, "start_generation", None)
        if start_generation is not None:  # an evaluator keeping something per generation (rcss traces)
            start_generation()
        scores = [INVALID_SCORE] * len(rulebases)
        spans = [range(lo, min(lo + self.chunk_size, len(rulebases))) for lo in range(0, len(rulebases), self.chunk_size)]
        group = self.workers if self._pool is not None else 1
        for first in range(0, len(spans), group):
            self._check_stop()
            chunks = [[(i, rulebase) for i in span if len(rulebase := rulebases[i])] for span in spans[first:first + group]]
            for chunk, results in zip(chunks, self._play_group(chunks, seeds)):
                for (i, _), result in zip(chunk, results):
                    scores[i] = _score(result)
            if self.progress is not None and report:
                self.progress(spans[min(first + group, len(spans)) - 1].stop, len(rulebases))
        return scores

    def _check_stop(self) -> None:
        if self.stop is not None and self.stop.is_set():
            raise EvaluationStopped()

    def _play_group(self, chunks: list[list[tuple[int, Rulebase]]], seeds: Sequence[int]) -> list[Sequence[Any]]:
        """The results of each chunk ((index, rulebase) pairs), in order: the first played here, the others
        by the worker processes meanwhile."""
        def play(chunk: list[tuple[int, Rulebase]]) -> Sequence[Any]:
            return _checked(self.evaluate([r for _, r in chunk], [seeds[i] for i, _ in chunk]), len(chunk)) if chunk else []

        futures = [self._pool.submit(self.evaluate, [r for _, r in chunk], [seeds[i] for i, _ in chunk]) if chunk else None
                   for chunk in chunks[1:]] if self._pool is not None else []
        try:
            first = play(chunks[0])
            return [first, *(_checked(future.result(), len(chunk)) if future is not None else []
                             for chunk, future in zip(chunks[1:], futures))]
        finally:
            for future in futures:
                if future is not None:
                    future.cancel()  # only what has not started: an error or interruption leaves nothing queued


def _checked(results: Sequence[Any], expected: int) -> Sequence[Any]:
    if len(results) != expected:
        raise EvaluationError(f"the evaluator returned {len(results)} results for {expected} rulebases")
    return results


def _score(result: Any) -> Score:
    try:
        fitness, goals = float(result.fitness), int(result.goals)
    except (AttributeError, TypeError, ValueError) as exc:
        raise EvaluationError(f"an evaluator result needs a numeric .fitness and .goals: {exc}") from None
    if not math.isfinite(fitness):
        raise EvaluationError(f"the evaluator returned a non-finite fitness {fitness}")
    return Score(fitness, goals)
