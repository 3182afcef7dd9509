import numpy as np
import pytest

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.config import GAConfig
from soccer_lab.ga.genes import GeneSpace
from soccer_lab.ga.individual import Individual
from soccer_lab.ga.provenance import Birth
from soccer_lab.ga.initialisation import random_population
from soccer_lab.ga.reproduction import next_generation
from soccer_lab.ga.selection import elite, roulette, tournament

VOCABULARY = Vocabulary.default()

FITNESS = np.array([0.9, 0.1, 0.5, 0.25, 1.0])
DRAWS = 200_000


def shares(indices, n=len(FITNESS)):
    return np.bincount(indices, minlength=n) / len(indices)


def test_roulette_picks_in_proportion_to_inverse_fitness():
    picked = shares(roulette(FITNESS, DRAWS, np.random.default_rng(0), "inverse"))
    expected = (1 / FITNESS) / (1 / FITNESS).sum()
    np.testing.assert_allclose(picked, expected, atol=0.005)
    assert FITNESS[roulette(FITNESS, DRAWS, np.random.default_rng(1), "inverse")].mean() < FITNESS.mean()


def test_linear_roulette_picks_in_proportion_to_one_minus_fitness():
    picked = shares(roulette(FITNESS, DRAWS, np.random.default_rng(0), "linear"))
    expected = (1 - FITNESS) / (1 - FITNESS).sum()
    np.testing.assert_allclose(picked, expected, atol=0.005)
    assert picked[4] == 0.0  # fitness 1.0 (never kicked) weighs nothing


def test_linear_roulette_draws_uniformly_when_nobody_kicked():
    picked = shares(roulette(np.ones(4), DRAWS, np.random.default_rng(0), "linear"), 4)
    np.testing.assert_allclose(picked, 0.25, atol=0.005)


def test_unknown_roulette_weighting_is_refused():
    with pytest.raises(ValueError, match="linear or inverse"):
        roulette(FITNESS, 3, np.random.default_rng(0), "square")


def test_roulette_survives_a_perfect_fitness_of_zero():
    picked = roulette(np.array([0.0, 0.5, 1.0]), 1000, np.random.default_rng(0), "inverse")
    assert np.all(picked == 0)  # the floored weight dwarfs the others


def test_tournament_of_two_lets_the_better_win_three_times_in_four():
    two = np.array([0.2, 0.8])
    # P(pick 0) = P(both entrants 0) + P(one each) * 0.75 = 0.25 + 0.5 * 0.75
    picked = shares(tournament(two, DRAWS, np.random.default_rng(0), size=2, selector=0.75), 2)
    assert picked[0] == pytest.approx(0.625, abs=0.005)


def test_tournament_prefers_lower_fitness_in_expectation():
    picked = tournament(FITNESS, DRAWS, np.random.default_rng(0))
    assert FITNESS[picked].mean() < FITNESS.mean()
    assert shares(picked).argmax() == FITNESS.argmin()


def test_tournament_selector_one_always_takes_the_best_entrant():
    picked = tournament(FITNESS, 5000, np.random.default_rng(0), size=5, selector=1.0)
    entrants_best = shares(picked)
    assert entrants_best[FITNESS.argmax()] == 0.0  # the worst only wins against itself five times
    assert entrants_best[1] == pytest.approx(1 - 0.8**5, abs=0.02)


def test_elite_takes_the_best_first_and_keeps_population_order_on_ties():
    assert elite(np.array([0.5, 0.1, 0.5, 0.1, 0.9]), 3).tolist() == [1, 3, 0]


def evaluated_population(size, seed):
    rng = np.random.default_rng(seed)
    chromosomes = random_population(GeneSpace.from_vocabulary(VOCABULARY), size, 16, 0.25, rng)
    return [Individual(c).evaluated(float(f), 0) for c, f in zip(chromosomes, rng.uniform(0.05, 1.0, size))]


def test_elitism_copies_the_best_five_percent_unchanged_with_their_running_means():
    config = GAConfig(population_size=40, selection="elitist", crossover_probability=1.0, mutation_probability=1.0)
    population = evaluated_population(40, seed=3)
    following = next_generation(population, config, GeneSpace.from_vocabulary(VOCABULARY), np.random.default_rng(0))
    best_two = sorted(range(40), key=lambda i: population[i].fitness)[:2]
    assert len(following) == 40
    for copy, parent in zip(following[:2], best_two):  # the same genes, evaluations and running mean
        assert copy.birth == Birth((parent,), elite=True)
        assert copy.chromosome is population[parent].chromosome
        assert (copy.evaluations, copy.fitness_sum) == (population[parent].evaluations, population[parent].fitness_sum)
    assert all(child.evaluations == 0 for child in following[2:])  # every other child was crossed


def test_children_untouched_by_crossover_and_mutation_are_their_parents():
    config = GAConfig(population_size=41, crossover_probability=0.0, mutation_probability=0.0)
    population = evaluated_population(41, seed=4)
    following = next_generation(population, config, GeneSpace.from_vocabulary(VOCABULARY), np.random.default_rng(0))
    assert len(following) == 41
    for child in following:
        (parent,) = child.birth.parents
        assert child.birth.kind == "copy" and child.chromosome is population[parent].chromosome
        assert child.to_dict() | {"birth": None} == population[parent].to_dict()  # running mean and all
