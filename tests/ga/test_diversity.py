"""Diversity per generation: the genotypic measures against the codec's own rules and a hand count, the
behavioural count against the games themselves, and neither changing the evolution."""

import itertools
import tracemalloc

import numpy as np
import pytest
from ga_synthetic import SyntheticEvaluator, play

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.algorithms import evolve, resume
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.config import GAConfig
from soccer_lab.ga import diversity
from soccer_lab.ga.diversity import behaviour_seeds, genotypic_diversity
from soccer_lab.ga.genes import GeneSpace
from soccer_lab.ga.initialisation import random_population
from soccer_lab.ga.notation import parse_compact
from soccer_lab.ga.statistics import NOT_MEASURED

VOCABULARY = Vocabulary.default()
CODEC = ChromosomeCodec(VOCABULARY)
CONFIG = GAConfig(population_size=30, max_generations=6, max_length=24, target_fitness=0.0, seed=4,
                  selection="elitist")


def chromosome(text):
    return parse_compact(text, VOCABULARY)


def test_a_hand_made_population():
    population = [
        chromosome("(B,N,O) (KG,n,H) (G,F,A) (RB,n,L)"),  # rules r1 = B N -> KG, r2 = G F -> RB
        chromosome("(B,N,A) (KG,n,H) (T,L,n)"),  # r1 again: the connector after a rule's last premise is ignored
        chromosome("(B,N,O) (KG,n,H) (G,F,A) (RB,n,L)"),  # the first one again
        chromosome("(T,L,n) (G,vF,O)"),  # no rule at all
    ]
    distinct_chromosomes, distinct_rules, distance = genotypic_diversity(population)
    assert (distinct_chromosomes, distinct_rules) == (3, 2)
    # Rule sets {r1, r2}, {r1}, {r1, r2}, {}: Jaccard distances of the six pairs.
    pairs = [1 - 1 / 2, 0.0, 1.0, 1 - 1 / 2, 1.0, 1.0]
    assert distance == pytest.approx(np.mean(pairs))
    assert genotypic_diversity([population[3]]) == (1, 0, 0.0)
    assert genotypic_diversity([population[0]] * 3) == (1, 2, 0.0)


@pytest.mark.parametrize("seed", range(6))
def test_genotypic_diversity_matches_the_decoded_rule_sets(seed):
    space = GeneSpace.from_vocabulary(VOCABULARY)
    population = random_population(space, 40, 20, 0.4, np.random.default_rng(seed))
    population += population[:10]  # some duplicates
    rule_sets = [frozenset(CODEC.decode(c).rules) for c in population]
    distinct_chromosomes, distinct_rules, distance = genotypic_diversity(population)
    assert distinct_chromosomes == 40
    assert distinct_rules == len(frozenset().union(*rule_sets))
    expected = [1 - len(a & b) / len(a | b) if a | b else 0.0 for a, b in itertools.combinations(rule_sets, 2)]
    assert distance == pytest.approx(np.mean(expected), abs=1e-12)


class CountingEvaluator:
    """The synthetic evaluator, noting every (chromosome, seed) it plays."""

    def __init__(self):
        self.played = []

    def __call__(self, rulebases, seeds):
        self.played += list(zip(rulebases, seeds))
        return [play(rulebase, seed) for rulebase, seed in zip(rulebases, seeds)]


def test_behaviours_are_the_distinct_outcomes_on_the_common_seeds_and_change_nothing_else():
    config = CONFIG.model_copy(update={"behaviour_seeds": 3})
    counting = CountingEvaluator()
    populations = []
    measured = evolve(config, counting, VOCABULARY, callbacks=[lambda stats, population: populations.append(population)])
    seeds = behaviour_seeds(config)
    assert len(seeds) == 3 and len(set(seeds)) == 3
    for stats, population in zip(measured.history, populations):
        outcomes = {tuple((play(CODEC.decode(i.chromosome), s).fitness, play(CODEC.decode(i.chromosome), s).goals)
                          if len(CODEC.decode(i.chromosome)) else (1.0, 0) for s in seeds) for i in population}
        assert stats.distinct_behaviours == len(outcomes)
        assert 1 <= stats.distinct_behaviours <= stats.distinct_chromosomes
    # Each chromosome plays the seeds once while it lives: an elite is not played again every generation.
    probes = [(rulebase, seed) for rulebase, seed in counting.played if seed in seeds]
    newcomers, previous = 0, set()
    for population in populations:
        keys = {i.chromosome.tobytes() for i in population}
        newcomers += sum(1 for key in keys - previous if len(CODEC.decode(np.frombuffer(key, np.int8).reshape(-1, 5))))
        previous = keys
    assert len(probes) == 3 * newcomers
    plain = evolve(CONFIG, SyntheticEvaluator(), VOCABULARY)
    assert [i.to_dict() for i in plain.population] == [i.to_dict() for i in measured.population]
    for without, with_ in zip(plain.history, measured.history):
        differing = {k for k, v in without.to_dict().items() if with_.to_dict()[k] != v}
        assert differing <= {"distinct_behaviours", "wall_time"} and without.distinct_behaviours == NOT_MEASURED


