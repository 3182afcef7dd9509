import threading

import pytest
from ga_synthetic import RecordingEvaluator, SyntheticEvaluator

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.algorithms import evolve, random_search
from soccer_lab.ga.codec import ChromosomeCodec
from soccer_lab.ga.config import GAConfig
from soccer_lab.ga.result import GENERATIONS_DONE, STOPPED, TARGET_REACHED

VOCABULARY = Vocabulary.default()

SMALL = GAConfig(population_size=30, max_generations=6, max_length=24, target_fitness=0.0, seed=7)


def comparable(result):
    """Everything a run produces except wall time."""
    history = [{k: v for k, v in s.to_dict().items() if k != "wall_time"} for s in result.history]
    return history, result.best.to_dict(), [i.to_dict() for i in result.population], result.stop_reason


def test_the_same_seed_gives_the_same_run_and_another_seed_another():
    first, again = evolve(SMALL, SyntheticEvaluator(), VOCABULARY), evolve(SMALL, SyntheticEvaluator(), VOCABULARY)
    assert comparable(first) == comparable(again)
    other_seed = evolve(SMALL.model_copy(update={"seed": 8}), SyntheticEvaluator(), VOCABULARY)
    assert comparable(other_seed) != comparable(first)


def test_parallel_evaluation_gives_the_serial_run():
    config = SMALL.model_copy(update={"max_generations": 3, "selection": "elitist"})
    serial = evolve(config, SyntheticEvaluator(), VOCABULARY)
    parallel = evolve(config.model_copy(update={"workers": 2}), SyntheticEvaluator(), VOCABULARY)
    assert comparable(parallel) == comparable(serial)


@pytest.mark.parametrize("selection", ["roulette", "tournament", "elitist"])
def test_the_loop_improves_fitness_over_generations(selection):
    config = GAConfig(population_size=60, max_generations=12, max_length=32, selection=selection,
                      target_fitness=0.0, seed=1)
    history = evolve(config, SyntheticEvaluator(), VOCABULARY).history
    assert len(history) == 12
    assert history[-1].mean < history[0].mean - 0.15
    assert history[-1].best <= history[0].best
    assert history[-1].goals_0 < history[0].goals_0


def test_history_counts_evaluations_and_the_best_is_the_best_seen():
    result = evolve(SMALL, SyntheticEvaluator(), VOCABULARY)
    assert [s.generation for s in result.history] == list(range(6))
    assert [s.evaluations for s in result.history] == [30 * (g + 1) for g in range(6)]
    assert result.stop_reason == GENERATIONS_DONE and result.evaluations == 180
    assert result.best.fitness == min(s.best for s in result.history)
    assert result.best_rulebase == ChromosomeCodec(VOCABULARY).decode(result.best.chromosome)


def test_the_run_stops_once_the_target_is_reached():
    result = evolve(SMALL.model_copy(update={"target_fitness": 0.5, "max_generations": 50}), SyntheticEvaluator(),
                    VOCABULARY)
    assert result.stop_reason == TARGET_REACHED
    assert result.history[-1].best <= 0.5 and all(s.best > 0.5 for s in result.history[:-1])


def test_invalid_rulesets_score_worst_without_being_played():
    played, populations = [], []
    config = SMALL.model_copy(update={"max_generations": 2, "max_length": 3})
    evolve(config, RecordingEvaluator(played), VOCABULARY,
           callbacks=[lambda stats, population: populations.append(population)])
    codec = ChromosomeCodec(VOCABULARY)
    valid = [i for population in populations for i in population if len(codec.decode(i.chromosome))]
    invalid = [i for population in populations for i in population if not len(codec.decode(i.chromosome))]
    assert invalid and all(i.fitness == 1.0 and i.goals == 0 for i in invalid)
    assert played == [codec.decode(i.chromosome) for i in valid]


def test_callbacks_hear_every_generation_functions_and_objects_alike():
    heard, seen = [], []

    class Listener:
        def on_generation(self, stats, population):
            seen.append((stats.generation, len(population)))

    result = evolve(SMALL, SyntheticEvaluator(), VOCABULARY, callbacks=[lambda s, p: heard.append(s), Listener()])
    assert heard == result.history
    assert seen == [(g, 30) for g in range(6)]


def test_a_stop_event_ends_the_run_after_the_generation_in_progress():
    stop = threading.Event()

    def stop_after_generation_2(stats, population):
        if stats.generation == 2:
            stop.set()

    result = evolve(SMALL, SyntheticEvaluator(), VOCABULARY, callbacks=[stop_after_generation_2], stop=stop)
    assert result.stop_reason == STOPPED and len(result.history) == 3


def test_unchanged_survivors_accumulate_evaluations():
    config = SMALL.model_copy(update={"selection": "elitist", "crossover_probability": 0.0,
                                      "mutation_probability": 0.0})
    result = evolve(config, SyntheticEvaluator(), VOCABULARY)
    evaluations = [i.evaluations for i in result.population]
    assert max(evaluations) == 6  # an individual alive since generation 0
    assert all(i.fitness == i.fitness_sum / i.evaluations for i in result.population)


def test_random_search_spends_the_same_evaluations_on_fresh_individuals():
    result = random_search(SMALL, SyntheticEvaluator(), VOCABULARY)
    assert [s.evaluations for s in result.history] == [30 * (g + 1) for g in range(6)]
    assert all(i.evaluations == 1 for i in result.population)
    assert comparable(result) == comparable(random_search(SMALL, SyntheticEvaluator(), VOCABULARY))
    assert result.best.fitness == min(s.best for s in result.history)


def test_an_initial_population_is_generation_0_and_the_run_goes_on_from_it():
    """A population evolved elsewhere (the transfer study seeds RoboCup runs with SimpleSoccer's) is played
    as generation 0, unevaluated; the run from it is as reproducible as any, and starts where it left off."""
    evolved = evolve(SMALL, SyntheticEvaluator(), VOCABULARY)
    chromosomes = [individual.chromosome for individual in evolved.population]
    recorder = RecordingEvaluator([])
    config = SMALL.model_copy(update={"seed": 11, "max_generations": 2})
    seeded = evolve(config, recorder, VOCABULARY, initial_population=chromosomes)
    codec = ChromosomeCodec(VOCABULARY)
    assert recorder.played[:30] == [codec.decode(chromosome) for chromosome in chromosomes]
    assert seeded.history[0].mean == pytest.approx(evolved.history[-1].mean, abs=0.1)  # not a random start's
    assert seeded.history[0].mean < evolve(config, SyntheticEvaluator(), VOCABULARY).history[0].mean - 0.1
    again = evolve(config, SyntheticEvaluator(), VOCABULARY, initial_population=chromosomes)
    assert comparable(again) == comparable(seeded)
    with pytest.raises(ValueError, match="an initial population of 29 for a population size of 30"):
        evolve(config, SyntheticEvaluator(), VOCABULARY, initial_population=chromosomes[:29])
