"""The evolution loop and the random-search baseline (the chapter, 6.5 for the baseline).

Generation 0 is the evaluated initial population; a run evaluates at most `max_generations`
generations, i.e. population_size x max_generations evaluations. Each generation: breed (or, for
random search, draw fresh individuals), draw one game seed per individual, evaluate, record
statistics (after the behaviour seeds' games, when the run counts behaviours), checkpoint, call the
callbacks. Everything random comes from one Generator seeded by config.seed and saved in every
checkpoint, so a resumed run continues bit for bit.

Co-evolution (`hall`, ga/hall_of_fame.py): before each generation is evaluated, the opponents it plays
are drawn from the hall of fame with the same Generator, and the evaluator is asked for one against them
(`evaluate.against(rulebases)`); after it, the generation's best joins the hall. The hall is part of the
state, so a resumed co-evolution run continues bit for bit too. Callbacks with an `on_opponents(generation,
members)` method hear whom the generation is scored against (the hall of fame members drawn: each with its
chromosome and label), before it is evaluated.

`stop` is obeyed within a generation too (ga/evaluation.py plays it in chunks and checks between them,
the behaviour seeds' games included): the generation in progress is abandoned and the run ends as it was
after the last finished generation, which is what its checkpoint holds, so a resumed run plays the
abandoned generation again, the same. Callbacks with an `on_progress(done, total)` method hear how many
of the generation's individuals have been evaluated, after every chunk.
"""

from __future__ import annotations

import threading
import time
from dataclasses import replace
from pathlib import Path
from typing import Any, Iterable, Sequence

import numpy as np

from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.checkpoint import load_checkpoint, save_checkpoint
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.config import SEED_BOUND, GAConfig
from soccer_lab.ga.diversity import BehaviourProbe, behaviour_seeds
from soccer_lab.ga.evaluation import Evaluation, EvaluationStopped, Evaluator
from soccer_lab.ga.genes import GeneSpace
from soccer_lab.ga.hall_of_fame import HallOfFame
from soccer_lab.ga.individual import Individual
from soccer_lab.ga.initialisation import random_population
from soccer_lab.ga.provenance import RANDOM_DRAW
from soccer_lab.ga.reproduction import next_generation
from soccer_lab.ga.result import GENERATIONS_DONE, STOPPED, TARGET_REACHED, RunResult
from soccer_lab.ga.state import GA, RANDOM_SEARCH, RunState
from soccer_lab.ga.statistics import NOT_MEASURED, generation_stats

# A callback is a function (stats, population) or an object with on_generation(stats, population).
Callback = Any


def evolve(config: GAConfig, evaluate: Evaluator, vocabulary: Vocabulary, *, callbacks: Iterable[Callback] = (),
           checkpoint: str | Path | None = None, stop: threading.Event | None = None,
           initial_population: Sequence[np.ndarray] | None = None, hall: HallOfFame | None = None) -> RunResult:
    """Run the messy-coded GA over rules in `vocabulary` (the one `evaluate` plays them in); `stop`
    ends it within the generation in progress (which is abandoned). `initial_population` (population_size
    chromosomes over the same vocabulary, e.g. a population evolved in another game) is generation 0 instead
    of random ones. `hall`: co-evolve against this hall of fame (its founder the first opponent); `evaluate`
    then has `against(rulebases)`."""
    if initial_population is not None and len(initial_population) != config.population_size:
        raise ValueError(f"an initial population of {len(initial_population)} for a population size of "
                         f"{config.population_size}")
    if hall is not None and not hasattr(evaluate, "against"):
        raise ValueError("co-evolution needs an evaluator that plays against opponents (with `against`)")
    state = replace(_fresh_state(GA, config, vocabulary), hall=hall)
    return _run(state, evaluate, callbacks, checkpoint, stop, initial_population)


def random_search(config: GAConfig, evaluate: Evaluator, vocabulary: Vocabulary, *,
                  callbacks: Iterable[Callback] = (), checkpoint: str | Path | None = None,
                  stop: threading.Event | None = None) -> RunResult:
    """The baseline: each "generation" is population_size fresh random individuals, same statistics."""
    return _run(_fresh_state(RANDOM_SEARCH, config, vocabulary), evaluate, callbacks, checkpoint, stop)


def resume(checkpoint_path: str | Path, evaluate: Evaluator, *, callbacks: Iterable[Callback] = (),
           stop: threading.Event | None = None, workers: int | None = None) -> RunResult:
    """Continue a run from its last checkpoint; it finishes exactly as if never interrupted.
    `workers` may differ from the original run's: results do not depend on it."""
    state = load_checkpoint(checkpoint_path)
    if workers is not None:
        state = replace(state, config=GAConfig(**{**state.config.model_dump(), "workers": workers}))
    return _run(state, evaluate, callbacks, checkpoint_path, stop)


