"""Breeding the next generation from an evaluated one (the chapter, 4 and Table 2). Every individual of
the new generation carries its birth (ga/provenance.py): its parents' places in `population` and the
operations that made it."""

from __future__ import annotations

import numpy as np

from soccer_lab.ga.config import GAConfig
from soccer_lab.ga.crossover import CROSSOVERS
from soccer_lab.ga.genes import GeneSpace
from soccer_lab.ga.individual import Individual
from soccer_lab.ga.mutation import mutate
from soccer_lab.ga.provenance import Birth
from soccer_lab.ga.selection import elite, roulette, tournament


def next_generation(population: list[Individual], config: GAConfig, space: GeneSpace,
                    rng: np.random.Generator) -> list[Individual]:
    """Elites (elitist selection) pass unchanged; the rest are children of selected pairs. A child that
    went through neither crossover nor mutation is its parent, running mean and all."""
    fitness = np.array([individual.fitness for individual in population])
    elites = [population[i].born(Birth((i,), elite=True)) for i in elite(fitness, config.elite_count).tolist()]
    needed = config.population_size - len(elites)
    parents = select_parents(fitness, needed + needed % 2, config, rng).tolist()
    crossover = CROSSOVERS[config.crossover]
    offspring: list[Individual] = []
    for a, b in zip(parents[0::2], parents[1::2]):
        pair = (population[a].chromosome, population[b].chromosome)
        if rng.random() < config.crossover_probability:
            children = [Individual(splice.apply(pair[0], pair), birth=Birth((a, b), (splice,)))
                        for splice in crossover(*pair, config.max_length, rng)]
        else:
            children = [population[a].born(Birth((a,))), population[b].born(Birth((b,)))]
        offspring += [_maybe_mutated(child, config, space, rng) for child in children]
    return elites + offspring[:needed]


def select_parents(fitness: np.ndarray, count: int, config: GAConfig, rng: np.random.Generator) -> np.ndarray:
    if config.selection == "tournament":
        return tournament(fitness, count, rng, config.tournament_size, config.tournament_selector)
    return roulette(fitness, count, rng, config.roulette_weighting)  # roulette, and elitist's non-elite part


def _maybe_mutated(individual: Individual, config: GAConfig, space: GeneSpace,
                   rng: np.random.Generator) -> Individual:
    if rng.random() < config.mutation_probability:
        mutation = mutate(individual.chromosome, config.mutation_rate, space, rng)
        return Individual(mutation.apply(individual.chromosome, ()), birth=individual.birth.with_operation(mutation))
    return individual
