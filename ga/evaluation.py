"""Scoring rulebases with the caller's evaluator, serially or across worker processes.

The evaluator is any picklable callable `evaluate(rulebases, seeds) -> results`, each result with
`.fitness` and `.goals`, whose result for one (rulebase, seed) does not depend on the rest of the
batch. Then splitting a generation into contiguous chunks, one per worker, gives exactly the
serial results, whatever the number of workers.
"""

from __future__ import annotations

import gc
import math
import multiprocessing
from concurrent.futures import ProcessPoolExecutor
from typing import Any, Callable, NamedTuple, Sequence

import numpy as np

from fuzzy.rule import Rulebase

INVALID_FITNESS = 1.0  # a ruleset with no valid rule is never played (docs/research/index.md, "The model")

Evaluator = Callable[[list[Rulebase], list[int]], Sequence[Any]]


class EvaluationError(RuntimeError):
    pass


class Score(NamedTuple):
    fitness: float
    goals: int


INVALID_SCORE = Score(INVALID_FITNESS, 0)


class Evaluation:
    """Use as a context manager: worker processes (spawned, so safe beside threads) live for one run.
    With `workers` = k, k - 1 processes are spawned and this process plays the first chunk itself
    while they play the others: it would otherwise sit idle, and one process fewer starts."""

    def __init__(self, evaluate: Evaluator, workers: int = 1):
        self.evaluate = evaluate
        self.workers = workers
        self._pool: ProcessPoolExecutor | None = None

    def __enter__(self) -> "Evaluation":
        # What exists when a run starts (modules, compiled kernels, the app's state) is frozen for the run, so
        # the cyclic garbage collector's full collections skip it (one walked 140,000 objects: 2% of a trial's
        # CPU); thawed when the run ends, so that what the process drops later is still collected
        gc.freeze()
        if self.workers > 1:
            # gc.freeze: what a worker has imported lives as long as it, and every full collection of the
            # cyclic garbage collector walked it all again (3% of a trial's CPU time)
            self._pool = ProcessPoolExecutor(self.workers - 1, mp_context=multiprocessing.get_context("spawn"),
                                             initializer=gc.freeze)
        return self

    def __exit__(self, *exc_info: object) -> None:
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)
            self._pool = None
        gc.unfreeze()

    def __call__(self, rulebases: list[Rulebase], seeds: list[int]) -> list[Score]:
        """One Score per rulebase; empty (invalid) rulebases score INVALID_SCORE without being played."""
        playable = [i for i, rulebase in enumerate(rulebases) if len(rulebase)]
        scores = [INVALID_SCORE] * len(rulebases)
        for i, result in zip(playable, self._play([rulebases[i] for i in playable], [seeds[i] for i in playable])):
            scores[i] = _score(result)
        return scores

    def _play(self, rulebases: list[Rulebase], seeds: list[int]) -> list[Any]:
        if not rulebases:
            return []
        if self._pool is None:
            return _checked(self.evaluate(rulebases, seeds), len(rulebases))
        bounds = np.linspace(0, len(rulebases), min(self.workers, len(rulebases)) + 1).astype(int)
        spans = list(zip(bounds[:-1], bounds[1:]))  # contiguous chunks, one per worker, in order
        futures = [self._pool.submit(self.evaluate, rulebases[lo:hi], seeds[lo:hi]) for lo, hi in spans[1:]]
        (lo, hi), rest = spans[0], spans[1:]
        first = _checked(self.evaluate(rulebases[lo:hi], seeds[lo:hi]), hi - lo)
        return [*first, *(result for (lo, hi), future in zip(rest, futures) for result in _checked(future.result(), hi - lo))]


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