def _fresh_state(algorithm: str, config: GAConfig, vocabulary: Vocabulary) -> RunState:
    rng = np.random.default_rng(config.seed)
    return RunState(algorithm, config, vocabulary, [], rng.bit_generator.state, [], None)


def _run(state: RunState, evaluate: Evaluator, callbacks: Iterable[Callback], checkpoint: str | Path | None,
         stop: threading.Event | None, initial_population: Sequence[np.ndarray] | None = None) -> RunResult:
    config = state.config
    rng = np.random.default_rng()
    rng.bit_generator.state = state.rng_state
    codec = ChromosomeCodec(state.vocabulary)
    callbacks = list(callbacks)
    listeners = [getattr(callback, "on_generation", callback) for callback in callbacks]
    watchers = [callback.on_progress for callback in callbacks if hasattr(callback, "on_progress")]
    hearing_opponents = [callback.on_opponents for callback in callbacks if hasattr(callback, "on_opponents")]

    def progress(done: int, total: int) -> None:
        for watcher in watchers:
            watcher(done, total)

    started = time.perf_counter() - state.wall_time
    probe = BehaviourProbe(behaviour_seeds(config), codec) if config.behaviour_seeds else None
    with Evaluation(evaluate, config.workers, stop=stop, progress=progress) as evaluation:
        while (reason := _stop_reason(state, stop)) is None:
            if not state.history and initial_population is not None:
                population = [Individual(np.array(chromosome, copy=True)) for chromosome in initial_population]
            else:
                population = _next_population(state, codec.space, rng)
            hall = state.hall
            if hall is not None:
                hall, opponents = hall.draw(rng)
                evaluation.use(evaluate.against([codec.decode(member.chromosome) for member in opponents]))
                for hear in hearing_opponents:
                    hear(len(state.history), opponents)
            try:
                population = _evaluated(population, evaluation, codec, rng)
                behaviours = probe(population, evaluation) if probe is not None else NOT_MEASURED
            except EvaluationStopped:
                reason = STOPPED  # the state (and rng) stay as after the last finished generation
                break
            state = _recorded(replace(state, hall=hall), population, rng, time.perf_counter() - started, behaviours)
            if checkpoint is not None:
                save_checkpoint(checkpoint, state)
            for listener in listeners:
                listener(state.history[-1], state.population)
    best_rulebase = codec.decode(state.best.chromosome) if state.best is not None else None
    return RunResult(config, state.vocabulary, state.history, state.population, state.best, best_rulebase, reason)


def _stop_reason(state: RunState, stop: threading.Event | None) -> str | None:
    if not state.history:
        return None  # generation 0 runs to its end unless stopped within it
    if state.history[-1].best <= state.config.target_fitness:
        return TARGET_REACHED
    if len(state.history) >= state.config.max_generations:
        return GENERATIONS_DONE
    if stop is not None and stop.is_set():
        return STOPPED
    return None


def _next_population(state: RunState, space: GeneSpace, rng: np.random.Generator) -> list[Individual]:
    config = state.config
    if state.history and state.algorithm == GA:
        return next_generation(state.population, config, space, rng)
    chromosomes = random_population(space, config.population_size, config.max_length,
                                    config.consequent_probability, rng)
    return [Individual(chromosome, birth=RANDOM_DRAW) for chromosome in chromosomes]


class _Decoded(Sequence[Rulebase]):
    """The population's rulebases, each decoded when the evaluation reaches its chunk (a large population's
    rulebases would take seconds to decode up front, with no stop obeyed meanwhile)."""

    def __init__(self, population: list[Individual], codec: ChromosomeCodec):
        self.population, self.codec = population, codec

    def __len__(self) -> int:
        return len(self.population)

    def __getitem__(self, index):  # type: ignore[override]
        if isinstance(index, slice):
            return [self.codec.decode(individual.chromosome) for individual in self.population[index]]
        return self.codec.decode(self.population[index].chromosome)


def _evaluated(population: list[Individual], evaluation: Evaluation, codec: ChromosomeCodec,
               rng: np.random.Generator) -> list[Individual]:
    seeds = rng.integers(0, SEED_BOUND, size=len(population)).tolist()
    scores = evaluation(_Decoded(population, codec), seeds)
    return [individual.evaluated(score.fitness, score.goals, seed)
            for individual, score, seed in zip(population, scores, seeds)]


def _recorded(state: RunState, population: list[Individual], rng: np.random.Generator,
              wall_time: float, behaviours: int) -> RunState:
    stats = generation_stats(len(state.history), population, state.evaluations + len(population), wall_time,
                             behaviours)
    contender = min(population, key=lambda individual: individual.fitness)  # first of equals
    best = contender if state.best is None or contender.fitness < state.best.fitness else state.best
    hall = state.hall.with_best(contender.chromosome, len(state.history)) if state.hall is not None else None
    return RunState(state.algorithm, state.config, state.vocabulary, population, rng.bit_generator.state,
                    [*state.history, stats], best, hall)


