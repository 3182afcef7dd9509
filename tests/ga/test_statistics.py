import numpy as np
import pytest

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.individual import Individual
from soccer_lab.ga.notation import parse_compact
from soccer_lab.ga.statistics import GenerationStats, generation_stats

VOCABULARY = Vocabulary.default()


def individual(notation, fitness, goals):
    return Individual(parse_compact(notation, VOCABULARY)).evaluated(fitness, goals)


# Hand-made population; per chromosome: (genes, premises, rules, valid rules)
POPULATION = [
    individual("(B,N,O) (B,nF,A) (G,N,A) (RB,n,L)", 0.5, 1),  # (4, 3, 1, 1)
    individual("(B,N,O) (RB,n,L) (T,L,n)", 0.25, 2),  # (3, 1, 2, 1): Turn has no premise
    individual("(T,L,n) (G,vF,O)", 1.0, 0),  # (2, 1, 1, 0)
    individual("(B,N,A) (RB,n,L) (B,N,O) (RB,n,L)", 0.05, 10),  # (4, 2, 2, 2): (B,N,A) differs from (B,N,O)
]


def test_statistics_of_a_hand_made_population():
    stats = generation_stats(3, POPULATION, evaluations=80, wall_time=1.5)
    assert (stats.generation, stats.evaluations, stats.wall_time) == (3, 80, 1.5)
    assert (stats.best, stats.worst) == (0.05, 1.0)
    assert stats.mean == pytest.approx(1.8 / 4)
    assert stats.std == pytest.approx(np.std([0.5, 0.25, 1.0, 0.05]))
    assert (stats.goals_0, stats.goals_1, stats.goals_2, stats.goals_3, stats.goals_4, stats.goals_more) == (
        0.25, 0.25, 0.25, 0.0, 0.0, 0.25)
    assert (stats.genes_mean, stats.genes_std) == (3.25, pytest.approx(np.std([4, 3, 2, 4])))
    assert stats.premises_mean == 7 / 4 and stats.rules_mean == 6 / 4 and stats.valid_rules_mean == 1.0
    assert stats.valid_rules_std == pytest.approx(np.std([1, 1, 0, 2]))
    # premise pool: (B,N,O) (B,nF,A) (G,N,A) (G,vF,O) (B,N,A); consequent pool: (RB,n,L) (T,L,n)
    assert (stats.unique_premise_genes, stats.unique_consequent_genes, stats.unique_genes) == (5, 2, 7)


def test_fitness_statistics_use_each_individuals_running_mean():
    twice = individual("(B,N,O) (RB,n,L)", 0.5, 1).evaluated(0.25, 2)
    stats = generation_stats(0, [twice], evaluations=1, wall_time=0.0)
    assert stats.best == 0.375 and stats.goals_2 == 1.0  # goals: the latest evaluation


def test_to_dict_is_flat_and_round_trips():
    stats = generation_stats(0, POPULATION, evaluations=4, wall_time=0.25)
    data = stats.to_dict()
    assert list(data) == list(GenerationStats.field_names())
    assert all(isinstance(v, (int, float)) for v in data.values())
    assert GenerationStats.from_dict(data) == stats
