"""An individual remembers the seed of its first game, and replaying that game gives the score the GA saw."""

import numpy as np

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga import GAConfig, evolve
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.individual import Individual
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.engine import play_game
from soccer_lab.soccer.evaluate import SimpleSoccerEvaluator

VOCABULARY = Vocabulary.default()


def test_first_seed_is_kept_through_later_evaluations():
    individual = Individual(np.zeros((0, 5), dtype=np.int8))
    once = individual.evaluated(0.5, 1, seed=11)
    twice = once.evaluated(0.25, 2, seed=12)
    assert (once.first_seed, twice.first_seed) == (11, 11)
    assert Individual.from_dict(twice.to_dict()).first_seed == 11


def test_replaying_an_individuals_first_seed_gives_its_first_fitness():
    game = GameConfig(max_ticks=150, idle_ticks=50)
    result = evolve(GAConfig(population_size=8, max_generations=2, max_length=16, seed=5),
                    SimpleSoccerEvaluator(game), VOCABULARY)
    codec = ChromosomeCodec(result.vocabulary)
    played = [i for i in result.population if i.evaluations == 1 and len(codec.decode(i.chromosome))]
    assert played, "expected freshly evaluated, valid individuals in the last generation"
    for individual in played:
        replay, _ = play_game(codec.decode(individual.chromosome), individual.first_seed, game, trace=False)
        assert replay.fitness == individual.fitness and replay.goals == individual.goals