def test_a_resumed_run_counts_the_same_behaviours(tmp_path):
    import threading

    config = CONFIG.model_copy(update={"behaviour_seeds": 2})
    whole = evolve(config, SyntheticEvaluator(), VOCABULARY)
    stop = threading.Event()
    evolve(config, SyntheticEvaluator(), VOCABULARY, checkpoint=tmp_path / "checkpoint", stop=stop,
           callbacks=[lambda stats, population: stats.generation == 2 and stop.set()])
    resumed = resume(tmp_path / "checkpoint", SyntheticEvaluator())
    assert [s.distinct_behaviours for s in resumed.history] == [s.distinct_behaviours for s in whole.history]


def test_the_behaviour_seeds_are_the_runs_own():
    assert behaviour_seeds(CONFIG.model_copy(update={"behaviour_seeds": 2})) != behaviour_seeds(
        CONFIG.model_copy(update={"behaviour_seeds": 2, "seed": 5}))
    assert behaviour_seeds(CONFIG) == []


def test_the_behaviour_games_report_no_progress_and_obey_a_stop_within_a_generation(tmp_path):
    import threading

    config = CONFIG.model_copy(update={"behaviour_seeds": 2})
    whole = evolve(config, SyntheticEvaluator(chunk_size=7), VOCABULARY)
    stop = threading.Event()

    class StopAfterEvaluating:
        """Sets the stop once generation 2's own evaluation is complete: only the behaviour games remain."""
        finished = 0
        heard: list[tuple[int, int, int]] = []

        def on_progress(self, evaluated, population):
            self.heard.append((self.finished, evaluated, population))
            if self.finished == 2 and evaluated == population:
                stop.set()

        def on_generation(self, stats, population):
            self.finished = stats.generation + 1

    watcher = StopAfterEvaluating()
    stopped = evolve(config, SyntheticEvaluator(chunk_size=7), VOCABULARY, callbacks=[watcher],
                     checkpoint=tmp_path / "checkpoint", stop=stop)
    assert {total for _, _, total in watcher.heard} == {config.population_size}  # never the behaviour games'
    assert [s.generation for s in stopped.history] == [0, 1]  # generation 2 abandoned in its behaviour games
    resumed = resume(tmp_path / "checkpoint", SyntheticEvaluator(chunk_size=7))
    assert [s.distinct_behaviours for s in resumed.history] == [s.distinct_behaviours for s in whole.history]
    assert [i.to_dict() for i in resumed.population] == [i.to_dict() for i in whole.population]


def brute_force_distance(population):
    rule_sets = [frozenset(CODEC.decode(c).rules) for c in population]
    return np.mean([1 - len(a & b) / len(a | b) if a | b else 0.0 for a, b in itertools.combinations(rule_sets, 2)])


def mixed_population(seed, size):
    """Random chromosomes, some repeated, some without any rule: every kind of pair."""
    space = GeneSpace.from_vocabulary(VOCABULARY)
    population = random_population(space, size, 20, 0.4, np.random.default_rng(seed))
    return population + population[: size // 4] + [chromosome("(T,L,n) (G,vF,O)")] * 3


def test_exact_distance_in_small_blocks_matches_every_pair(monkeypatch):
    population = mixed_population(7, 60)
    expected = brute_force_distance(population)
    monkeypatch.setattr(diversity, "BLOCK_ENTRIES", 1)  # one row per block
    assert genotypic_diversity(population)[2] == pytest.approx(expected, abs=1e-12)


def test_sampled_distance_is_within_its_stated_error_and_the_same_for_the_same_population(monkeypatch):
    population = mixed_population(8, 120)
    exact = brute_force_distance(population)
    monkeypatch.setattr(diversity, "EXACT_PAIRS", 10)
    estimate = genotypic_diversity(population)[2]
    assert abs(estimate - exact) <= 4 * 0.5 / np.sqrt(diversity.SAMPLED_PAIRS)
    assert genotypic_diversity(list(population))[2] == estimate  # bit for bit: a run and its replay agree
    assert genotypic_diversity(population[::-1])[2] != estimate  # another population, another sample


def test_rule_set_distance_of_population_10000_does_not_build_dense_pair_matrices():
    """The probe measured 2.8 GB at population 10,000: four dense 10,000 x 10,000 matrices."""
    population = mixed_population(9, 10_000)
    tracemalloc.start()
    try:
        genotypic_diversity(population)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 200 * 2**20, f"{peak / 2**20:.0f} MB"
