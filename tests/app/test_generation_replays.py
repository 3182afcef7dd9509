"""Which game a run's recording replays for each generation's best (app/runs/run.py, GenerationReplays), where
games cannot be played again: rcssserver trials, traced by the evaluator as they are played."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from soccer_lab.app.runs.environments import RcssTrials
from soccer_lab.app.runs.run import GenerationReplays
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.individual import Individual
from soccer_lab.ga.notation import parse_compact
from soccer_lab.soccer.config import SOCCER_VOCABULARY
from soccer_lab.soccer.rcss.trial import TrialConfig, TrialResult, TrialTrace

CODEC = ChromosomeCodec(SOCCER_VOCABULARY)
STRIKER, CHASER, TURNER = "(B,vN,A)(KG,n,H)", "(B,nF,A)(GB,n,M)", "(B,nA,A)(T,L,n)"


class TracingEvaluator:
    """What GenerationReplays reads of RcssEvaluator: `traced`, the last call's results by (rulebase, seed)."""

    def __init__(self):
        self.traced: dict = {}

    def play(self, population: list[Individual], seeds: list[int], fitnesses: list[float]) -> list[Individual]:
        """One generation: each individual's trial (a trace whose ball x is the seed, to tell them apart)."""
        self.traced = {}
        evaluated = []
        for individual, seed, fitness in zip(population, seeds, fitnesses):
            rulebase = CODEC.decode(individual.chromosome)
            trace = TrialTrace(*(np.full(3, float(seed)) for _ in range(5)), np.zeros(3, np.int64),
                               np.zeros(3, np.int64), SOCCER_VOCABULARY, np.zeros(3, np.int64), np.zeros(3),
                               np.zeros(3), np.zeros(3, np.int64))
            self.traced[(rulebase, seed)] = TrialResult(fitness, 0, 0, 3, "time", seed, trace)
            evaluated.append(individual.evaluated(fitness, 0, seed))
        return evaluated


class Recorder:
    def __init__(self):
        self.replays: list[tuple[int, float]] = []  # (generation, the replayed trial's seed)

    def log_generation_replay(self, generation, trace, result) -> None:
        self.replays.append((generation, trace.ball_x[0]))


def fresh(compact: str) -> Individual:
    return Individual(parse_compact(compact, SOCCER_VOCABULARY))


def test_each_best_is_replayed_from_its_first_trial_kept_while_it_lives():
    evaluate, recorder = TracingEvaluator(), Recorder()
    replays = GenerationReplays(RcssTrials(("127.0.0.1:6000",), TrialConfig()), recorder, SOCCER_VOCABULARY, evaluate)
    striker, chaser = evaluate.play([fresh(STRIKER), fresh(CHASER)], [10, 11], [0.5, 0.9])
    replays.on_generation(SimpleNamespace(generation=0), [striker, chaser])
    # Generation 1: the chaser is re-evaluated (its running mean becomes the best), the striker is gone.
    chaser, turner = evaluate.play([chaser, fresh(TURNER)], [20, 21], [0.1, 0.95])
    replays.on_generation(SimpleNamespace(generation=1), [chaser, turner])
    # Its first trial (seed 11, generation 0), not the one it just played (seed 20).
    assert recorder.replays == [(0, 10.0), (1, 11.0)]
    assert sorted(seed for _, seed in replays.first_trials) == [11, 21]  # the living only
