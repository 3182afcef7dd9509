"""A stop is obeyed within a generation: ga/evaluation.py plays each generation in chunks and checks the
stop event between them. The generation in progress is abandoned, every finished one kept, and a resumed
run finishes bit for bit as the uninterrupted one; results never depend on the chunk size."""

import threading

import pytest
from ga_synthetic import SyntheticEvaluator

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.algorithms import evolve, resume
from soccer_lab.ga.config import GAConfig
from soccer_lab.ga.result import GENERATIONS_DONE, STOPPED

VOCABULARY = Vocabulary.default()
CONFIG = GAConfig(population_size=40, max_generations=5, max_length=24, target_fitness=0.0, seed=11)


def comparable(result):
    history = [{k: v for k, v in s.to_dict().items() if k != "wall_time"} for s in result.history]
    return history, result.best.to_dict(), [i.to_dict() for i in result.population], result.stop_reason


class StopAt:
    """Callback: sets `stop` once `chunks` chunks of generation `generation` are evaluated; hears the progress."""

    def __init__(self, generation: int, chunks: int):
        self.generation, self.chunks = generation, chunks
        self.stop = threading.Event()
        self.finished = 0  # generations finished so far
        self.progress: list[tuple[int, int, int]] = []  # (generation, evaluated, population)

    def on_progress(self, evaluated, population):
        self.progress.append((self.finished, evaluated, population))
        if self.finished == self.generation and sum(g == self.generation for g, _, _ in self.progress) == self.chunks:
            self.stop.set()

    def on_generation(self, stats, population):
        self.finished = stats.generation + 1


@pytest.mark.parametrize("workers", [1, 2])
def test_results_do_not_depend_on_the_chunk_size(workers):
    whole = evolve(CONFIG, SyntheticEvaluator(chunk_size=CONFIG.population_size), VOCABULARY)
    chunked = evolve(CONFIG.model_copy(update={"workers": workers}), SyntheticEvaluator(chunk_size=7), VOCABULARY)
    assert comparable(chunked) == comparable(whole)


def test_progress_is_heard_after_every_chunk_up_to_the_population():
    watcher = StopAt(generation=-1, chunks=0)
    evolve(CONFIG, SyntheticEvaluator(chunk_size=15), VOCABULARY, callbacks=[watcher])
    first_generation = [(evaluated, population) for g, evaluated, population in watcher.progress if g == 0]
    # Chunks of 15 individuals (the invalid ones among them scored without being played).
    assert first_generation == [(15, 40), (30, 40), (40, 40)]
    assert {g for g, _, _ in watcher.progress} == set(range(CONFIG.max_generations))


@pytest.mark.parametrize("workers", [1, 2])
def test_a_stop_mid_generation_abandons_it_and_keeps_the_finished_ones(workers, tmp_path):
    stopper = StopAt(generation=2, chunks=1)  # after the first chunk of generation 2
    config = CONFIG.model_copy(update={"workers": workers})
    result = evolve(config, SyntheticEvaluator(chunk_size=5), VOCABULARY, callbacks=[stopper],
                    checkpoint=tmp_path / "run.ckpt", stop=stopper.stop)
    assert result.stop_reason == STOPPED
    assert [s.generation for s in result.history] == [0, 1]
    # Generation 2 was abandoned right after its first group of chunks (one chunk per worker), not played on.
    evaluated = [e for g, e, _ in stopper.progress if g == 2]
    assert len(evaluated) == 1 and evaluated[0] < CONFIG.population_size


def test_a_stop_in_generation_0_leaves_no_generation_and_no_best():
    stopper = StopAt(generation=0, chunks=1)
    result = evolve(CONFIG, SyntheticEvaluator(chunk_size=5), VOCABULARY, callbacks=[stopper], stop=stopper.stop)
    assert result.stop_reason == STOPPED and result.history == []
    assert result.best is None and result.best_rulebase is None


@pytest.mark.parametrize("generation", [0, 3])
def test_a_run_resumed_after_a_stop_mid_generation_finishes_as_the_uninterrupted_one(generation, tmp_path):
    uninterrupted = evolve(CONFIG, SyntheticEvaluator(chunk_size=5), VOCABULARY)
    assert uninterrupted.stop_reason == GENERATIONS_DONE
    stopper = StopAt(generation=generation, chunks=3)
    checkpoint = tmp_path / "run.ckpt"
    stopped = evolve(CONFIG, SyntheticEvaluator(chunk_size=5), VOCABULARY, callbacks=[stopper],
                     checkpoint=checkpoint, stop=stopper.stop)
    assert stopped.stop_reason == STOPPED and len(stopped.history) == generation
    if generation == 0:  # nothing finished, no checkpoint: the run starts again from its seed
        assert not checkpoint.exists()
        again = evolve(CONFIG, SyntheticEvaluator(chunk_size=9), VOCABULARY)
    else:
        again = resume(checkpoint, SyntheticEvaluator(chunk_size=9))
    assert comparable(again) == comparable(uninterrupted)
